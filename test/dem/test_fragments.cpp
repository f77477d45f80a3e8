// Fragments over intact bonds and square-mesh sieve sizes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "dem/fragments.hpp"

namespace {

using Eigen::Vector3d;

// Chain of n touching spheres along direction u, radii alternating to give distinct masses.
dem::Particles chain(int n, const Vector3d& u, double r, std::vector<std::pair<int, int>>* bonds) {
  dem::Particles p;
  for (int i = 0; i < n; ++i) {
    const Vector3d x = (2 * r * i) * u;
    p.add(x.x(), x.y(), x.z(), r * (i % 2 ? 0.8 : 1.0), 2600.0, 0);
    if (i > 0 && bonds) bonds->emplace_back(i - 1, i);
  }
  return p;
}

TEST(Fragments, BreakingOneBondSplitsAChainIntoTwoOfTheRightMasses) {
  std::vector<std::pair<int, int>> bonds;
  const dem::Particles p = chain(10, Vector3d::UnitX(), 0.005, &bonds);
  auto fr = dem::Fragments::from_particles(p, bonds);
  ASSERT_EQ(fr.num_fragments(), 1);
  double total = 0;
  for (double m : p.m) total += m;
  auto info = fr.info(p);
  ASSERT_EQ(info.size(), 1u);
  EXPECT_NEAR(info[0].mass, total, 1e-15);
  EXPECT_TRUE(fr.break_bond(p.id[3], p.id[4]));
  ASSERT_EQ(fr.num_fragments(), 2);
  EXPECT_NE(fr.fragment_of(p.id[3]), fr.fragment_of(p.id[4]));
  EXPECT_EQ(fr.fragment_of(p.id[0]), fr.fragment_of(p.id[3]));
  EXPECT_EQ(fr.fragment_of(p.id[9]), fr.fragment_of(p.id[4]));
  double m_left = 0, m_right = 0;
  for (int i = 0; i < 4; ++i) m_left += p.m[i];
  for (int i = 4; i < 10; ++i) m_right += p.m[i];
  info = fr.info(p);
  ASSERT_EQ(info.size(), 2u);
  for (const auto& f : info) {
    if (f.label == fr.fragment_of(p.id[0])) {
      EXPECT_EQ(f.count, 4);
      EXPECT_NEAR(f.mass, m_left, 1e-15);
      EXPECT_LT(f.centre.x(), 0.03);
    } else {
      EXPECT_EQ(f.count, 6);
      EXPECT_NEAR(f.mass, m_right, 1e-15);
    }
  }
  // Breaking the same bond twice is an error; a non-bonded pair too.
  EXPECT_THROW(fr.break_bond(p.id[3], p.id[4]), std::invalid_argument);
  EXPECT_THROW(fr.break_bond(p.id[0], p.id[9]), std::invalid_argument);
  EXPECT_EQ(fr.members(fr.fragment_of(p.id[0])), (std::vector<uint64_t>{0, 1, 2, 3}));
}

TEST(Fragments, RingNeedsTwoBreaksAndBreakLogIsApplied) {
  std::vector<std::pair<int, int>> bonds;
  dem::Particles p = chain(8, Vector3d::UnitY(), 0.01, &bonds);
  bonds.emplace_back(7, 0);  // close the ring
  auto fr = dem::Fragments::from_particles(p, bonds);
  EXPECT_EQ(fr.num_bonds(), 8u);
  dem::BondBreak b1, b2;
  b1.id_i = p.id[2]; b1.id_j = p.id[3];
  b2.id_i = p.id[6]; b2.id_j = p.id[7];
  EXPECT_EQ(fr.apply_breaks({b1}), 0);  // a ring stays one piece
  EXPECT_EQ(fr.num_fragments(), 1);
  EXPECT_EQ(fr.apply_breaks({b2}), 1);
  EXPECT_EQ(fr.num_fragments(), 2);
  EXPECT_EQ(fr.members(fr.fragment_of(p.id[3])), (std::vector<uint64_t>{3, 4, 5, 6}));
  // Discharging particle 4 splits {3,4,5,6} into {3} and {5,6}.
  fr.remove_particle(p.id[4]);
  EXPECT_EQ(fr.num_fragments(), 3);
  EXPECT_EQ(fr.members(fr.fragment_of(p.id[5])), (std::vector<uint64_t>{5, 6}));
  EXPECT_EQ(fr.members(fr.fragment_of(p.id[3])), (std::vector<uint64_t>{3}));
  fr.remove_particle(p.id[3]);
  EXPECT_EQ(fr.num_fragments(), 2);
  EXPECT_FALSE(fr.contains(p.id[3]));
  fr.add_particle(1000);
  EXPECT_EQ(fr.num_fragments(), 3);
  EXPECT_THROW(fr.add_particle(1000), std::invalid_argument);
  EXPECT_THROW(dem::Fragments({1, 1}, {}), std::invalid_argument);
  EXPECT_THROW(dem::Fragments({1, 2}, {{1, 3}}), std::invalid_argument);
}

// Large random clusters: incremental splitting agrees with recomputing from scratch.
TEST(Fragments, IncrementalSplitsMatchRecomputation) {
  std::mt19937 rng(1);
  const int n = 400;
  std::vector<uint64_t> ids(n);
  for (int i = 0; i < n; ++i) ids[i] = 10 * i + 3;
  std::vector<std::pair<uint64_t, uint64_t>> bonds;
  std::uniform_int_distribution<int> pick(0, n - 1);
  for (int k = 0; k < 520; ++k) {
    int a = pick(rng), b = pick(rng);
    if (a != b) bonds.emplace_back(ids[std::min(a, b)], ids[std::max(a, b)]);
  }
  std::sort(bonds.begin(), bonds.end());
  bonds.erase(std::unique(bonds.begin(), bonds.end()), bonds.end());
  dem::Fragments fr(ids, bonds);
  std::shuffle(bonds.begin(), bonds.end(), rng);
  std::vector<std::pair<uint64_t, uint64_t>> intact = bonds;
  for (int k = 0; k < 300; ++k) {
    const auto b = intact.back();
    intact.pop_back();
    ASSERT_TRUE(fr.bonded(b.first, b.second));
    fr.break_bond(b.first, b.second);
    if (k % 50 == 0) {
      dem::Fragments ref(ids, intact);
      ASSERT_EQ(ref.num_fragments(), fr.num_fragments());
      for (int i = 0; i < n; ++i)
        for (int j : {0, 7, 123}) {
          ASSERT_EQ(ref.fragment_of(ids[i]) == ref.fragment_of(ids[j]),
                    fr.fragment_of(ids[i]) == fr.fragment_of(ids[j]));
        }
    }
  }
}

TEST(Sieve, SimpleShapes) {
  const double r = 0.004, d = 2 * r;
  // A single sphere passes its diameter.
  EXPECT_NEAR(dem::square_sieve_size({{0.1, 0.2, 0.3}}, {r}, {1.0}), d, 1e-15);
  // A rod of spheres in any direction passes its diameter.
  const Vector3d u = Vector3d(1, -2, 0.5).normalized();
  std::vector<Vector3d> c;
  std::vector<double> rr, mm;
  for (int i = 0; i < 9; ++i) {
    c.push_back(Vector3d(0.01, 0, 0) + i * d * u);
    rr.push_back(r);
    mm.push_back(1.0);
  }
  EXPECT_NEAR(dem::square_sieve_size(c, rr, mm), d, 1e-12);
  // A 2x2x2 cube of spheres: 2 d.
  c.clear(); rr.clear(); mm.clear();
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k) {
        c.push_back(Vector3d(i, j, k) * d);
        rr.push_back(r);
        mm.push_back(2.0);
      }
  EXPECT_NEAR(dem::square_sieve_size(c, rr, mm), 2 * d, 1e-12);
  // A one-layer 5 x 3 plate of spheres (5d x 3d x d): the 3d x d section passes aligned at 3d,
  // turned 45 degrees at (3d + d)/sqrt(2) = 2.83 d: 2.83 d.
  c.clear(); rr.clear(); mm.clear();
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 3; ++j) {
      c.push_back(Vector3d(i, j, 0) * d);
      rr.push_back(r);
      mm.push_back(1.0);
    }
  EXPECT_NEAR(dem::square_sieve_size(c, rr, mm), 4 * d / std::sqrt(2.0), 1e-12);
  EXPECT_THROW(dem::square_sieve_size({}, {}, {}), std::invalid_argument);
  EXPECT_THROW(dem::square_sieve_size({{0, 0, 0}}, {-1}, {1}), std::invalid_argument);

  // Through Fragments::info: the chain of two radii passes the larger diameter.
  std::vector<std::pair<int, int>> bonds;
  const dem::Particles p = chain(6, Vector3d::UnitZ(), r, &bonds);
  auto fr = dem::Fragments::from_particles(p, bonds);
  EXPECT_NEAR(fr.info(p)[0].sieve_size, d, 1e-12);
}

}  // namespace

namespace {

TEST(Fragments, FromWorldBondsSkipsBrokenOnes) {
  const dem::Particles p = chain(5, Vector3d::UnitX(), 0.005, nullptr);
  std::vector<dem::Bond> bonds(4);
  for (int k = 0; k < 4; ++k) {
    bonds[k].i = k;
    bonds[k].j = k + 1;
  }
  bonds[1].alive = 0;  // 1-2 already broken
  const auto fr = dem::Fragments::from_bonds(p, bonds);
  EXPECT_EQ(fr.num_fragments(), 2);
  EXPECT_EQ(fr.num_bonds(), 3u);
  EXPECT_EQ(fr.members(fr.fragment_of(p.id[4])), (std::vector<uint64_t>{2, 3, 4}));
}

}  // namespace
