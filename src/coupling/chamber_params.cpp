#include "coupling/chamber_params.hpp"

#include "core/units.hpp"

namespace coupling {

namespace u = core::units;

ChamberParams load_chamber_params(const core::ConfigNode& dem, const core::ChamberGeometry& chamber,
                                  double mantle_com_z_m, double concave_com_z_m) {
  ChamberParams p;
  p.chamber = chamber;
  p.mantle_com_z_m = mantle_com_z_m;
  p.concave_com_z_m = concave_com_z_m;
  p.liner_sectors = dem.integer_or("liner_sectors", p.liner_sectors, 12, 720);
  p.dt_s = dem.number_or("dt_s", p.dt_s, 0, 1e-3, "s (0: automatic)");
  p.threads = dem.integer_or("threads", p.threads, 0, 256);
  p.discharge_below_m = dem.number_or("discharge_below_mm", p.discharge_below_m / u::mm, 0, 1000, "mm", u::mm);
  if (dem.has("sieves_mm")) {
    p.sieves_m = dem.numbers("sieves_mm", 0.01, 1000, "mm", u::mm);
    for (std::size_t i = 1; i < p.sieves_m.size(); ++i)
      if (p.sieves_m[i] <= p.sieves_m[i - 1]) dem.fail("sieves_mm", "sizes must be strictly ascending");
  }
  p.rings = dem.integer_or("force_map_rings", p.rings, 1, 100);
  p.sectors = dem.integer_or("force_map_sectors", p.sectors, 1, 100);
  p.bookkeeping_s = dem.number_or("bookkeeping_s", p.bookkeeping_s, 1e-5, 0.1, "s");
  p.throughput_window_s = dem.number_or("throughput_window_s", p.throughput_window_s, 0.01, 100, "s");
  p.tracked_particles = dem.integer_or("tracked_particles", p.tracked_particles, 0, 100);

  auto f = dem.child("feed");
  p.feed.shapes = f.integer_or("shapes", p.feed.shapes, 1, 16);
  p.feed.rock_size_m = f.number("rock_size_mm", 5, 300, "mm", u::mm);
  p.feed.metaparticles = std::make_shared<rocks::SizeDistribution>(
      rocks::SizeDistribution::from_config(f.child("metaparticles")));
  p.feed.packing_density = f.number_or("packing_density", p.feed.packing_density, 0.3, 0.7);
  p.feed.seed = static_cast<unsigned long long>(f.integer_or("seed", 7, 0, 2147483647));
  p.feed.choke_height_m = f.number_or("choke_height_mm", p.feed.choke_height_m / u::mm, 0, 2000, "mm", u::mm);
  p.feed.max_rate_kg_s = f.number_or("max_rate_kg_s", p.feed.max_rate_kg_s, 0.01, 1e4, "kg/s");
  p.feed.drop_speed_m_s = f.number_or("drop_speed_m_s", p.feed.drop_speed_m_s, 0, 20, "m/s");
  p.feed.max_fed_kg = f.number_or("max_fed_kg", p.feed.max_fed_kg, 0, 1e9, "kg");

  // BPM parameters (Table 4 names and units; the calibration writes these keys).
  auto b = dem.child("bpm");
  p.bond.kn = b.number("normal_stiffness_GPa_per_m", 1e-3, 1e4, "GPa/m", u::GPa_per_m);
  p.bond.kt = b.number("shear_stiffness_GPa_per_m", 1e-3, 1e4, "GPa/m", u::GPa_per_m);
  p.bond.sigma_c = b.number("normal_critical_stress_MPa", 1e-3, 1e4, "MPa", u::MPa);
  p.bond.tau_c = b.number("shear_critical_stress_MPa", 1e-3, 1e4, "MPa", u::MPa);
  if (b.has("bond_radius_mm")) {
    p.bond.radius = b.number("bond_radius_mm", 0.01, 100, "mm", u::mm);
  } else {
    p.bond.radius_multiplier = b.number("bond_radius_multiplier", 0.05, 2.0);
  }
  p.bond.damping = b.number_or("damping_ratio", 0.0, 0, 1);
  try {
    p.bond.validate();
  } catch (const std::invalid_argument& e) {
    b.fail("", e.what());
  }
  return p;
}

}  // namespace coupling
