// Particle-triangle contact: faces, edges, vertices, no double counting, wrench balance, regions.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dem/mesh_contact.hpp"
#include "dem/revolution.hpp"

namespace {

using dem::MeshContact;
using dem::TriMesh;
using Eigen::Vector3d;

constexpr int kRock = 0, kSteel = 1;

// Hertz normal force of a sphere on a rigid wall at rest, Eq. 16 with r* = r: 4/3 E* sqrt(r) d^1.5.
double hertz_plane(double E_star, double r, double delta) {
  return 4.0 / 3.0 * E_star * std::sqrt(r) * std::pow(delta, 1.5);
}

dem::Particles one_sphere(const Vector3d& x, double r, const Vector3d& v = Vector3d::Zero(),
                          const Vector3d& w = Vector3d::Zero()) {
  dem::Particles p;
  p.add(x.x(), x.y(), x.z(), r, 2600.0, kRock, v.x(), v.y(), v.z(), w.x(), w.y(), w.z());
  return p;
}

// Unit square in z = 0 split along the diagonal (0,0)-(1,1), normals +z.
TriMesh square() {
  return TriMesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 2, 3}}, "square");
}

Vector3d force_of(const dem::Particles& p) { return {p.fx[0], p.fy[0], p.fz[0]}; }

TEST(MeshContact, FaceContactEqualsHertzPlaneAtRest) {
  const auto mats = dem::default_table4();
  MeshContact mc(square(), mats, kSteel);
  const double r = 0.01, delta = 1e-4;
  auto p = one_sphere({0.7, 0.2, r - delta}, r);
  mc.add_forces(p, 0.0, 1e-6);
  ASSERT_EQ(mc.contacts().size(), 1u);
  EXPECT_EQ(mc.contacts()[0].feature, dem::TriFeature::Face);
  const double E = mats.pair(kRock, kSteel).E_star;
  const double F = hertz_plane(E, r, delta);
  EXPECT_NEAR(p.fz[0], F, 1e-12 * F);
  EXPECT_NEAR(p.fx[0], 0.0, 1e-12 * F);
  EXPECT_NEAR(p.fy[0], 0.0, 1e-12 * F);
  // A wrong radius in the law (e.g. r* = r/2 as for two equal spheres) would be off by 29 %.
  EXPECT_GT(F, 1.0);
}

TEST(MeshContact, FaceContactWithApproachVelocityHasEq16Damping) {
  const auto mats = dem::default_table4();
  MeshContact mc(square(), mats, kSteel);
  const double r = 0.01, delta = 2e-5, vn = -0.5;
  auto p = one_sphere({0.3, 0.6, r - delta}, r, {0, 0, vn});
  mc.add_forces(p, 0.0, 1e-6);
  const auto& pp = mats.pair(kRock, kSteel);
  const double kn = 2.0 * pp.E_star * std::sqrt(r * delta);
  const double expected = hertz_plane(pp.E_star, r, delta) -
                          2.0 * std::sqrt(5.0 / 6.0) * pp.beta * std::sqrt(p.m[0] * kn) * vn;
  EXPECT_NEAR(p.fz[0], expected, 1e-10 * expected);
  EXPECT_GT(p.fz[0], hertz_plane(pp.E_star, r, delta) * 1.01);  // damping is really there
}

