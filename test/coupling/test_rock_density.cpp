// feed.rock_density (coupling/chamber_params.hpp): a fed rock weighs its solid density times its volume.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>

#include "coupling/chamber_dem.hpp"
#include "small_chamber.hpp"

using test_chamber::sphere_density;

// Packed to solid fraction phi, a rock of Table 4 spheres (2600 kg/m^3) weighs phi 2600 V; with rock_density
// 2600 the same spheres weigh 2600 / phi each and the rock 2600 V. The DEM step stays that of 2600 kg/m^3.
TEST(RockDensity, ARockWeighsItsSolidDensityTimesItsVolume) {
  const auto p = test_chamber::small_chamber();
  auto q = p;
  q.feed.rock_density = 2600;
  const coupling::ChamberDem light(p), heavy(q);
  ASSERT_EQ(light.rock_shapes(), heavy.rock_shapes());
  for (int s = 0; s < light.rock_shapes(); ++s) {
    const double phi = light.packing_density(s);
    std::printf("shape %d: phi %.3f, %.4f kg -> %.4f kg, spheres at %.0f kg/m^3\n", s, phi, light.rock_mass_kg(s),
                heavy.rock_mass_kg(s), heavy.sphere_density(s));
    EXPECT_EQ(light.rock_particles(s), heavy.rock_particles(s));
    EXPECT_DOUBLE_EQ(light.sphere_density(s), 2600.0);
    EXPECT_NEAR(heavy.sphere_density(s), 2600.0 / phi, 1e-9 * 2600.0 / phi);
    EXPECT_NEAR(heavy.rock_mass_kg(s), light.rock_mass_kg(s) / phi, 1e-12 * heavy.rock_mass_kg(s));
  }
  EXPECT_DOUBLE_EQ(light.dt(), heavy.dt());
}

// Fed and pre-filled rocks carry the heavier spheres, the mass balance closes, and crushed spheres' grown
// fragments keep their parent's volume (at the spheres' mean density), not the volume of their mass as solid rock.
TEST(RockDensity, FedRocksCarryTheHeavierSpheresAndFragmentsKeepTheirVolume) {
  auto p = test_chamber::prefilled_small_chamber(0.5, 0.8);
  p.feed.rock_density = 2600;
  p.crushing.enabled = true;
  p.crushing.tensile_strength = 0.5e6;  // weak rock: the 3 deg gyration crushes many metaparticles
  p.crushing.batch_s = 2e-4;
  p.crushing.fragments = true;
  p.crushing.min_fragment_m = 4e-3;
  p.crushing.fragment_growth_s = 5e-3;
  coupling::ChamberDem dem(p);
  std::set<double> rock_rho;
  double mean_mass = 0, mean_volume = 0;
  for (int s = 0; s < dem.rock_shapes(); ++s) {
    rock_rho.insert(dem.sphere_density(s));
    mean_mass += dem.rock_mass_kg(s);
    mean_volume += dem.rock_mass_kg(s) / dem.sphere_density(s);
  }
  const double rho_grown = mean_mass / mean_volume;
  coupling::BodyMotion m, c;
  c.com = Eigen::Vector3d(0, 0, p.concave_com_z_m);
  for (int k = 0; k < 140; ++k) {  // 120 ms of gyration, then 20 ms held at the last pose
    if (k < 120) test_chamber::gyrate(p, k * 1e-3, 3.0 * M_PI / 180, &m);
    dem.advance(m, c, 1e-3);
  }
  const auto s = dem.product();
  std::printf("fed %.4f kg, %ld fragmented, %ld crushed to fines, %.4f kg in the chamber, %zu growing\n", s.fed_kg,
              s.metaparticles_fragmented, s.metaparticles_crushed, s.in_chamber_kg, dem.growing_fragments());
  EXPECT_NEAR(s.fed_kg, s.in_chamber_kg + s.discharged_kg + s.lost_kg, 1e-9 * s.fed_kg);
  ASSERT_GT(s.metaparticles_fragmented, 20);
  // Every sphere is a rock's (one of the shapes' densities), a grown fragment (rho_grown) or still growing.
  const auto& P = dem.world().particles();
  std::size_t whole = 0, grown = 0, growing = 0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const double rho = sphere_density(P, i);
    bool is_rock = false;
    for (double r : rock_rho) is_rock = is_rock || std::abs(rho - r) < 1e-9 * r;
    if (is_rock) ++whole;
    else if (std::abs(rho - rho_grown) < 1e-9 * rho_grown) ++grown;
    else if (rho > rho_grown) ++growing;
    else ADD_FAILURE() << "sphere " << i << " at " << rho << " kg/m^3, lighter than any rock sphere";
  }
  std::printf("%zu rock spheres, %zu grown fragments (%.0f kg/m^3), %zu growing\n", whole, grown, rho_grown,
              growing);
  EXPECT_GT(whole, 0u);
  EXPECT_GT(grown, 20u);
  EXPECT_LE(growing, dem.growing_fragments());  // the list may still hold one discharged since the last step
}

// dem.feed.rock_density_kg_m3 is read in kg/m^3; absent it is 0 (spheres at the material's density), and a value
// out of range is refused by name.
TEST(RockDensity, ConfigReadsTheRockDensity) {
  auto load = [](const std::string& extra) { return test_chamber::quick_demo_with(extra, "    prefill: true"); };
  EXPECT_DOUBLE_EQ(load("    rock_density_kg_m3: 2700\n").feed.rock_density, 2700.0);
  EXPECT_EQ(load("").feed.rock_density, 0.0);
  try {
    load("    rock_density_kg_m3: 100\n");
    FAIL() << "expected a ConfigError";
  } catch (const core::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("dem.feed.rock_density_kg_m3"), std::string::npos) << e.what();
  }
}
