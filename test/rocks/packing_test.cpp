// Size distributions, rock shapes, packing density, bonding and the rock file.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>

#include "core/units.hpp"
#include "rocks/packing.hpp"
#include "rocks/rock_file.hpp"
#include "rocks/shape.hpp"
#include "rocks/size_distribution.hpp"

using namespace rocks;
using core::units::mm;

TEST(SizeDistribution, PaperBimodalMoments) {
  const auto d = SizeDistribution::preset("paper_bimodal");
  Rng rng(7);
  const auto r = d.sample_volume(2e-3, rng);  // ~4e5 mm^3 of solid
  double vc = 0, vf = 0, sc = 0, sc2 = 0, sf = 0, sf2 = 0;
  int nc = 0, nf = 0;
  for (double x : r) {
    const double v = x * x * x;
    if (x > 2.0 * mm) { vc += v; sc += x; sc2 += x * x; ++nc; }
    else { vf += v; sf += x; sf2 += x * x; ++nf; }
  }
  const double mc = sc / nc, mf = sf / nf;
  EXPECT_NEAR(mc, 3.0 * mm, 0.03 * mm);
  EXPECT_NEAR(mf, 1.0 * mm, 0.01 * mm);
  // truncation at +-2 sd lowers the sd by the factor 0.880 of a normal truncated at 2 sd
  EXPECT_NEAR(std::sqrt(sc2 / nc - mc * mc), 0.525 * mm * 0.880, 0.03 * mm);
  EXPECT_NEAR(std::sqrt(sf2 / nf - mf * mf), 0.225 * mm * 0.880, 0.006 * mm);
  EXPECT_NEAR(vc / (vc + vf), 0.7, 0.01);
  EXPECT_THROW(SizeDistribution::preset("nonsense"), std::invalid_argument);
  EXPECT_THROW(SizeDistribution({{1 * mm, 0.6 * mm, 1.0}}, 2.0), std::invalid_argument);
  EXPECT_THROW(SizeDistribution({{1 * mm, 0.1 * mm, 0.5}}, 2.0), std::invalid_argument);
}

TEST(SizeDistribution, FromConfig) {
  auto c = core::ConfigNode::load_string(
      "m: {coarse: {mean_radius_mm: 6, sd_mm: 1.05}, fine: {mean_radius_mm: 2, sd_mm: 0.45}, "
      "coarse_volume_fraction: 0.7}");
  const auto d = SizeDistribution::from_config(c.child("m"));
  ASSERT_EQ(d.modes().size(), 2u);
  EXPECT_DOUBLE_EQ(d.modes()[0].mean_radius, 6e-3);
  EXPECT_DOUBLE_EQ(d.modes()[1].sd, 0.45e-3);
  auto bad = core::ConfigNode::load_string("m: {preset: fine_sand}");
  EXPECT_THROW(SizeDistribution::from_config(bad.child("m")), core::ConfigError);
}

TEST(Shape, CylinderAndRockMeshes) {
  CylinderShape cyl(50 * mm, 50 * mm, 128);
  EXPECT_NEAR(cyl.volume(), M_PI * 25e-3 * 25e-3 * 50e-3, 1e-12);
  // 128-gon prism volume = (n/2) sin(2 pi / n) R^2 L
  EXPECT_NEAR(cyl.mesh().volume(), 64 * std::sin(2 * M_PI / 128) * 25e-3 * 25e-3 * 50e-3, 1e-12);
  EXPECT_NEAR(cyl.clearance({0, 0, 0}), 25e-3, 1e-15);
  EXPECT_NEAR(cyl.clearance({0, 0, 20e-3}), 5e-3, 1e-15);
  for (int k = 1; k <= 4; ++k) {
    auto rock = make_irregular_rock(k, 50 * mm);
    const TriMesh m = rock->mesh();
    EXPECT_NEAR(rock->max_corner().y() - rock->min_corner().y(), 50 * mm, 1e-9);  // nominal size
    EXPECT_GT(m.volume(), 0.0);
    // closed surface: every edge used twice, once per direction
    std::map<std::pair<int, int>, int> edges;
    for (const auto& t : m.triangles)
      for (int e = 0; e < 3; ++e) ++edges[{t[e], t[(e + 1) % 3]}];
    for (const auto& kv : edges) {
      EXPECT_EQ(kv.second, 1);
      const std::pair<int, int> back(kv.first.second, kv.first.first);
      EXPECT_EQ(edges.count(back), 1u);
    }
    // the mesh vertices lie on the boundary, the origin inside
    for (const auto& v : m.vertices) EXPECT_NEAR(rock->clearance(v), 0.0, 1e-9);
    EXPECT_GT(rock->clearance(Vec3::Zero()), 5 * mm);
  }
  // same seed, same rock; another seed, another rock
  EXPECT_EQ(make_irregular_rock(3, 0.05)->mesh().vertices[0], make_irregular_rock(3, 0.05)->mesh().vertices[0]);
  EXPECT_NE(make_irregular_rock(3, 0.05)->volume(), make_irregular_rock(4, 0.05)->volume());
}