// The wall's own motion enters the relative velocity: v + w x (q - origin) at the contact point q.
TEST(MeshContact, RotatingWallVelocityAtTheContactPoint) {
  const auto mats = dem::default_table4();
  const auto& pp = mats.pair(kRock, kSteel);
  const double r = 0.01, delta = 2e-5, omega = 3.0, x = 0.6;
  MeshContact mc(square(), mats, kSteel);
  dem::Pose pose;
  pose.position = Vector3d(0.2, 0, 0);  // rotation axis through (0.2, 0, 0) along -y
  pose.orientation.setIdentity();
  mc.set_pose(pose);
  dem::Twist tw;
  tw.angular = Vector3d(0, -omega, 0);  // the point at x lifts at omega (x - 0.2)
  tw.linear = Vector3d(0, 0, 0.1);      // plus a uniform lift
  mc.set_twist(tw);
  auto p = one_sphere({0.2 + x, 0.5, r - delta}, r);  // body-frame x = 0.6, above the square
  mc.add_forces(p, 0.0, 1e-6);
  ASSERT_EQ(mc.contacts().size(), 1u);
  const double vn = -(0.1 + omega * x);  // sphere at rest, wall approaching
  const double kn = 2.0 * pp.E_star * std::sqrt(r * delta);
  const double expected = hertz_plane(pp.E_star, r, delta) -
                          2.0 * std::sqrt(5.0 / 6.0) * pp.beta * std::sqrt(p.m[0] * kn) * vn;
  EXPECT_NEAR(p.fz[0], expected, 1e-10 * expected);
  // Rolling friction acts on the spin relative to the wall: a sphere turning with the wall feels none.
  EXPECT_NEAR(p.tx[0], 0.0, 1e-12);
  auto q = one_sphere({0.2 + x, 0.5, r - delta}, r, Vector3d::Zero(), tw.angular);
  MeshContact mc2(square(), mats, kSteel);
  mc2.set_pose(pose);
  mc2.set_twist(tw);
  mc2.add_forces(q, 0.0, 1e-6);
  EXPECT_GT(std::fabs(p.ty[0]), 0.0);  // the still sphere spins relative to the wall: rolling torque
  EXPECT_NEAR(mc2.contacts()[0].roll_torque.norm(), 0.0, 1e-15);
}

// A sphere resting on the 2-triangle square gets exactly the plane force anywhere over it: inside
// either face, on the shared diagonal, at the shared and unshared corners, on the boundary edges.
TEST(MeshContact, FlatTwoTriangleSquareNoDoubleCounting) {
  const auto mats = dem::default_table4();
  const double r = 0.02, delta = 3e-5;
  const double F = hertz_plane(mats.pair(kRock, kSteel).E_star, r, delta);
  std::vector<Vector3d> spots = {{0.5, 0.5, 0},   {0.25, 0.25, 0}, {0.7, 0.7, 0}, {0, 0, 0},
                                 {1, 1, 0},       {1, 0, 0},       {0, 1, 0},     {0.5, 0, 0},
                                 {1, 0.3, 0},     {0.6, 0.2, 0},   {0.2, 0.6, 0}};
  // points a hair off the diagonal on both sides
  for (double e : {1e-15, -1e-15, 1e-12, -1e-12, 1e-9, -1e-9}) spots.push_back({0.4 + e, 0.4 - e, 0});
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 200; ++k) spots.push_back({u(rng), u(rng), 0});
  for (const auto& s : spots) {
    MeshContact mc(square(), mats, kSteel);
    auto p = one_sphere({s.x(), s.y(), r - delta}, r);
    mc.add_forces(p, 0.0, 1e-6);
    ASSERT_EQ(mc.contacts().size(), 1u) << "at " << s.transpose();
    EXPECT_NEAR(p.fz[0], F, 1e-9 * F) << "at " << s.transpose();
    EXPECT_NEAR(std::hypot(p.fx[0], p.fy[0]), 0.0, 1e-9 * F) << "at " << s.transpose();
  }
}

// Same on a fan: a flat disk revolved from its centre (12 triangles meet at the centre vertex).
TEST(MeshContact, FlatFanNoDoubleCounting) {
  const auto mats = dem::default_table4();
  auto disk = dem::revolve_profile({{0.0, 0.0}, {0.0, 0.5}, {0.0, 1.0}}, 12, dem::NormalSide::Inward);
  // Inward for a profile listed outward along r at constant z gives normal +z ((dz, -dr) = (0, -dr) -> -z, flipped).
  ASSERT_GT(disk.normal(0).z(), 0.99);
  const double r = 0.03, delta = 1e-4;
  const double F = hertz_plane(mats.pair(kRock, kSteel).E_star, r, delta);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  std::vector<Vector3d> spots = {{0, 0, 0}, {0.5, 0, 0}, {1e-14, 0, 0}, {0.25, 0.0, 0}};
  for (int k = 0; k < 300; ++k) spots.push_back({u(rng), u(rng), 0});
  MeshContact mc(disk, mats, kSteel);
  for (const auto& s : spots) {
    auto p = one_sphere({s.x(), s.y(), r - delta}, r);
    mc.add_forces(p, 0.0, 1e-6);
    ASSERT_EQ(mc.contacts().size(), 1u) << "at " << s.transpose();
    EXPECT_NEAR(p.fz[0], F, 1e-9 * F) << "at " << s.transpose();
  }
}

