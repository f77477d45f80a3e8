// Each omitted-physics effect changes the signals the way its law says.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>

#include "core/config.hpp"
#include "mbd/mechanism.hpp"
#include "mbd/mechanism_params.hpp"
#include "mbd/simulate.hpp"
#include "shipped_mechanism.hpp"

namespace {

double mean(const std::vector<double>& x) {
  double m = 0;
  for (double v : x) m += v;
  return m / x.size();
}

double harmonic(const std::vector<double>& t, const std::vector<double>& x, double f) {
  const double m = mean(x);
  std::complex<double> s = 0;
  for (std::size_t i = 0; i < x.size(); ++i) s += (x[i] - m) * std::exp(std::complex<double>(0, -2 * M_PI * f * t[i]));
  return 2.0 * std::abs(s) / x.size();
}

mbd::Recording run(const mbd::MechanismParams& p, double seconds = 3.0) {
  mbd::SimOptions o;
  o.duration_s = seconds;
  o.settle_s = 3.0;
  return mbd::simulate(p, o);
}

const mbd::Recording& baseline() {
  static const mbd::Recording r = run(test_mbd::shipped_mechanism());
  return r;
}

TEST(Effects, MotorDroopLowersSpeedByDroopTimesTorque) {
  auto p = test_mbd::shipped_mechanism();
  p.effects.motor_droop.enabled = true;
  p.effects.motor_droop.droop_rad_s_per_Nm = 0.5e-3;  // 0.5 rad/s per kN m
  const auto r = run(p);
  const double w = mean(r.speed_rad_s);
  double torque = 0;
  for (std::size_t i = 0; i < r.t_s.size(); ++i) torque += r.power_W[i] / r.speed_rad_s[i];
  torque /= r.t_s.size();
  const double expected = p.drive_speed_rad_s - 0.5e-3 * torque;
  std::printf("droop: mean torque %.0f N m, mean speed %.4f rad/s, expected %.4f, baseline %.4f\n", torque, w, expected,
              mean(baseline().speed_rad_s));
  EXPECT_GT(torque, 1000.0);
  EXPECT_NEAR(w, expected, 0.02 * (p.drive_speed_rad_s - expected));
  EXPECT_NEAR(mean(baseline().speed_rad_s), p.drive_speed_rad_s, 1e-6);
}

TEST(Effects, MotorDroopTooStiffForTheStepIsRejected) {
  auto p = test_mbd::shipped_mechanism();
  p.effects.motor_droop.enabled = true;
  p.effects.motor_droop.droop_rad_s_per_Nm = 1e-6;
  try {
    mbd::validate(p);
    FAIL() << "expected a throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mbd.effects.motor_droop.droop_rad_s_per_kNm"), std::string::npos) << e.what();
  }
}

TEST(Effects, JointFrictionAddsItsDissipationToThePower) {
  auto p = test_mbd::shipped_mechanism();
  p.effects.joint_friction.enabled = true;
  p.effects.joint_friction.coulomb_Nm = 300.0;
  mbd::Mechanism m(p, mbd::LoadModel::Bed);
  m.advance(3.0);
  const auto a = m.energy();
  m.advance(3.0);
  const auto b = m.energy();
  const double friction_power = (b.joint_friction_dissipation - a.joint_friction_dissipation) / 3.0;
  const double drive_power = (b.drive_work - a.drive_work) / 3.0;
  const double base_power = mean(baseline().power_W);
  // O3 turns at ~ the drive speed relative to the shaft: ~ coulomb x w = 12.6 kW.
  const double coulomb_w = 300.0 * p.drive_speed_rad_s;
  std::printf("joint friction: dissipation %.2f kW (coulomb x w %.2f kW), power %.2f kW vs baseline %.2f kW\n",
              friction_power / 1e3, coulomb_w / 1e3, drive_power / 1e3, base_power / 1e3);
  EXPECT_NEAR(friction_power, coulomb_w, 0.15 * coulomb_w);
  EXPECT_NEAR(drive_power - base_power, friction_power, 0.3 * friction_power);
}

