// effects.drive_efficiency (mbd/drive_efficiency.hpp): the recorded power is the motor's input, shaft power /
// efficiency (x efficiency when the shaft drives the motor) + P0 (w / w_ref)^k; the motion is that of the run
// without it, bit for bit (a measurement transform), and the audit books the drive's losses.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/config.hpp"
#include "mbd/drive_efficiency.hpp"
#include "mbd/mechanism.hpp"
#include "mbd/power_partition.hpp"
#include "mbd/simulate.hpp"
#include "shipped_mechanism.hpp"

namespace {

mbd::Recording run(const mbd::MechanismParams& p) {
  mbd::SimOptions o;
  o.duration_s = 1.0;
  o.settle_s = 3.0;
  return mbd::simulate(p, o);
}

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s / v.size();
}

TEST(DriveEfficiency, RecordedPowerIsShaftOverEfficiencyPlusNoLoadLossAndTheMotionIsUnchanged) {
  for (double rpm : {400.0, 600.0}) {
    auto base = test_mbd::shipped_mechanism();
    base.drive_speed_rad_s = rpm * 2 * M_PI / 60;
    base.dt_s = 0.5e-3;
    auto p = base;
    auto& d = p.effects.drive_efficiency;
    d.enabled = true;
    d.efficiency = 0.85;
    d.no_load_W = 4e3;
    d.reference_speed_rad_s = 400 * 2 * M_PI / 60;
    d.speed_exponent = 2.0;
    const auto r = run(p), r0 = run(base);
    ASSERT_EQ(r.t_s.size(), r0.t_s.size());
    const double no_load = 4e3 * std::pow(rpm / 400.0, 2.0);
    int regen = 0;
    for (std::size_t i = 0; i < r.t_s.size(); ++i) {
      ASSERT_EQ(r.x_m[i], r0.x_m[i]) << "the motion changed at sample " << i;
      ASSERT_EQ(r.speed_rad_s[i], r0.speed_rad_s[i]);
      const double shaft = r0.power_W[i];
      const double expected = (shaft >= 0 ? shaft / 0.85 : shaft * 0.85) +
                              4e3 * std::pow(r0.speed_rad_s[i] / d.reference_speed_rad_s, 2.0);
      ASSERT_NEAR(r.power_W[i], expected, 1e-9 * std::fabs(expected)) << "sample " << i;
      regen += shaft < 0;
    }
    std::printf("drive efficiency 0.85, no-load 4 kW at 400 rpm: %.0f rpm shaft %.2f kW -> recorded %.2f kW "
                "(no-load %.2f kW, %d regenerating samples)\n",
                rpm, mean(r0.power_W) / 1e3, mean(r.power_W) / 1e3, no_load / 1e3, regen);
    EXPECT_NEAR(mean(r.power_W), mean(r0.power_W) / 0.85 + no_load, 0.002 * mean(r.power_W));
  }
}

TEST(DriveEfficiency, TheAuditBooksTheMotorInputAndOffItIsTheDrive) {
  auto base = test_mbd::shipped_mechanism();
  auto p = base;
  p.effects.drive_efficiency.enabled = true;
  p.effects.drive_efficiency.efficiency = 0.9;
  mbd::Mechanism m(p, mbd::LoadModel::Bed), m0(base, mbd::LoadModel::Bed);
  m.advance(3.0);
  m0.advance(3.0);
  const auto a = m.flows(), a0 = m0.flows();
  m.advance(1.0);
  m0.advance(1.0);
  const auto part = mbd::power_partition(a, 3.0, m.flows(), 4.0), part0 = mbd::power_partition(a0, 3.0, m0.flows(), 4.0);
  std::printf("%s\n", mbd::describe(part).c_str());
  EXPECT_EQ(part0.motor_input, part0.drive);  // off: the same number
  EXPECT_EQ(part.drive, part0.drive);         // the shaft does the same work
  EXPECT_NEAR(part.motor_input, part.drive / 0.9, 0.01 * part.motor_input);
  EXPECT_EQ(m.drive().power, m0.drive().power);
  EXPECT_NEAR(m.drive().input_power, mbd::motor_input_power(p.effects.drive_efficiency, m.drive().power, m.drive().speed),
              1e-12 * std::fabs(m.drive().input_power));
}

TEST(DriveEfficiency, KeysLoadAndAreWrittenOnlyWhenOn) {
  auto p = test_mbd::shipped_mechanism();
  const std::string off = mbd::to_yaml(p);
  EXPECT_EQ(off.find("drive_efficiency"), std::string::npos) << off;
  EXPECT_EQ(off.find("bearing_friction"), std::string::npos) << off;
  p.effects.drive_efficiency.enabled = true;
  p.effects.drive_efficiency.efficiency = 0.87;
  p.effects.drive_efficiency.no_load_W = 2.5e3;
  p.effects.bearing_friction.enabled = true;
  p.effects.bearing_friction.mu = 0.01;
  const auto q = mbd::load_mechanism_params(core::ConfigNode::load_string(mbd::to_yaml(p), "test").child("mbd"));
  EXPECT_TRUE(q.effects.drive_efficiency.enabled);
  EXPECT_DOUBLE_EQ(q.effects.drive_efficiency.efficiency, 0.87);
  EXPECT_DOUBLE_EQ(q.effects.drive_efficiency.no_load_W, 2.5e3);
  EXPECT_NEAR(q.effects.drive_efficiency.reference_speed_rad_s, 400 * 2 * M_PI / 60, 1e-12);
  EXPECT_TRUE(q.effects.bearing_friction.enabled);
  EXPECT_DOUBLE_EQ(q.effects.bearing_friction.mu, 0.01);
  EXPECT_DOUBLE_EQ(q.effects.bearing_friction.bushing_radius_m, 0.1);
  p.effects.drive_efficiency.efficiency = 1.2;
  try {
    mbd::validate(p);
    FAIL() << "expected a throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mbd.effects.drive_efficiency.efficiency"), std::string::npos) << e.what();
  }
}

}  // namespace