TEST(MeshContact, EdgeAndVertexContactsOfASingleTriangle) {
  const auto mats = dem::default_table4();
  const double E = mats.pair(kRock, kSteel).E_star;
  TriMesh tri({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}, "tri");
  const double r = 0.05;
  {  // beside edge (0,0)-(1,0): centre at y = -s, height h
    MeshContact mc(tri, mats, kSteel);
    const double s = 0.03, h = 0.035, d = std::hypot(s, h);
    auto p = one_sphere({0.4, -s, h}, r);
    mc.add_forces(p, 0.0, 1e-6);
    ASSERT_EQ(mc.contacts().size(), 1u);
    EXPECT_EQ(mc.contacts()[0].feature, dem::TriFeature::Edge);
    const double F = hertz_plane(E, r, r - d);
    const Vector3d n(0, -s / d, h / d);
    EXPECT_NEAR((force_of(p) - F * n).norm(), 0.0, 1e-10 * F);
    EXPECT_NEAR((mc.contacts()[0].point - Vector3d(0.4, 0, 0)).norm(), 0.0, 1e-14);
  }
  {  // beyond vertex (1,0,0)
    MeshContact mc(tri, mats, kSteel);
    const Vector3d c(1.02, -0.01, 0.03);
    const double d = (c - Vector3d(1, 0, 0)).norm();
    auto p = one_sphere(c, r);
    mc.add_forces(p, 0.0, 1e-6);
    ASSERT_EQ(mc.contacts().size(), 1u);
    EXPECT_EQ(mc.contacts()[0].feature, dem::TriFeature::Vertex);
    const double F = hertz_plane(E, r, r - d);
    EXPECT_NEAR((force_of(p) - F * (c - Vector3d(1, 0, 0)) / d).norm(), 0.0, 1e-10 * F);
  }
  {  // out of reach
    MeshContact mc(tri, mats, kSteel);
    auto p = one_sphere({1.04, -0.04, 0.0}, r);  // d = 0.0566 > r
    mc.add_forces(p, 0.0, 1e-6);
    EXPECT_EQ(mc.contacts().size(), 0u);
    EXPECT_EQ(p.fx[0], 0.0);
  }
}

// A roof (convex ridge) and a valley (concave corner) made of two 2-triangle faces each.
TEST(MeshContact, ConvexRidgeOneContactConcaveValleyTwo) {
  const auto mats = dem::default_table4();
  const double E = mats.pair(kRock, kSteel).E_star;
  const double a = 0.3;  // slope angle of each face
  const double c = std::cos(a), s = std::sin(a);
  // Ridge along y at x = 0, z = 0; faces slope down to x = -1 and x = +1.
  auto roof = [&](double sign) {
    std::vector<Vector3d> v = {{-c, 0, -sign * s}, {0, 0, 0}, {c, 0, -sign * s},
                               {-c, 1, -sign * s}, {0, 1, 0}, {c, 1, -sign * s}};
    std::vector<dem::Triangle> t = {{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}};
    return TriMesh(v, t, sign > 0 ? "roof" : "valley");
  };
  const double r = 0.05;
  {  // directly above the ridge: one edge contact at the ridge, force straight up
    MeshContact mc(roof(+1), mats, kSteel);
    auto p = one_sphere({0, 0.5, 0.049}, r);
    mc.add_forces(p, 0.0, 1e-6);
    ASSERT_EQ(mc.contacts().size(), 1u);
    const double F = hertz_plane(E, r, 0.001);
    EXPECT_NEAR((force_of(p) - Vector3d(0, 0, F)).norm(), 0.0, 1e-9 * F);
  }
  {  // slightly to the side but still in the ridge's Voronoi wedge: one contact
    MeshContact mc(roof(+1), mats, kSteel);
    const Vector3d ctr(0.01, 0.5, 0.045);  // wedge half-angle a: |x|/z < tan(a) = 0.31
    auto p = one_sphere(ctr, r);
    mc.add_forces(p, 0.0, 1e-6);
    ASSERT_EQ(mc.contacts().size(), 1u);
    const double d = std::hypot(0.01, 0.045);
    const double F = hertz_plane(E, r, r - d);
    EXPECT_NEAR((force_of(p) - F * Vector3d(0.01, 0, 0.045) / d).norm(), 0.0, 1e-9 * F);
  }
  {  // on one slope, touching it only: one face contact (the ridge edge contact is dropped)
    MeshContact mc(roof(+1), mats, kSteel);
    const Vector3d foot(0.02 * c, 0.5, -0.02 * s), n(s, 0, c);
    auto p = one_sphere(foot + (r - 1e-4) * n, r);
    mc.add_forces(p, 0.0, 1e-6);
    ASSERT_EQ(mc.contacts().size(), 1u);
    EXPECT_EQ(mc.contacts()[0].feature, dem::TriFeature::Face);
    const double F = hertz_plane(E, r, 1e-4);
    EXPECT_NEAR((force_of(p) - F * n).norm(), 0.0, 1e-9 * F);
  }
  {  // in the valley: one contact per face, horizontal parts cancel
    MeshContact mc(roof(-1), mats, kSteel);
    const double h = (r - 1e-4) / c;  // centre height above the valley line giving overlap 1e-4 on both faces
    auto p = one_sphere({0, 0.5, h}, r);
    mc.add_forces(p, 0.0, 1e-6);
    ASSERT_EQ(mc.contacts().size(), 2u);
    const double F = hertz_plane(E, r, 1e-4);
    EXPECT_NEAR(p.fz[0], 2.0 * F * c, 1e-9 * F);
    EXPECT_NEAR(p.fx[0], 0.0, 1e-9 * F);
  }
}

