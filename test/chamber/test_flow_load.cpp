// The flow model as the mechanism's load (chamber/flow_load.hpp) on the shipped GYP1200: the drive's power is
// accounted for (drive = rock + absorbers + contact to a small residual at the steady state) and the power into the
// rock is the crushing energy the compression events booked (what the mechanism does on the bed is the beds' loss).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "chamber/flow_config.hpp"
#include "chamber/flow_load.hpp"
#include "core/config.hpp"
#include "mbd/power_partition.hpp"

namespace {
// The shipped run: the machine and the flow model's parameters of a config.
chamber::FlowRunConfig gyp1200(const std::string& name) {
  return chamber::load_flow_run_config(std::string(CRUSHER_SOURCE_DIR) + "/launch_free_configs/" + name);
}
}  // namespace

TEST(FlowLoad, DrivePowerGoesIntoTheRockAndMatchesTheCrushingEnergyBooked) {
  const auto [p, fp, run] = gyp1200("gyp1200_400rpm.yaml");
  mbd::Mechanism m(p, mbd::LoadModel::None);
  chamber::FlowLoad load(fp, p);
  while (m.time() < 4.0 - 1e-9) load.step(m);  // start-up: drive ramp, frame transient (the run's settle_s)
  const auto a = m.flows();
  const double ta = m.time(), e0 = load.model().crushing_energy_J();
  const double period = 2 * M_PI / p.drive_speed_rad_s;
  while (m.time() < ta + 20 * period - 1e-9) load.step(m);  // twenty whole drive cycles
  const auto part = mbd::power_partition(a, ta, m.flows(), m.time());
  const double crushing = (load.model().crushing_energy_J() - e0) / (m.time() - ta);
  ASSERT_GT(part.load, 5e3) << mbd::describe(part);
  EXPECT_LT(std::fabs(part.residual()), 0.03 * part.drive) << mbd::describe(part);
  // The rock's share and the events' booking agree (the bed's stored energy at both ends differs a little).
  EXPECT_NEAR(crushing, part.load, 0.03 * part.load) << mbd::describe(part) << "; booked " << crushing << " W";
  EXPECT_GT(load.model().mass_kg(), 50.0);  // the choke-fed chamber stays full
  std::printf("%s; booked %.2f kW\n", mbd::describe(part).c_str(), crushing * 1e-3);
}
