// effects.bearing_friction (mechanism.cpp): Coulomb friction mu r |reaction| in the vibrator's bushing O3 and the
// spherical support O1. Closed form on the idle machine: the bushing carries the vibrator's centripetal force
// m_v w^2 R_c (R_c: the radius of its centre of mass's circle, e + the floating cone's swing at O3; the O4 plane
// leaves the in-plane force to O3 and the light O5), the bushing slides at w_rel (the vibrator's spin relative to
// the floating cone), so its power is mu r m_v w^2 R_c w_rel ~ mu r S w^3 at a constant swing: a w^3 law.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>

#include "mbd/mechanism.hpp"
#include "mbd/power_partition.hpp"
#include "shipped_mechanism.hpp"

namespace {

struct IdleRun {
  double w = 0;           // rad/s, drive
  double bushing = 0;     // W, bushing friction dissipation
  double sphere = 0;      // W
  double radius = 0;      // m, R_c: first-harmonic amplitude of the vibrator COM's x
  double w_rel = 0;       // rad/s, mean spin of the vibrator relative to the floating cone
  mbd::PowerPartition part;
};

IdleRun idle(mbd::MechanismParams p, double rpm, double seconds = 2.0) {
  p.drive_speed_rad_s = rpm * 2 * M_PI / 60;
  p.dt_s = 0.5e-3;
  mbd::Mechanism m(p, mbd::LoadModel::None);
  m.advance(3.0);  // ramp and frame transient
  IdleRun r;
  r.w = p.drive_speed_rad_s;
  const double period = 2 * M_PI / r.w, t0 = m.time();
  const auto a = m.flows();
  std::complex<double> h = 0;
  long n = 0;
  const long steps = std::lround(std::round(seconds / period) * period / p.dt_s);
  for (long i = 0; i < steps; ++i) {
    m.step();
    const auto v = m.body(mbd::BodyId::Vibrator), c = m.body(mbd::BodyId::FloatingCone);
    const Eigen::Vector3d ax = c.orientation * Eigen::Vector3d::UnitZ();
    r.w_rel += ax.dot(v.angular_velocity - c.angular_velocity);
    h += v.position.x() * std::exp(std::complex<double>(0, -r.w * (m.time() - t0)));
    ++n;
  }
  const auto b = m.flows();
  const double T = m.time() - t0;
  r.w_rel /= n;
  r.radius = 2.0 * std::abs(h) / n;
  r.bushing = (b.bushing_friction_dissipation - a.bushing_friction_dissipation) / T;
  r.sphere = (b.sphere_friction_dissipation - a.sphere_friction_dissipation) / T;
  r.part = mbd::power_partition(a, t0, b, m.time());
  return r;
}

TEST(BearingFriction, IdleBushingPowerIsMuRTimesTheVibratorForceTimesSlipAndGrowsAsWCubed) {
  auto p = test_mbd::shipped_mechanism();
  p.effects.bearing_friction.enabled = true;
  p.effects.bearing_friction.mu = 0.05;
  p.effects.bearing_friction.bushing_radius_m = 0.1;
  p.effects.bearing_friction.sphere_radius_m = 0.0;  // O3 alone (the cone contact holds the mantle's spin at idle)
  const double mu_r = 0.05 * 0.1, S = p.vibrator_static_moment_kg_m, mv = p.vibrator.mass_kg;
  IdleRun run[2] = {idle(p, 400), idle(p, 600)};
  for (const auto& r : run) {
    const double closed = mu_r * mv * r.w * r.w * r.radius * r.w_rel;
    std::printf("bearing friction idle %.0f rpm: bushing %.2f kW, mu r m_v w^2 R_c w_rel %.2f kW (R_c %.1f mm = e + "
                "%.1f mm, w_rel/w %.4f), mu r S w^3 %.2f kW; %s\n",
                r.w * 60 / (2 * M_PI), r.bushing / 1e3, closed / 1e3, r.radius * 1e3,
                (r.radius - S / mv) * 1e3, r.w_rel / r.w, mu_r * S * std::pow(r.w, 3) / 1e3,
                mbd::describe(r.part).c_str());
    EXPECT_NEAR(r.bushing, closed, 0.03 * closed);
    EXPECT_EQ(r.sphere, 0.0);
    EXPECT_NEAR(r.part.bearing_friction, r.bushing, 1e-9 * r.bushing);
    EXPECT_LT(std::fabs(r.part.residual()), 0.02 * r.part.drive) << mbd::describe(r.part);
  }
  // The law: w^3 at a constant swing (the mantle rests on the concave: R_c the same at both speeds). A w^2 law
  // would give 2.25 instead of 3.375.
  const double ratio = run[1].bushing / run[0].bushing, cube = std::pow(run[1].w / run[0].w, 3);
  std::printf("bearing friction idle: P(600) / P(400) = %.3f, (600/400)^3 = %.3f\n", ratio, cube);
  EXPECT_NEAR(ratio, cube, 0.05 * cube);
}

// Loaded (the equivalent bed), both joints on: the friction's power is booked (drive = the dissipations + a small
// residual) and the drive supplies it (its power rises by about the friction's).
TEST(BearingFriction, LoadedRunBooksItsDissipationAndTheDrivePaysForIt) {
  auto base = test_mbd::shipped_mechanism();
  auto p = base;
  p.effects.bearing_friction.enabled = true;
  p.effects.bearing_friction.mu = 0.02;
  auto measure = [](const mbd::MechanismParams& q) {
    mbd::Mechanism m(q, mbd::LoadModel::Bed);
    m.advance(4.0);
    const auto a = m.flows();
    const double t0 = m.time(), period = 2 * M_PI / q.drive_speed_rad_s;
    m.advance(std::round(2.0 / period) * period);
    return mbd::power_partition(a, t0, m.flows(), m.time());
  };
  const auto with = measure(p), without = measure(base);
  std::printf("bearing friction mu 0.02 (bed): %s\nbaseline: %s\n", mbd::describe(with).c_str(),
              mbd::describe(without).c_str());
  EXPECT_GT(with.bearing_friction, 1e3);
  EXPECT_LT(std::fabs(with.residual()), 0.02 * with.drive) << mbd::describe(with);
  EXPECT_NEAR(with.drive - without.drive, with.bearing_friction, 0.25 * with.bearing_friction);
  EXPECT_EQ(without.bearing_friction, 0.0);
}

TEST(BearingFriction, AFrictionCoefficientOutOfRangeIsRefusedByName) {
  auto p = test_mbd::shipped_mechanism();
  p.effects.bearing_friction.enabled = true;
  p.effects.bearing_friction.mu = 0.5;
  try {
    mbd::validate(p);
    FAIL() << "expected a throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mbd.effects.bearing_friction.mu"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("[0, 0.3]"), std::string::npos) << e.what();
  }
}

}  // namespace