// Many particles against a moving, rotated cone: the mesh wrench is minus the sum of the particle
// reactions, for force and for torque about an arbitrary point; same results with 1 and N threads.
TEST(MeshContact, WrenchEqualsMinusSumOfParticleReactions) {
  const auto mats = dem::default_table4();
  auto cone = dem::revolve_profile({{0.0, 0.6}, {0.4, 0.3}}, 48, dem::NormalSide::Outward, 0.0, "mantle");
  MeshContact mc(cone, mats, kSteel);
  dem::Pose pose;
  pose.position = Vector3d(0.1, -0.2, 0.3);
  pose.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.05, Vector3d(1, 2, 0).normalized()));
  dem::Twist tw;
  tw.linear = Vector3d(0.1, 0.0, -0.2);
  tw.angular = Vector3d(0.3, -0.1, 2.0);
  mc.set_pose(pose);
  mc.set_twist(tw);
  dem::Particles p;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const TriMesh& m = mc.mesh();
  for (int k = 0; k < 400; ++k) {
    // a random point of a random triangle, the centre offset along its normal
    const int t = static_cast<int>(u(rng) * m.num_triangles()) % static_cast<int>(m.num_triangles());
    double b1 = u(rng), b2 = u(rng);
    if (b1 + b2 > 1) { b1 = 1 - b1; b2 = 1 - b2; }
    const auto& tr = m.triangle(t);
    const Vector3d s = m.vertex(tr[0]) + b1 * (m.vertex(tr[1]) - m.vertex(tr[0])) +
                       b2 * (m.vertex(tr[2]) - m.vertex(tr[0]));
    const double rad = 0.005 + 0.01 * u(rng);
    const double off = rad - 2e-4 * u(rng) + (k % 5 == 0 ? 0.01 : 0.0);  // some not touching
    const Vector3d xw = m.to_world(s + off * m.normal(t));
    p.add(xw.x(), xw.y(), xw.z(), rad, 2600.0, kRock, u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5,
          10 * (u(rng) - 0.5), 10 * (u(rng) - 0.5), 10 * (u(rng) - 0.5));
  }
  mc.add_forces(p, 0.0, 1e-6);
  mc.add_forces(p, 1e-6, 1e-6);  // second step: tangential springs are loaded
  ASSERT_GT(mc.contacts().size(), 250u);
  p.clear_forces();
  mc.add_forces(p, 2e-6, 1e-6);
  const Vector3d P(0.05, 0.02, 0.5);
  Vector3d F = Vector3d::Zero(), T = Vector3d::Zero();
  for (size_t i = 0; i < p.size(); ++i) {
    const Vector3d f(p.fx[i], p.fy[i], p.fz[i]);
    F += f;
    T += (Vector3d(p.x[i], p.y[i], p.z[i]) - P).cross(f) + Vector3d(p.tx[i], p.ty[i], p.tz[i]);
  }
  const auto w = mc.wrench_about(P);
  const double scale = F.norm() + 1.0;
  EXPECT_GT(F.norm(), 10.0);
  EXPECT_NEAR((w.force + F).norm(), 0.0, 1e-10 * scale);
  EXPECT_NEAR((w.torque + T).norm(), 0.0, 1e-10 * (T.norm() + 1.0));
  // friction really acts (tangential forces present)
  double ft = 0.0;
  for (const auto& c : mc.contacts()) ft += (c.force - c.force.dot(c.normal) * c.normal).norm();
  EXPECT_GT(ft, 0.01 * mc.total_normal_force());

  // Deterministic across thread counts: bit-identical forces with 1 thread.
  MeshContact a(cone, mats, kSteel), b(cone, mats, kSteel);
  for (auto* m : {&a, &b}) { m->set_pose(pose); m->set_twist(tw); }
  a.set_threads(1);
  b.set_threads(3);
  dem::Particles pa = p, pb = p;
  pa.clear_forces(); pb.clear_forces();
  for (int s = 0; s < 3; ++s) a.add_forces(pa, s * 1e-6, 1e-6);
  for (int s = 0; s < 3; ++s) b.add_forces(pb, s * 1e-6, 1e-6);
  for (size_t i = 0; i < p.size(); ++i) {
    ASSERT_EQ(pa.fx[i], pb.fx[i]);
    ASSERT_EQ(pa.tz[i], pb.tz[i]);
  }
  EXPECT_EQ(a.wrench_about(P).torque, b.wrench_about(P).torque);
}

