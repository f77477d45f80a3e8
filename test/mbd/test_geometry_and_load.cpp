// Chamber profiles (closest approach in the meridian plane) and the external (particle) wrench input.
#include <gtest/gtest.h>

#include <cmath>

#include "core/chamber_geometry.hpp"
#include "core/config.hpp"
#include "mbd/mechanism.hpp"
#include "mbd/mechanism_params.hpp"
#include "shipped_mechanism.hpp"

namespace {

TEST(ChamberGeometry, SignedDistanceToAConeProfile) {
  core::Profile c;
  c.z = {0.0, -1.0};
  c.r = {0.5, 1.5};  // r = 0.5 - z: a 45 deg cone opening downwards
  Eigen::Vector2d n;
  // Point on the axis side at z = -0.5 (profile radius 1.0), r = 0.8: distance 0.2 cos 45.
  EXPECT_NEAR(core::signed_distance_inside(c, {-0.5, 0.8}, &n), 0.2 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(n.x(), 1.0 / std::sqrt(2.0), 1e-12);  // outward normal (z, r) = (1, 1)/sqrt 2
  EXPECT_NEAR(n.y(), 1.0 / std::sqrt(2.0), 1e-12);
  // Outside (penetrating the concave) is negative.
  EXPECT_NEAR(core::signed_distance_inside(c, {-0.5, 1.1}, nullptr), -0.1 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(c.radius_at(-0.25), 0.75, 1e-12);
  EXPECT_NEAR(c.length(), std::sqrt(2.0), 1e-12);
}

// The batch form (the flow model's cells) gives what signed_distance gives point by point (to round-off: the compiler
// may fuse the multiply-adds of the two loops differently), with the same closest segment: points beside segments,
// past both ends, at a kink, on both sides and more than one block of them.
TEST(ChamberGeometry, ProfileDistancesOfManyPointsAreThoseOfEachPoint) {
  core::Profile c;
  c.z = {0.0, -0.3, -0.5, -1.0};
  c.r = {0.4, 0.55, 0.9, 1.2};  // three segments, kinks at -0.3 and -0.5
  const core::ProfileDistance pd(c);
  std::vector<double> z, r;
  for (int i = 0; i < 150; ++i) {  // 150 points: more than one block of 64
    z.push_back(0.2 - 1.5 * i / 149.0);
    r.push_back(0.3 + 1.1 * std::fmod(0.37 * i, 1.0));
  }
  std::vector<double> d(z.size());
  std::vector<int> seg(z.size());
  pd.signed_distances(z.size(), z.data(), r.data(), d.data(), seg.data());
  int positive = 0, negative = 0;
  for (std::size_t i = 0; i < z.size(); ++i) {
    Eigen::Vector2d n;
    const double one = pd.signed_distance(z[i], r[i], &n);
    EXPECT_NEAR(d[i], one, 1e-15) << "point " << i;
    EXPECT_EQ(pd.normal_zr(seg[i]), n) << "point " << i;
    (one > 0 ? positive : negative) += 1;
  }
  EXPECT_GT(positive, 20);
  EXPECT_GT(negative, 20);
}

TEST(ChamberGeometry, ShippedChamberHasPositiveRestGaps) {
  const auto p = test_mbd::shipped_mechanism();
  const auto& g = p.chamber;
  for (std::size_t i = 0; i < g.mantle.size(); ++i) {
    const double gap = core::signed_distance_inside(g.concave, {g.mantle.z[i], g.mantle.r[i]}, nullptr);
    EXPECT_GT(gap, 0.015);
    EXPECT_LT(gap, 0.1);
  }
}

TEST(ChamberGeometry, LinerPosesStartAtTheSphereCentre) {
  const auto p = test_mbd::shipped_mechanism();
  mbd::Mechanism m(p);
  EXPECT_LT(m.liner_pose(mbd::BodyId::FloatingCone).translation().norm(), 1e-12);
  EXPECT_LT(m.liner_pose(mbd::BodyId::FixedCone).translation().norm(), 1e-12);
  EXPECT_THROW(m.liner_pose(mbd::BodyId::Vibrator), std::invalid_argument);
  m.advance(3.0);
  // The mantle frame stays on the spherical joint O1 (its origin is the O1 point of both cones).
  const auto a = m.liner_pose(mbd::BodyId::FloatingCone), b = m.liner_pose(mbd::BodyId::FixedCone);
  EXPECT_LT((a.translation() - b.translation()).norm(), 1e-4);
  // ... and its axis is tilted by the nutation angle against the concave's.
  const double ang = std::acos(std::min(1.0, a.linear().col(2).dot(b.linear().col(2))));
  EXPECT_NEAR(ang, m.nutation_angle(), 1e-9);
  EXPECT_GT(ang, 0.1 * M_PI / 180);
}

TEST(ParticleWrench, StaticForceOnTheConcaveDisplacesTheFrameByForceOverStiffness) {
  const auto p = test_mbd::shipped_mechanism();
  auto mean_x = [&](bool loaded, double* ext_work) {
    mbd::Mechanism m(p, mbd::LoadModel::Bed);
    if (loaded) m.set_particle_wrench(mbd::BodyId::FixedCone, {2e4, 0, 0}, {0, 0, 0});
    m.advance(6.0);  // absorber transient (0.5 Hz, damping ratio 0.5) dies out
    double s = 0;
    const long n = std::lround(3.0 / p.dt_s);  // 20 whole cycles at 400 rpm
    for (long i = 0; i < n; ++i) {
      m.step();
      s += m.body(mbd::BodyId::FixedCone).position.x();
    }
    *ext_work = m.energy().external_work;
    return s / n;
  };
  double w0 = 0, w1 = 0;
  const double x0 = mean_x(false, &w0), x1 = mean_x(true, &w1);
  // 20 kN on 320 N/mm absorbers: 62.5 mm static shift of the frame.
  EXPECT_NEAR(x1 - x0, 2e4 / p.absorber_k_N_per_m.x(), 0.03 * 2e4 / p.absorber_k_N_per_m.x());
  EXPECT_EQ(w0, 0.0);
  EXPECT_NEAR(w1, 2e4 * (x1 - x0), 0.2 * 2e4 * (x1 - x0));  // work of the held force ~ F x shift
}

}  // namespace