TEST(Effects, CardanMisalignmentGivesTwiceDriveFrequencyRipple) {
  auto p = test_mbd::shipped_mechanism();
  p.effects.cardan_misalignment.enabled = true;
  p.effects.cardan_misalignment.angle_rad = 10.0 * M_PI / 180;
  const auto r = run(p);
  const double f = p.drive_speed_rad_s / (2 * M_PI);
  const double h2 = harmonic(r.t_s, r.power_W, 2 * f), h2_base = harmonic(baseline().t_s, baseline().power_W, 2 * f);
  // Vibrator speed ripple +-(1/cos b - cos b)/2 ~ 1.5 % at 2w; its inertia torque I w (2w) dw ripples
  // the drive power at 2f by several kW.
  std::printf("cardan 10 deg: power 2f harmonic %.2f kW (baseline %.2f kW), x 2f %.4f mm (baseline %.4f mm)\n",
              h2 / 1e3, h2_base / 1e3, harmonic(r.t_s, r.x_m, 2 * f) * 1e3,
              harmonic(baseline().t_s, baseline().x_m, 2 * f) * 1e3);
  EXPECT_GT(h2, 3.0 * h2_base);
  EXPECT_GT(h2, 2e3);
}

TEST(Effects, AbsorberNonlinearityStiffensTheFrame) {
  auto p = test_mbd::shipped_mechanism();
  p.effects.absorber_nonlinearity.enabled = true;
  p.effects.absorber_nonlinearity.cubic_N_per_m3 = 5e10;
  const auto r = run(p);
  const double f = p.drive_speed_rad_s / (2 * M_PI);
  const double a = harmonic(r.t_s, r.x_m, f), a0 = harmonic(baseline().t_s, baseline().x_m, f);
  const double a3 = harmonic(r.t_s, r.x_m, 3 * f), a3_0 = harmonic(baseline().t_s, baseline().x_m, 3 * f);
  std::printf("absorber cubic: x at f %.4f mm (baseline %.4f), at 3f %.5f mm (baseline %.5f)\n", a * 1e3, a0 * 1e3,
              a3 * 1e3, a3_0 * 1e3);
  // Above resonance (mass-controlled frame) a stiffer spring raises the amplitude: harmonic balance
  // k_eq = k1 + 3/4 k3 X^2, X ~ F / (M w^2 - k_eq).
  const double M = p.fixed_cone.mass_kg + p.floating_cone.mass_kg + p.vibrator.mass_kg + p.globe_bearing.mass_kg;
  const double w = p.drive_speed_rad_s, k1 = p.absorber_k_N_per_m.x();
  const double predicted = (M * w * w - k1) / (M * w * w - k1 - 0.75 * 5e10 * a * a);
  std::printf("absorber cubic: amplitude ratio %.4f, harmonic balance %.4f\n", a / a0, predicted);
  EXPECT_NEAR(a / a0 - 1.0, predicted - 1.0, 0.3 * (predicted - 1.0));
  EXPECT_GT(a3, 1.2 * a3_0);  // odd harmonics of the cubic spring
}

TEST(Effects, AbsorberHysteresisDissipates) {
  auto p = test_mbd::shipped_mechanism();
  p.effects.absorber_nonlinearity.enabled = true;
  p.effects.absorber_nonlinearity.hysteresis = 0.5;
  mbd::Mechanism m(p, mbd::LoadModel::Bed), m0(test_mbd::shipped_mechanism(), mbd::LoadModel::Bed);
  m.advance(4.0);
  m0.advance(4.0);
  const auto a = m.energy(), a0 = m0.energy();
  m.advance(2.0);
  m0.advance(2.0);
  const double d = (m.energy().absorber_dissipation - a.absorber_dissipation) / 2.0;
  const double d0 = (m0.energy().absorber_dissipation - a0.absorber_dissipation) / 2.0;
  std::printf("absorber hysteresis 0.5: absorber dissipation %.1f W (baseline %.1f W)\n", d, d0);
  // Equivalent viscous c_h = eta k / w adds 3.8 % (x, y) and 11.6 % (z) to Table 1's dampers.
  EXPECT_GT(d, d0 * 1.015);
  EXPECT_LT(d, d0 * 1.15);
}

}  // namespace
