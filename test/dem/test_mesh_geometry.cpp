// Meshes: surfaces of revolution vs closed forms, STL round trips, region maps, pose and velocity.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>

#include "dem/mesh_contact.hpp"
#include "dem/mesh_geometry.hpp"
#include "dem/mesh_liners.hpp"
#include "dem/region_map.hpp"
#include "dem/revolution.hpp"
#include "dem/stl.hpp"

namespace {

using dem::NormalSide;
using dem::TriMesh;
using Eigen::Vector3d;
constexpr double kPi = 3.14159265358979323846;

// Closed frustum: bottom disk r1 at z = 0, top disk r2 at z = h.
TriMesh frustum(double r1, double r2, double h, int n, NormalSide side) {
  return dem::revolve_profile({{0, 0}, {0, r1}, {h, r2}, {h, 0}}, n, side, 0.0, "frustum");
}

TEST(Revolution, FrustumVolumeAndAreaMatchClosedForms) {
  const double r1 = 0.6, r2 = 0.35, h = 0.5;
  for (int n : {9, 72, 360}) {
    const TriMesh m = frustum(r1, r2, h, n, NormalSide::Outward);
    // Exact values of the tessellation: cross-sections are regular n-gons inscribed in the circles.
    const double f = n * std::sin(2 * kPi / n) / (2 * kPi);  // polygon / circle area
    const double v_cont = kPi * h / 3 * (r1 * r1 + r1 * r2 + r2 * r2);
    const double lat_poly = n * (r1 + r2) * std::sin(kPi / n) *
                            std::sqrt(h * h + std::pow((r2 - r1) * std::cos(kPi / n), 2));
    const double a_poly = lat_poly + f * kPi * (r1 * r1 + r2 * r2);
    EXPECT_NEAR(m.signed_volume(), f * v_cont, 1e-12 * v_cont) << n;
    EXPECT_NEAR(m.area(), a_poly, 1e-12 * a_poly) << n;
    // Against the smooth frustum: stated tessellation error (2 pi / n)^2 / 6 (leading term of 1 - f).
    const double tol = std::pow(2 * kPi / n, 2) / 6 * 1.01;
    const double a_cont = kPi * (r1 + r2) * std::hypot(h, r1 - r2) + kPi * (r1 * r1 + r2 * r2);
    EXPECT_LT(std::fabs(m.signed_volume() / v_cont - 1), tol) << n;
    EXPECT_LT(std::fabs(m.area() / a_cont - 1), tol) << n;
    EXPECT_EQ(m.num_triangles(), static_cast<size_t>(4 * n));  // 2 fans + 1 band of quads
    // Closed and manifold: every edge has two triangles.
    for (const auto& e : m.edges()) ASSERT_GE(e.tri1, 0);
  }
  EXPECT_NEAR(frustum(r1, r2, h, 72, NormalSide::Inward).signed_volume(),
              -frustum(r1, r2, h, 72, NormalSide::Outward).signed_volume(), 1e-15);
}

TEST(Revolution, NormalSidesOfMantleAndConcave) {
  const std::vector<dem::ProfilePoint> prof = {{0.0, 0.7}, {0.3, 0.55}, {0.6, 0.4}};
  const TriMesh mantle = dem::revolve_profile(prof, 36, NormalSide::Outward);
  const TriMesh concave = dem::revolve_profile(prof, 36, NormalSide::Inward);
  for (size_t t = 0; t < mantle.num_triangles(); ++t) {
    const Vector3d c = mantle.centroid(static_cast<int>(t));
    const Vector3d radial = Vector3d(c.x(), c.y(), 0).normalized();
    ASSERT_GT(mantle.normal(static_cast<int>(t)).dot(radial), 0.8);
    ASSERT_LT(concave.normal(static_cast<int>(t)).dot(radial), -0.8);
  }
  // Open surface: boundary edges at the two rims only.
  int boundary = 0;
  for (const auto& e : mantle.edges()) boundary += e.tri1 < 0;
  EXPECT_EQ(boundary, 72);
}

TEST(Revolution, ProfileOrderDoesNotChangeTheSide) {
  const std::vector<dem::ProfilePoint> up = {{0.0, 0.7}, {0.3, 0.55}, {0.6, 0.4}};
  const std::vector<dem::ProfilePoint> down(up.rbegin(), up.rend());
  for (auto side : {NormalSide::Outward, NormalSide::Inward}) {
    const TriMesh a = dem::revolve_profile(up, 24, side), b = dem::revolve_profile(down, 24, side);
    const double sign = side == NormalSide::Outward ? 1.0 : -1.0;
    for (const TriMesh* m : {&a, &b})
      for (size_t t = 0; t < m->num_triangles(); ++t) {
        const Vector3d c = m->centroid(static_cast<int>(t));
        ASSERT_GT(sign * m->normal(static_cast<int>(t)).dot(Vector3d(c.x(), c.y(), 0).normalized()), 0.8);
      }
  }
}

// The concave from a core::Profile (the chamber geometry shared with the MBD), refined at the 14 ring
// boundaries: every triangle lies inside one ring band, so the 13 x 9 map has no straddling triangles.
TEST(Revolution, RefinedConcaveAlignsWithRings) {
  core::Profile prof;
  prof.z = {0.62, 0.35, 0.05};  // top to bottom, as a config may list it
  prof.r = {0.72, 0.58, 0.50};
  std::vector<double> cuts;
  for (int k = 0; k <= 13; ++k) cuts.push_back(0.05 + (0.62 - 0.05) * k / 13);
  const auto pts = dem::refine_profile(dem::profile_points(prof), 0.02, cuts);
  for (size_t i = 0; i + 1 < pts.size(); ++i) {
    ASSERT_LE(std::hypot(pts[i + 1].z - pts[i].z, pts[i + 1].r - pts[i].r), 0.02 + 1e-12);
    ASSERT_LT(pts[i + 1].z, pts[i].z);  // order kept
    // on the original polyline
    ASSERT_NEAR(pts[i].r, prof.radius_at(pts[i].z), 1e-12);
  }
  for (double zc : cuts) {
    bool found = false;
    for (const auto& p : pts) found |= std::fabs(p.z - zc) < 1e-12;
    EXPECT_TRUE(found) << zc;
  }
  const TriMesh concave = dem::revolve_profile(pts, 72, NormalSide::Inward, 0.0, "concave");
  const auto map = dem::RegionMap::rings_sectors(concave, 13, 9);
  const double band = (0.62 - 0.05) / 13;
  for (size_t t = 0; t < concave.num_triangles(); ++t) {
    const int reg = map.region_of(static_cast<int>(t));
    const int ring = reg / 9 + 1;
    for (int v : concave.triangle(static_cast<int>(t))) {
      ASSERT_LE(concave.vertex(v).z(), 0.62 - (ring - 1) * band + 1e-12);
      ASSERT_GE(concave.vertex(v).z(), 0.62 - ring * band - 1e-12);
    }
  }
  EXPECT_THROW(dem::refine_profile({{0, 1}}, 0.1), std::invalid_argument);
}

TEST(Revolution, BadProfilesAreRejected) {
  EXPECT_THROW(dem::revolve_profile({{0, 1}}, 12, NormalSide::Outward), std::invalid_argument);
  EXPECT_THROW(dem::revolve_profile({{0, 1}, {1, 1}}, 2, NormalSide::Outward), std::invalid_argument);
  EXPECT_THROW(dem::revolve_profile({{0, 1}, {1, -1}}, 12, NormalSide::Outward), std::invalid_argument);
  EXPECT_THROW(dem::revolve_profile({{0, 1}, {0.5, 0}, {1, 1}}, 12, NormalSide::Outward),
               std::invalid_argument);
  EXPECT_THROW(dem::revolve_profile({{0, 1}, {0, 1}}, 12, NormalSide::Outward), std::invalid_argument);
}

TEST(ClosestPoint, FeaturesOfATriangle) {
  const Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  auto cp = dem::closest_point_on_triangle({0.2, 0.2, 0.5}, a, b, c);
  EXPECT_EQ(cp.feature, dem::TriFeature::Face);
  EXPECT_NEAR((cp.point - Vector3d(0.2, 0.2, 0)).norm(), 0, 1e-15);
  cp = dem::closest_point_on_triangle({0.7, 0.7, 0.1}, a, b, c);
  EXPECT_EQ(cp.feature, dem::TriFeature::Edge);
  EXPECT_EQ(cp.index, 1);
  EXPECT_NEAR((cp.point - Vector3d(0.5, 0.5, 0)).norm(), 0, 1e-15);
  cp = dem::closest_point_on_triangle({-0.3, 0.4, 0.0}, a, b, c);
  EXPECT_EQ(cp.feature, dem::TriFeature::Edge);
  EXPECT_EQ(cp.index, 2);
  cp = dem::closest_point_on_triangle({-1, -1, 2}, a, b, c);
  EXPECT_EQ(cp.feature, dem::TriFeature::Vertex);
  EXPECT_EQ(cp.index, 0);
  cp = dem::closest_point_on_triangle({2, -0.5, 0}, a, b, c);
  EXPECT_EQ(cp.feature, dem::TriFeature::Vertex);
  EXPECT_EQ(cp.index, 1);
}

TEST(Stl, BinaryAndAsciiRoundTrip) {
  const TriMesh m = frustum(0.6, 0.35, 0.5, 40, NormalSide::Outward);
  for (auto fmt : {dem::StlFormat::Binary, dem::StlFormat::Ascii}) {
    const std::string path = ::testing::TempDir() + "/rt_" + std::to_string(static_cast<int>(fmt)) + ".stl";
    dem::save_stl(m, path, fmt, 1e-3);  // written in mm
    const TriMesh back = dem::load_stl(path, 1e-3);
    ASSERT_EQ(back.num_triangles(), m.num_triangles());
    ASSERT_EQ(back.num_vertices(), m.num_vertices());  // welded back to the same topology
    EXPECT_EQ(back.edges().size(), m.edges().size());
    const double tol = fmt == dem::StlFormat::Binary ? 1e-7 : 1e-15;  // float vs 17 digits
    for (size_t t = 0; t < m.num_triangles(); ++t)
      for (int k = 0; k < 3; ++k)
        ASSERT_NEAR((back.vertex(back.triangle(t)[k]) - m.vertex(m.triangle(t)[k])).norm(), 0.0, tol);
    EXPECT_NEAR(back.signed_volume(), m.signed_volume(), 1e-6 * m.signed_volume());
    std::remove(path.c_str());
  }
}

TEST(Stl, FixtureInMillimetres) {
  // test/fixtures/tetra_mm.stl: ASCII, the tetrahedron (0,0,0), (30,0,0), (0,30,0), (0,0,30) mm.
  const TriMesh m = dem::load_stl(std::string(CRUSHER_SOURCE_DIR) + "/test/fixtures/tetra_mm.stl", 1e-3);
  EXPECT_EQ(m.num_triangles(), 4u);
  EXPECT_EQ(m.num_vertices(), 4u);
  EXPECT_NEAR(m.signed_volume(), std::pow(0.03, 3) / 6, 1e-15);  // outward normals
  const double a = 0.03 * 0.03;
  EXPECT_NEAR(m.area(), 1.5 * a + std::sqrt(3.0) / 2 * a, 1e-15);
}

TEST(Stl, BadFilesAreRejected) {
  EXPECT_THROW(dem::load_stl("/nonexistent/x.stl"), std::invalid_argument);
  const std::string path = ::testing::TempDir() + "/bad.stl";
  {  // binary header announcing 10 triangles, holding 1
    std::ofstream f(path, std::ios::binary);
    char header[80] = {0};
    f.write(header, 80);
    uint32_t n = 10;
    f.write(reinterpret_cast<const char*>(&n), 4);
    char tri[50] = {0};
    f.write(tri, 50);
  }
  try {
    dem::load_stl(path);
    FAIL() << "truncated STL accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  }
  {
    std::ofstream f(path);
    f << "solid x\nfacet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 0 0\n endloop\nendfacet\nendsolid\n";
  }
  EXPECT_THROW(dem::load_stl(path), std::invalid_argument);
  std::remove(path.c_str());
}

TEST(Mesh, PoseCacheAndSurfaceVelocity) {
  TriMesh m = frustum(0.6, 0.35, 0.5, 12, NormalSide::Outward);
  dem::Pose pose;
  pose.position = Vector3d(1, 2, 3);
  pose.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Vector3d::UnitZ()));
  m.set_pose(pose);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vector3d::UnitZ()).toRotationMatrix();
  for (size_t v = 0; v < m.num_vertices(); ++v)
    ASSERT_NEAR((m.world_vertices()[v] - (R * m.vertex(v) + pose.position)).norm(), 0, 1e-14);
  EXPECT_NEAR((m.to_body(m.to_world(Vector3d(0.1, 0.2, 0.3))) - Vector3d(0.1, 0.2, 0.3)).norm(), 0, 1e-15);
  dem::Twist tw;
  tw.linear = Vector3d(0.5, 0, 0);
  tw.angular = Vector3d(0, 0, 2);
  m.set_twist(tw);
  // v + w x (p - origin): at 1 m along +y from the origin, w z-axis 2 rad/s gives -2 m/s along x.
  EXPECT_NEAR((m.velocity_at(Vector3d(1, 3, 3)) - Vector3d(0.5 - 2.0, 0, 0)).norm(), 0, 1e-15);
  EXPECT_THROW(TriMesh({{0, 0, 0}, {1, 0, 0}}, {{0, 1, 2}}), std::invalid_argument);
  EXPECT_THROW(TriMesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {{0, 1, 2}}), std::invalid_argument);
}