// Documented in src/rocks/README.md ("Reference rock"): irregular rock seed 1, nominal 50 mm,
// paper_bimodal, density 0.62, packing seed 1, bond gap ratio 0.1 -> 3083 particles in the largest
// bonded cluster (46 free fines dropped), density 0.617, 8083 bonds (coordination 5.24), max residual
// overlap 1 % of the smaller radius.
TEST(Packing, SeededRockIsAsDocumentedAndReproducible) {
  auto rock = make_irregular_rock(1, 50 * mm);
  PackingOptions o;
  o.density = 0.62;
  o.seed = 1;
  o.bond_gap_ratio = 0.1;
  const auto dist = SizeDistribution::preset("paper_bimodal");
  const RockPacking p = pack_shape(*rock, dist, o);
  EXPECT_NEAR(p.density(), 0.617, 0.004);  // 0.62 drawn, less the free fines dropped
  EXPECT_NEAR(static_cast<double>(p.size()), 3083.0, 0.03 * 3083);
  EXPECT_NEAR(static_cast<double>(p.bonds.size()), 8083.0, 0.04 * 8083);
  EXPECT_NEAR(p.coordination(), 5.24, 0.2);
  EXPECT_LE(p.max_overlap_ratio, 0.0101);
  for (std::size_t i = 0; i < p.size(); ++i) ASSERT_GE(rock->clearance(p.positions[i]), p.radii[i] * 0.98);
  // every bond joins near neighbours, and every near pair is bonded
  for (const auto& b : p.bonds) {
    const double gap = (p.positions[b.second] - p.positions[b.first]).norm() - p.radii[b.first] - p.radii[b.second];
    ASSERT_LE(gap, 0.1 * std::min(p.radii[b.first], p.radii[b.second]) + 1e-15);
  }
  // same seed -> identical rock; another seed -> another arrangement, same statistics
  const RockPacking q = pack_shape(*rock, dist, o);
  ASSERT_EQ(q.size(), p.size());
  EXPECT_EQ(q.positions, p.positions);
  EXPECT_EQ(q.bonds, p.bonds);
  o.seed = 2;
  const RockPacking s = pack_shape(*rock, dist, o);
  EXPECT_NE(s.positions[0], p.positions[0]);
  EXPECT_NEAR(s.coordination(), p.coordination(), 0.2);

  // the rock file round-trips exactly
  const std::string file = ::testing::TempDir() + "/rock_test.rock";
  save_rock(p, file);
  const RockPacking l = load_rock(file);
  EXPECT_EQ(l.positions, p.positions);
  EXPECT_EQ(l.radii, p.radii);
  EXPECT_EQ(l.bonds, p.bonds);
  EXPECT_EQ(l.seed, p.seed);
  EXPECT_DOUBLE_EQ(l.container_volume, p.container_volume);
  std::remove(file.c_str());
}

TEST(Packing, RejectsBadInput) {
  CylinderShape cyl(20 * mm, 10 * mm);
  PackingOptions o;
  o.density = 0.9;
  EXPECT_THROW(pack_shape(cyl, SizeDistribution::preset("paper_bimodal"), o), std::invalid_argument);
  o.density = 0.6;
  EXPECT_THROW(pack_shape(CylinderShape(10 * mm, 10 * mm), SizeDistribution::preset("crusher_coarse3"), o),
               std::invalid_argument);
  const std::string file = ::testing::TempDir() + "/bad.rock";
  {
    std::ofstream f(file);
    f << "inertia_crusher_rock 1\nname x\nseed 1\ntarget_density 0.6\ncontainer_volume_m3 1e-6\n"
         "bond_gap_ratio 0.1\ndistribution d\nparticles 2\n0 0 0 0.001\n0.002 0 0 0.001\nbonds 1\n1 0\nend\n";
  }
  EXPECT_THROW(load_rock(file), std::runtime_error);
  std::remove(file.c_str());
}