// The tangential spring follows a particle sliding across the shared edge of two coplanar triangles.
TEST(MeshContact, TangentialHistorySurvivesCrossingASharedEdge) {
  const auto mats = dem::default_table4();
  MeshContact mc(square(), mats, kSteel);
  const double r = 0.01, delta = 1e-5;
  // Sticking: tiny tangential velocity across the diagonal x = y (from triangle 1 into triangle 0).
  auto p = one_sphere({0.5 - 2e-7, 0.5 + 2e-7, r - delta}, r, {1e-3, -1e-3, 0});
  const double dt = 1e-6;
  double last_ft = 0.0;
  int tri_before = -1, tri_after = -1;
  for (int s = 0; s < 400; ++s) {
    p.clear_forces();
    mc.add_forces(p, s * dt, dt);
    ASSERT_EQ(mc.contacts().size(), 1u);
    const double ft = std::hypot(p.fx[0], p.fy[0]);
    if (s == 0) tri_before = mc.contacts()[0].triangle;
    tri_after = mc.contacts()[0].triangle;
    if (s > 0) {
      EXPECT_GE(ft, last_ft * 0.999) << "spring lost at step " << s;
    }
    last_ft = ft;
    p.x[0] += p.vx[0] * dt;  // kinematic sliding, velocity kept constant
    p.y[0] += p.vy[0] * dt;
  }
  EXPECT_NE(tri_before, tri_after);  // it did cross
  // Eq. 18 with the spring grown over all 400 steps: F_t = k_t (400 v dt) + c_t v.
  const auto& pp = mats.pair(kRock, kSteel);
  const double v = std::sqrt(2.0) * 1e-3, kt = 8.0 * pp.G_star * std::sqrt(r * delta);
  const double ct = 2.0 * std::sqrt(5.0 / 6.0) * pp.beta * std::sqrt(p.m[0] * kt);
  EXPECT_NEAR(last_ft, kt * 400 * v * dt + ct * v, 1e-6 * last_ft);
}

TEST(MeshContact, BadInputsAreRejected) {
  const auto mats = dem::default_table4();
  EXPECT_THROW(MeshContact(square(), mats, 7), std::invalid_argument);
  MeshContact mc(square(), mats, kSteel);
  EXPECT_THROW(mc.set_regions(dem::RegionMap({0}, {"a"})), std::invalid_argument);
  dem::Particles p;
  p.add(0.5, 0.5, 0.005, 0.01, 2600.0, 5);  // material 5 does not exist
  EXPECT_THROW(mc.add_forces(p, 0.0, 1e-6), std::invalid_argument);
}

}  // namespace