// The concave: 13 rings x 9 sectors (section 4.2.3), ring 1 at the top, sector 1 from +x.
TEST(RegionMap, ConcaveThirteenRingsNineSectors) {
  std::vector<dem::ProfilePoint> prof;
  const double z0 = 0.0, z1 = 0.65;
  for (int i = 0; i <= 26; ++i) {  // two profile segments per ring
    const double z = z0 + (z1 - z0) * i / 26;
    prof.push_back({z, 0.45 + 0.4 * z});
  }
  const TriMesh concave = dem::revolve_profile(prof, 72, NormalSide::Inward, 0.0, "concave");
  const auto map = dem::RegionMap::rings_sectors(concave, 13, 9);
  ASSERT_EQ(map.num_regions(), 117);
  EXPECT_EQ(map.name(map.ring_sector(3, 1)), "P_{3,1}");
  EXPECT_EQ(map.ring_sector(11, 1), 90);
  std::vector<int> count(117, 0);
  for (size_t t = 0; t < concave.num_triangles(); ++t) {
    const int reg = map.region_of(static_cast<int>(t));
    ASSERT_GE(reg, 0);
    ++count[reg];
    const Vector3d c = concave.centroid(static_cast<int>(t));
    const int ring = static_cast<int>((z1 - c.z()) / (z1 - z0) * 13) + 1;
    double phi = std::atan2(c.y(), c.x());
    if (phi < 0) phi += 2 * kPi;
    const int sector = static_cast<int>(phi / (2 * kPi / 9)) + 1;
    ASSERT_EQ(reg, map.ring_sector(ring, sector));
  }
  for (int c : count) EXPECT_EQ(c, 2 * 2 * 8);  // 2 segments x 8 sectors x 2 triangles
  // Areas: equal within a ring, growing downwards? (radius shrinks downwards here: 0.45 at z = 0).
  const auto areas = map.region_areas(concave);
  double total = 0;
  for (double a : areas) total += a;
  EXPECT_NEAR(total, concave.area(), 1e-12);
  EXPECT_NEAR(areas[map.ring_sector(5, 2)], areas[map.ring_sector(5, 7)], 1e-12);

  // Particles pressed on the concave's inner face: per-region normal forces sum to the total, and
  // a particle in P_{3,1} loads exactly that region.
  const auto mats = dem::default_table4();
  dem::MeshContact mc(concave, mats, 1);
  mc.set_regions(map);
  dem::Particles p;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double rad = 0.01;
  auto place = [&](double z, double phi) {
    const double rs = 0.45 + 0.4 * z;
    const Vector3d n_in = Vector3d(-std::cos(phi), -std::sin(phi), 0.4).normalized();  // inward normal
    const Vector3d s(rs * std::cos(phi), rs * std::sin(phi), z);
    const Vector3d x = s + (rad - 1e-4) * n_in;
    p.add(x.x(), x.y(), x.z(), rad, 2600.0, 0);
  };
  place(z1 - 2.5 * (z1 - z0) / 13, 20.0 * kPi / 180);  // middle of ring 3, sector 1
  mc.add_forces(p, 0, 1e-6);
  ASSERT_GE(mc.contacts().size(), 1u);
  const int r31 = map.ring_sector(3, 1);
  EXPECT_GT(mc.region_normal_force()[r31], 0.0);
  EXPECT_NEAR(mc.region_normal_force()[r31], mc.total_normal_force(), 1e-12);
  for (int k = 0; k < 500; ++k) place(0.01 + 0.63 * u(rng), 2 * kPi * u(rng));
  mc.add_forces(p, 0, 1e-6);
  double sum = 0;
  Vector3d fsum = Vector3d::Zero();
  int loaded = 0;
  for (int r = 0; r < 117; ++r) {
    sum += mc.region_normal_force()[r];
    fsum += mc.region_force()[r];
    loaded += mc.region_normal_force()[r] > 0;
  }
  EXPECT_GT(loaded, 90);
  EXPECT_GT(mc.total_normal_force(), 100.0);
  EXPECT_NEAR(sum, mc.total_normal_force(), 1e-9 * mc.total_normal_force());
  EXPECT_NEAR((fsum - mc.wrench_about(Vector3d::Zero()).force).norm(), 0.0, 1e-9 * mc.total_normal_force());

  dem::RegionAverager avg(117);
  avg.add(mc.region_normal_force(), 1e-3);
  std::vector<double> zero(117, 0.0);
  avg.add(zero, 1e-3);
  EXPECT_NEAR(avg.window(), 2e-3, 1e-18);
  EXPECT_NEAR(avg.mean()[r31], 0.5 * mc.region_normal_force()[r31], 1e-12);
  EXPECT_THROW(avg.add(std::vector<double>(3, 0.0), 1e-3), std::invalid_argument);
  EXPECT_THROW(dem::RegionMap::rings_sectors(concave, 0, 9), std::invalid_argument);
  EXPECT_THROW(map.ring_sector(14, 1), std::out_of_range);
}

}  // namespace

