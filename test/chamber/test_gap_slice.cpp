// The virtual gap slice (src/chamber/gap_slice.hpp) and the pouring it shares with the piston die (rock_pour.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "chamber/gap_slice.hpp"

using namespace chamber;

namespace {
GapSliceOptions tiny_slice() {
  GapSliceOptions o;
  o.rock_count = 6, o.rock_min = 0.028, o.rock_max = 0.030;
  o.gap = o.depth = 0.07, o.stroke = 0.012;
  o.frequencies = {10.0, 20.0};
  o.cycles = 2;
  o.settle_max_time = 0.15;
  o.record_every = 1;
  o.threads = 1;
  return o;
}
void expect_refused(GapSliceOptions o, const std::string& name) {
  try {
    o.validate();
    ADD_FAILURE() << "accepted a bad " << name;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("accepted"), std::string::npos) << e.what();
  }
}
}  // namespace

TEST(GapSlice, OptionsNameWhatIsWrong) {
  EXPECT_NO_THROW(tiny_slice().validate());
  GapSliceOptions o = tiny_slice();
  o.gap = 0.05;  // under 2 x the largest rock
  expect_refused(o, "gap");
  o = tiny_slice(), o.stroke = 0.04;  // over half the gap
  expect_refused(o, "stroke");
  o = tiny_slice(), o.frequencies = {10.0, 0.0};
  expect_refused(o, "frequency");
  o = tiny_slice(), o.frequencies.clear();
  expect_refused(o, "frequencies");
  o = tiny_slice(), o.cycles = 0;
  expect_refused(o, "cycles");
}

// A small slice of the calibrated rock: the mantle plate moves on its closed-form path, every speed starts from the
// same poured bed, and the plate's work has the signs a dissipative bed gives.
TEST(GapSlice, ThePlateFollowsItsPathOverTheSamePouredBedAtEverySpeed) {
  const rocks::BpmModel bpm =
      rocks::load_bpm_model(std::string(CRUSHER_SOURCE_DIR) + "/launch_free_configs/bpm_calibrated.yaml");
  const GapSliceOptions o = tiny_slice();
  const GapSliceResult r = run_gap_slice(bpm, o);
  ASSERT_EQ(r.runs.size(), 2u);
  EXPECT_EQ(r.rocks, 6);
  EXPECT_GT(r.loose_solid_fraction, 0.1);
  EXPECT_LT(r.loose_solid_fraction, 0.75);
  for (const auto& run : r.runs) {
    ASSERT_TRUE(run.blowup.empty()) << run.blowup;
    ASSERT_EQ(run.cycles.size(), 2u);
    // the plate where the world moved it, every step: x = gap - stroke (1 - cos 2 pi f t) / 2 to round-off
    ASSERT_FALSE(run.t.empty());
    double worst = 0.0, closest = o.gap;
    for (std::size_t i = 0; i < run.t.size(); ++i) {
      const double x = o.gap - 0.5 * o.stroke * (1.0 - std::cos(2.0 * M_PI * run.frequency * run.t[i]));
      worst = std::max(worst, std::abs(run.gap[i] - x));
      closest = std::min(closest, run.gap[i]);
    }
    EXPECT_LT(worst, 1e-12);
    EXPECT_NEAR(closest, o.gap - o.stroke, 1e-9);
    EXPECT_NEAR(run.t.back(), o.cycles / run.frequency, 1e-12);
    // both speeds press the bed as it was poured
    EXPECT_EQ(run.cycles[0].top, r.bed_height);
    for (const auto& c : run.cycles) {
      // the plate only pushes (no adhesion): it works on the rock while closing and the rock works on it while it
      // opens, so the cycle's net work is at most the closing half's
      EXPECT_GE(c.loading_work_per_kg, c.work_per_kg);
      EXPECT_GE(c.peak_force, 0.0);
    }
    EXPECT_GT(run.cycles[0].peak_force, 0.0);      // the 12 mm stroke reaches a bed poured across 70 mm
    EXPECT_GT(run.cycles[0].work_per_kg, 0.0);     // and dissipates
  }
  // the second speed alone is the same run: each speed's bed is a copy of the one poured bed
  GapSliceOptions alone = o;
  alone.frequencies = {20.0};
  const GapSliceResult s = run_gap_slice(bpm, alone);
  ASSERT_EQ(s.runs.size(), 1u);
  ASSERT_EQ(s.runs[0].cycles.size(), 2u);
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(s.runs[0].cycles[k].work_per_kg, r.runs[1].cycles[k].work_per_kg) << "cycle " << k + 1;
    EXPECT_EQ(s.runs[0].cycles[k].bonds_broken, r.runs[1].cycles[k].bonds_broken) << "cycle " << k + 1;
  }
  std::printf("tiny slice: %zu particles; 10 Hz %.3f, %.3f J/kg; 20 Hz %.3f, %.3f J/kg\n", r.particles,
              r.runs[0].cycles[0].work_per_kg, r.runs[0].cycles[1].work_per_kg, r.runs[1].cycles[0].work_per_kg,
              r.runs[1].cycles[1].work_per_kg);
}
