// Hertz-Mindlin contact law against closed forms: Hertz impact, restitution, oblique impact (Chung & Ooi 2011
// test 6 style, sliding regime), rolling friction (CDT) deceleration.
#include <gtest/gtest.h>

#include <cmath>

#include "dem/world.hpp"

namespace {

// Steps a single sphere (index 0) of radius r falling on the floor z = 0 until it has touched and left it.
void step_until_rebound(dem::World& w, double r) {
  bool touched = false;
  for (int s = 0; s < 2000000; ++s) {
    w.step(1);
    const bool in = w.particles().z[0] < r;
    if (in) touched = true;
    if (touched && !in) break;
  }
}

dem::WorldParams params_with(double e, double mu, double mu_r, double dt) {
  dem::WorldParams wp;
  wp.dt = dt;
  wp.gravity = {{0, 0, 0}};
  wp.threads = 1;
  dem::MaterialTable t;
  const int rock = t.add(dem::rock_table4());
  const int steel = t.add(dem::steel_table4());
  t.set_pair(rock, rock, mu, e, mu_r);
  t.set_pair(rock, steel, mu, e, mu_r);
  t.set_pair(steel, steel, mu, e, mu_r);
  wp.materials = t;
  return wp;
}

struct ImpactResult {
  double t_contact = 0, max_overlap = 0, v_after = 0;
};

// Two equal rock spheres approaching head-on with relative speed v.
ImpactResult head_on(double e, double v, double r, double dt) {
  dem::World w(params_with(e, 0.5, 0.0, dt));
  const double a[3] = {-r - 1e-6, 0, 0}, b[3] = {r + 1e-6, 0, 0};
  const double va[3] = {0.5 * v, 0, 0}, vb[3] = {-0.5 * v, 0, 0};
  w.add_particle(a, r, 0, va);
  w.add_particle(b, r, 0, vb);
  ImpactResult res;
  double t_in = -1;
  for (int s = 0; s < 200000; ++s) {
    w.step(1);
    const auto& p = w.particles();
    const double overlap = 2 * r - (p.x[1] - p.x[0]);
    // contact start interpolated inside the step from the approach speed
    if (overlap > 0 && t_in < 0) t_in = w.time() - overlap / v;
    if (overlap > 0) res.max_overlap = std::max(res.max_overlap, overlap);
    if (t_in >= 0 && overlap <= 0) {
      res.v_after = p.vx[1] - p.vx[0];
      res.t_contact = w.time() + overlap / res.v_after - t_in;  // end interpolated likewise (overlap <= 0)
      break;
    }
  }
  return res;
}

// Hertz theory: peak overlap (15 M* v^2 / (16 E* sqrt(r*)))^(2/5), contact time 2.94328 d_max / v.
TEST(HertzMindlin, ElasticImpactMatchesHertzTheory) {
  const double r = 1e-3, v = 0.5;
  const dem::Material rock = dem::rock_table4();
  const double m = rock.density * 4.0 / 3.0 * M_PI * r * r * r;
  const double Ms = m / 2, rs = r / 2, Es = rock.E() / (2 * (1 - rock.nu * rock.nu));
  const double dmax = std::pow(15 * Ms * v * v / (16 * Es * std::sqrt(rs)), 0.4);
  const double tc = 2.94328 * dmax / v;
  const double dt = tc / 2000;
  const ImpactResult res = head_on(1.0, v, r, dt);
  EXPECT_NEAR(res.max_overlap, dmax, 0.02 * dmax);
  // contact start/end are resolved to one step each
  EXPECT_NEAR(res.t_contact, tc, 0.02 * tc);
  EXPECT_NEAR(res.v_after, v, 1e-3 * v);  // elastic: relative speed restored
}

class Restitution : public ::testing::TestWithParam<double> {};

TEST_P(Restitution, MatchesRequestedCoefficient) {
  const double e = GetParam(), r = 1e-3;
  for (double v : {0.2, 2.0}) {
    const ImpactResult res = head_on(e, v, r, 1e-8);
    EXPECT_NEAR(res.v_after / v, e, 0.02 * e) << "impact speed " << v;
  }
}
INSTANTIATE_TEST_SUITE_P(HertzMindlin, Restitution, ::testing::Values(0.15, 0.5, 0.9));

// Sphere hitting a steel wall obliquely with no initial spin. In the sliding regime
// (v_t / v_n >= 7/2 mu (1 + e)) the friction impulse is mu (1 + e) m v_n, hence
// v_t' = v_t - mu (1 + e) v_n and w' = 5 mu (1 + e) v_n / (2 R) (Chung & Ooi 2011, test 6).
TEST(HertzMindlin, ObliqueImpactSlidingRegimeMatchesCoulombClosedForm) {
  const double r = 5e-3, V = 1.0, mu = 0.1, e = 0.9;
  for (double deg : {40.0, 50.0, 60.0, 70.0, 80.0}) {
    dem::World w(params_with(e, mu, 0.0, 2e-8));
    const double o[3] = {0, 0, 0}, nz[3] = {0, 0, 1};
    w.add_plane(o, nz, 1);
    const double th = deg * M_PI / 180;
    const double vn = V * std::cos(th), vt = V * std::sin(th);
    const double x[3] = {0, 0, r + 1e-7}, v[3] = {vt, 0, -vn};
    w.add_particle(x, r, 0, v);
    step_until_rebound(w, r);
    const auto& p = w.particles();
    const double e_meas = p.vz[0] / vn;  // normal restitution of this impact
    EXPECT_NEAR(e_meas, e, 0.02 * e);
    ASSERT_GE(vt / vn, 3.5 * mu * (1 + e_meas)) << "angle chosen outside the sliding regime";
    const double vt_expect = vt - mu * (1 + e_meas) * vn;
    const double w_expect = 5 * mu * (1 + e_meas) * vn / (2 * r);
    EXPECT_NEAR(p.vx[0], vt_expect, 0.01 * vt_expect) << deg << " deg";
    EXPECT_NEAR(p.wy[0], w_expect, 0.01 * w_expect) << deg << " deg";  // spin about +y for motion along +x
  }
}

// Below the sliding limit the contact sticks: the rebound spin stays below the sliding value and the contact
// point's tangential velocity is reversed or close to zero (Mindlin), unlike a pure Coulomb slider.
TEST(HertzMindlin, ObliqueImpactStickRegimeSpinBelowSlidingValue) {
  const double r = 5e-3, V = 1.0, mu = 0.1, e = 0.9, deg = 15;
  dem::World w(params_with(e, mu, 0.0, 2e-8));
  const double o[3] = {0, 0, 0}, nz[3] = {0, 0, 1};
  w.add_plane(o, nz, 1);
  const double th = deg * M_PI / 180, vn = V * std::cos(th), vt = V * std::sin(th);
  const double x[3] = {0, 0, r + 1e-7}, v[3] = {vt, 0, -vn};
  w.add_particle(x, r, 0, v);
  step_until_rebound(w, r);
  const auto& p = w.particles();
  EXPECT_LT(p.wy[0], 5 * mu * (1 + e) * vn / (2 * r));
  const double vc = p.vx[0] - r * p.wy[0];  // contact point velocity after impact
  EXPECT_LT(std::fabs(vc), 0.5 * vt) << "contact point velocity " << vc << " spin " << p.wy[0];
}

// A sphere rolling without slip on a wall under gravity with CDT rolling friction decelerates at
// a = 5/7 mu_r g (torque mu_r R m g, I = 2/5 m R^2).
TEST(HertzMindlin, RollingFrictionDecelerationMatchesClosedForm) {
  const double r = 5e-3, mu_r = 0.05, g = 9.81, v0 = 0.1;
  dem::WorldParams wp = params_with(0.5, 0.5, mu_r, 1e-6);
  wp.gravity = {{0, 0, -g}};
  dem::World w(wp);
  const double o[3] = {0, 0, 0}, nz[3] = {0, 0, 1};
  w.add_plane(o, nz, 1);
  const double x[3] = {0, 0, r}, v[3] = {v0, 0, 0}, om[3] = {0, v0 / r, 0};
  w.add_particle(x, r, 0, v, om);
  w.step(20000);  // settle the normal bounce
  const double t1 = w.time(), v1 = w.particles().vx[0];
  w.step(50000);
  const double t2 = w.time(), v2 = w.particles().vx[0];
  const double a = (v2 - v1) / (t2 - t1);
  EXPECT_NEAR(a, -5.0 / 7.0 * mu_r * g, 0.02 * 5.0 / 7.0 * mu_r * g);
  // still rolling without slip
  EXPECT_NEAR(w.particles().wy[0] * r, v2, 1e-3 * v0);
}

TEST(HertzMindlin, TimeStepCheckRefusesUnstableStepWithBothNumbers) {
  dem::World w(params_with(0.5, 0.5, 0.0, 1e-4));
  const double x[3] = {0, 0, 0};
  w.add_particle(x, 1e-3, 0);
  try {
    w.step(1);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& ex) {
    const std::string m = ex.what();
    EXPECT_NE(m.find("Rayleigh"), std::string::npos) << m;
    EXPECT_NE(m.find("bond"), std::string::npos) << m;
  }
  // Rayleigh step of a 1 mm rock sphere: pi r sqrt(rho/G) / (0.1631 nu + 0.8766)
  const double expect = M_PI * 1e-3 * std::sqrt(2600 / 5.08e8) / (0.1631 * 0.35 + 0.8766);
  EXPECT_NEAR(w.time_step_check().rayleigh, expect, 1e-12);
}

}  // namespace