namespace {

// The GYP1200 chamber of launch_free_configs/gyp1200_400rpm.yaml (liner frame, m).
TEST(Liners, MantleAndConcaveFromTheChamberGeometry) {
  core::ChamberGeometry g;
  g.mantle.z = {-0.200, -0.715};
  g.mantle.r = {0.168, 0.600};
  g.concave.z = {-0.100, -0.760};
  g.concave.r = {0.194, 0.662};
  const auto liners = dem::make_liner_meshes(g, 72, 0.03);
  // Lateral areas vs the smooth cone frusta, within the tessellation error (pi/n)^2/6 + slant term.
  auto lateral = [](double r1, double r2, double h) { return kPi * (r1 + r2) * std::hypot(h, r1 - r2); };
  const double tol = std::pow(kPi / 72, 2) * 0.7;
  EXPECT_NEAR(liners.mantle.area() / lateral(0.168, 0.600, 0.515), 1.0, tol);
  EXPECT_NEAR(liners.concave.area() / lateral(0.194, 0.662, 0.660), 1.0, tol);
  EXPECT_LT(liners.mantle.area(), lateral(0.168, 0.600, 0.515));  // inscribed polygons
  for (size_t t = 0; t < liners.mantle.num_triangles(); ++t) {
    const Vector3d c = liners.mantle.centroid(static_cast<int>(t));
    ASSERT_GT(liners.mantle.normal(static_cast<int>(t)).dot(Vector3d(c.x(), c.y(), 0).normalized()), 0.5);
  }
  const auto& map = liners.concave_regions;
  ASSERT_EQ(map.num_regions(), 117);
  std::vector<int> per_region(117, 0);
  for (size_t t = 0; t < liners.concave.num_triangles(); ++t) {
    const Vector3d c = liners.concave.centroid(static_cast<int>(t));
    ASSERT_LT(liners.concave.normal(static_cast<int>(t)).dot(Vector3d(c.x(), c.y(), 0).normalized()), -0.5);
    ASSERT_GE(map.region_of(static_cast<int>(t)), 0);
    ++per_region[map.region_of(static_cast<int>(t))];
  }
  for (int n : per_region) EXPECT_EQ(n, per_region[0]);  // 72 = 8 x 9 sectors, rings cut exactly
  EXPECT_THROW(dem::make_liner_meshes(g, 72, 0.0), std::invalid_argument);
  g.concave.r = {0.10, 0.30};  // concave inside the mantle
  EXPECT_THROW(dem::make_liner_meshes(g, 72, 0.03), std::invalid_argument);
}

}  // namespace
