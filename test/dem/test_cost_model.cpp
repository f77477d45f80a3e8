// The azimuthal-sector cost model (dem/cost_model.hpp) against its formula worked by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "dem/cost_model.hpp"

namespace {

dem::CostModelInputs inputs() {
  dem::CostModelInputs in;
  in.particles = 1e5;
  in.dt_s = 1e-6;
  in.core_s_per_particle_step = 2e-7;  // 0.02 s per step on one core
  in.serial_s_per_step = 1e-4;
  in.ghost_width_m = 0.02;
  in.mean_radius_m = 0.5 / M_PI;  // circumference 1 m: 2,000 ghosts per boundary
  in.bandwidth_B_s = 1e9;
  in.latency_s = 1e-5;
  in.steps_per_coupling = 1000;
  return in;
}

TEST(CostModel, OneRankHasNoCommunication) {
  const auto r = dem::cost_model(inputs(), 1);
  EXPECT_DOUBLE_EQ(r.comm_s, 0.0);
  EXPECT_NEAR(r.wall_h_per_sim_s, (0.02 + 1e-4) / 1e-6 / 3600, 1e-9);
  EXPECT_DOUBLE_EQ(r.efficiency, 1.0);
}

TEST(CostModel, EightRanksByHand) {
  const auto r = dem::cost_model(inputs(), 8);
  EXPECT_NEAR(r.ghosts_per_boundary, 2000, 1e-9);
  EXPECT_NEAR(r.compute_s, (1e5 / 8 + 2 * 2000 * 0.25) * 2e-7, 1e-15);  // its own 12,500; 4,000 ghosts at 0.25
  // 4 messages + 2 boundaries x 2000 ghosts x 72 B at 1 GB/s + allreduce 2 x 3 x L over 1000 steps
  const double comm = 4e-5 + 2 * 2000 * 72 / 1e9 + 6e-5 / 1000;
  EXPECT_NEAR(r.comm_s, comm, 1e-15);
  const double t = 0.0027 + 1e-4 + comm;
  EXPECT_NEAR(r.wall_h_per_sim_s, t / 1e-6 / 3600, 1e-9);
  EXPECT_NEAR(r.efficiency, 0.0201 / (8 * t), 1e-12);
  EXPECT_FALSE(r.sectors_too_thin);  // 1 m / 8 = 125 mm > 40 mm
  EXPECT_TRUE(dem::cost_model(inputs(), 32).sectors_too_thin);  // 31 mm < 40 mm
}

TEST(CostModel, AMeasuredGhostFactorScalesTheGhostsAndTheirTraffic) {
  auto in = inputs();
  in.ghost_factor = 1.5;
  const auto r = dem::cost_model(in, 8);
  EXPECT_NEAR(r.ghosts_per_boundary, 3000, 1e-9);
  EXPECT_NEAR(r.comm_s, 4e-5 + 2 * 3000 * 72 / 1e9 + 6e-5 / 1000, 1e-15);
  EXPECT_NEAR(r.compute_s, (1e5 / 8 + 2 * 3000 * 0.25) * 2e-7, 1e-15);
  in.ghost_factor = 0;
  EXPECT_THROW(dem::cost_model(in, 8), std::invalid_argument);
}

TEST(CostModel, RefusesBadInput) {
  auto in = inputs();
  in.particles = 0;
  EXPECT_THROW(dem::cost_model(in, 2), std::invalid_argument);
  EXPECT_THROW(dem::cost_model(inputs(), 0), std::invalid_argument);
  in = inputs();
  in.ghost_work = -0.1;
  EXPECT_THROW(dem::cost_model(in, 2), std::invalid_argument);
}

}  // namespace
