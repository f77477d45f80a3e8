// Where the drive's power goes (mbd::power_partition): a drag on the mantle stands for the rock.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "core/config.hpp"
#include "mbd/mechanism.hpp"
#include "mbd/mechanism_params.hpp"
#include "mbd/power_partition.hpp"
#include "shipped_mechanism.hpp"

namespace {

// The idle machine with a viscous drag F = -c v held on the floating cone's centre of mass, set each step from its
// velocity (as the DEM's wrench is set each coupling step). Over 20 whole cycles the partition's load is that
// drag's power, c |v|^2 summed by the test, and the parts add up to the drive's power (the mechanism's energy
// returns to itself over whole cycles).
TEST(PowerPartition, DragOnTheMantleIsBookedAsLoadAndThePartsAddUp) {
  const auto p = test_mbd::shipped_mechanism();
  const double c = 1e5;  // N s/m
  mbd::Mechanism m(p, mbd::LoadModel::None);
  m.advance(4.0);  // drive ramp and frame transient gone
  auto drag = [&] {
    const Eigen::Vector3d v = m.body(mbd::BodyId::FloatingCone).linear_velocity;
    m.set_particle_wrench(mbd::BodyId::FloatingCone, -c * v, Eigen::Vector3d::Zero());
    return c * v.squaredNorm();
  };
  for (int i = 0; i < 2000; ++i) drag(), m.step();  // 2 s more with the drag: its own steady state
  const auto a = m.flows();
  const double ta = m.time();
  const long steps = std::lround(20 * 2 * M_PI / p.drive_speed_rad_s / p.dt_s);
  double work = 0;
  for (long i = 0; i < steps; ++i) {
    work += drag() * p.dt_s;
    m.step();
  }
  const auto part = mbd::power_partition(a, ta, m.flows(), m.time());
  std::printf("%s; the drag's own c v^2: %.2f kW\n", mbd::describe(part).c_str(), work / (m.time() - ta) / 1e3);
  EXPECT_GT(part.load, 5e3);
  EXPECT_NEAR(part.load, work / (m.time() - ta), 0.03 * part.load);
  EXPECT_GT(part.absorbers, 0.0);
  EXPECT_EQ(part.bed, 0.0);
  EXPECT_EQ(part.joint_friction, 0.0);
  EXPECT_NEAR(part.residual(), 0.0, 0.01 * part.drive);
  EXPECT_GT(part.drive, part.load + part.absorbers - 0.01 * part.drive);
  EXPECT_THROW(mbd::power_partition(a, ta, a, ta), std::invalid_argument);
}

}  // namespace
