#pragma once
// What a run of the small test chamber produced, for comparing a decomposed run with another (test_chamber_domains.cpp,
// test/parallel/test_chamber_mpi.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "coupling/chamber_dem.hpp"

namespace test_chamber {

struct Outcome {
  std::vector<uint64_t> ids;
  std::vector<double> state;   // x, v, w by id (dem::kGhostDoubles each)
  std::vector<double> wrench;  // mantle and concave force and torque per coupling step
  std::vector<double> map;
  std::vector<std::pair<uint64_t, uint64_t>> broken;  // the bonds broken, by particle ids, sorted
  coupling::ProductState product;
  long broken_bonds = 0;
  int recuts = 0;
};

// Everything but the particle state (taken by the caller: in one process or gathered over MPI). Collective.
inline void finish_outcome(coupling::ChamberDem& d, Outcome* o) {
  o->map = d.force_map();
  for (const auto& b : d.take_breaks()) o->broken.push_back({std::min(b.id_i, b.id_j), std::max(b.id_i, b.id_j)});
  std::sort(o->broken.begin(), o->broken.end());
  o->product = d.product();
  o->broken_bonds = d.broken_bonds();
  o->recuts = d.engine().recuts();
}

// The same particles, breaks, feed, crushing and discharge.
inline void expect_same_counts(const Outcome& a, const Outcome& b) {
  EXPECT_EQ(a.ids, b.ids);
  EXPECT_EQ(a.broken, b.broken);
  EXPECT_EQ(a.broken_bonds, b.broken_bonds);
  EXPECT_EQ(a.product.fed_kg, b.product.fed_kg);
  EXPECT_EQ(a.product.metaparticles_crushed, b.product.metaparticles_crushed);
  EXPECT_EQ(a.product.metaparticles_fragmented, b.product.metaparticles_fragmented);
  EXPECT_EQ(a.product.crushed_kg, b.product.crushed_kg);
  EXPECT_EQ(a.product.discharged_kg, b.product.discharged_kg);
  EXPECT_EQ(a.product.lost_kg, b.product.lost_kg);
  EXPECT_EQ(a.product.passing_pct, b.product.passing_pct);
}

}  // namespace test_chamber
