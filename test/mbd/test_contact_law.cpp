// Eq. 11 (normal force), Eq. 14-15 (friction coefficient), Table 1 unit conversion.
#include <gtest/gtest.h>

#include <cmath>

#include "core/config.hpp"
#include "mbd/contact_law.hpp"
#include "mbd/mechanism_params.hpp"
#include "shipped_mechanism.hpp"

namespace {

TEST(ContactLaw, TableOneConvertedToSiAtLoad) {
  const auto p = test_mbd::shipped_mechanism();
  // k = 1e5 N/mm^1.5 -> 1e5 * 1000^1.5 N/m^1.5; c = 50 (kg-s-mm) -> 50 * 1000^(1+2).
  EXPECT_NEAR(p.contact.k, 3.1622776601683795e9, 1.0);
  EXPECT_NEAR(p.contact.c, 5.0e10, 1.0);
  EXPECT_DOUBLE_EQ(p.contact.h1, 1.5);
  EXPECT_DOUBLE_EQ(p.contact.v_s, 1e-3);
  EXPECT_DOUBLE_EQ(p.contact.v_d, 1e-2);
  // Absorbers: 320 N/mm -> 3.2e5 N/m, 100 N s/mm -> 1e5 N s/m.
  EXPECT_DOUBLE_EQ(p.absorber_k_N_per_m.x(), 3.2e5);
  EXPECT_DOUBLE_EQ(p.absorber_k_N_per_m.z(), 9.7e5);
  EXPECT_DOUBLE_EQ(p.absorber_c_Ns_per_m.y(), 1.0e5);
}

TEST(ContactLaw, Eq11HandComputedInBothUnitSystems) {
  const auto p = test_mbd::shipped_mechanism();
  // Hand computation in kg-s-mm-N: d = 0.5 mm, d_dot = 20 mm/s:
  //   1e5 * 0.5^1.5 + 50 * 20^1 * 0.5^2 = 35355.339 + 250 = 35605.339 N
  const double mm_units = 1e5 * std::pow(0.5, 1.5) + 50.0 * 20.0 * 0.25;
  EXPECT_NEAR(mm_units, 35605.339, 1e-3);
  // Same contact in SI through our law with the converted parameters.
  EXPECT_NEAR(mbd::normal_force_eq11(p.contact, 0.5e-3, 0.02), 35605.339, 1e-2);
  // Separating (d_dot < 0): the damping term changes sign ("d/|d_dot|" read as sign(d_dot)).
  EXPECT_NEAR(mbd::normal_force_eq11(p.contact, 0.5e-3, -0.02), 35355.339 - 250.0, 1e-2);
  // No indentation, no force; the force never pulls.
  EXPECT_EQ(mbd::normal_force_eq11(p.contact, -1e-3, 0.0), 0.0);
  // d = 0.1 mm separating at 100 m/s: 3162 N elastic - 50000 N damping -> clipped to 0.
  EXPECT_EQ(mbd::normal_force_eq11(p.contact, 1e-4, -100.0), 0.0);
  // Second point: d = 2 mm, d_dot = 5 mm/s: 1e5 * 2^1.5 + 50 * 5 * 4 = 282842.712 + 1000.
  EXPECT_NEAR(mbd::normal_force_eq11(p.contact, 2e-3, 5e-3), 283842.712, 1e-2);
}

TEST(ContactLaw, Eq15Haversine) {
  EXPECT_DOUBLE_EQ(mbd::havsin(-1.0, 0.0, 0.0, 1.0, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(mbd::havsin(2.0, 0.0, 0.0, 1.0, 1.0), 1.0);
  EXPECT_NEAR(mbd::havsin(0.5, 0.0, 0.0, 1.0, 1.0), 0.5, 1e-15);
  EXPECT_NEAR(mbd::havsin(0.25, 0.0, 0.0, 1.0, 1.0), 0.5 - 0.5 * std::sin(0.25 * M_PI), 1e-15);
}

TEST(ContactLaw, Eq14FrictionCoefficient) {
  const double ms = 0.3, md = 0.25, vs = 1e-3, vd = 10e-3;  // Table 1
  auto mu = [&](double v) { return mbd::friction_coefficient_eq14(v, ms, md, vs, vd); };
  EXPECT_NEAR(mu(0.0), 0.0, 1e-15);
  EXPECT_NEAR(mu(vs), -ms, 1e-12);
  EXPECT_NEAR(mu(-vs), ms, 1e-12);
  EXPECT_NEAR(mu(vd), -md, 1e-12);
  EXPECT_NEAR(mu(0.1), -md, 1e-15);
  EXPECT_NEAR(mu(-0.1), md, 1e-15);
  // Inside the stick band: havsin(0.5, -1, 0.3, 1, -0.3) = -0.3 sin(pi/4) (mm/s units).
  EXPECT_NEAR(mu(0.5e-3), -0.3 * std::sin(M_PI / 4.0), 1e-12);
  // Middle of the stick-slip transition: (mu_s + mu_d) / 2.
  EXPECT_NEAR(mu(5.5e-3), -0.275, 1e-12);
  EXPECT_NEAR(mu(-5.5e-3), 0.275, 1e-12);
  // Odd function and continuous at the band edges.
  for (double v : {2e-4, 9e-4, 3e-3, 9.9e-3, 0.05}) EXPECT_NEAR(mu(v), -mu(-v), 1e-14);
  EXPECT_NEAR(mu(vs * (1 - 1e-9)), mu(vs * (1 + 1e-9)), 1e-6);
  EXPECT_NEAR(mu(vd * (1 - 1e-9)), mu(vd * (1 + 1e-9)), 1e-6);
}

}  // namespace
