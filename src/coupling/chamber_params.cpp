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

  if (dem.has("crushing")) {  // metaparticle crushing (coupling/metaparticle_crushing.hpp)
    auto c = dem.child("crushing");
    p.crushing.enabled = c.boolean_or("enabled", true);
    p.crushing.tensile_strength =
        c.number_or("tensile_strength_MPa", p.crushing.tensile_strength / 1e6, 0.01, 1000, "MPa", 1e6);
    p.crushing.progeny_exponent = c.number_or("progeny_exponent", p.crushing.progeny_exponent, 0.1, 5, "");
    p.crushing.batch_s = c.number_or("batch_s", p.crushing.batch_s, 0, 0.01, "s");
    p.crushing.stress_criterion = c.choice_or("criterion", "contact", {"contact", "stress"}) == "stress";
    p.crushing.fragments = c.boolean_or("fragments", p.crushing.fragments);
    p.crushing.min_fragment_m =
        c.number_or("min_fragment_mm", p.crushing.min_fragment_m / u::mm, 0.1, 1000, "mm", u::mm);
    p.crushing.fragment_growth_s = c.number_or("fragment_growth_s", p.crushing.fragment_growth_s, 0, 1, "s");
    p.crushing.reference_size =
        c.number_or("reference_size_mm", p.crushing.reference_size / u::mm, 1, 10000, "mm", u::mm);
    p.crushing.size_exponent = c.number_or("size_exponent", p.crushing.size_exponent, 0, 1.5, "");
  }

  if (dem.has("fines_bed")) {  // retained fines (coupling/fines_bed.hpp)
    auto c = dem.child("fines_bed");
    auto& b = p.fines_bed;
    b.enabled = c.boolean_or("enabled", true);
    b.bands = c.integer_or("bands", b.bands, 1, 200);
    b.sectors = c.integer_or("sectors", b.sectors, 1, 360);
    b.bulk_fraction = c.number_or("bulk_fraction", b.bulk_fraction, 0.1, 0.9, "");
    b.modulus_Pa = c.number_or("modulus_MPa", b.modulus_Pa / 1e6, 0.01, 1e5, "MPa", 1e6);
    b.exponent = c.number_or("exponent", b.exponent, 1, 4, "");
    b.rebound = c.number_or("rebound", b.rebound, 0.01, 1, "");
    b.max_strain = c.number_or("max_strain", b.max_strain, 0.05, 0.95, "");
    if (b.enabled && !p.crushing.enabled)
      c.fail("enabled", "retains the fines of dem.crushing, which is off");
  }

  auto f = dem.child("feed");
  p.feed.shapes = f.integer_or("shapes", p.feed.shapes, 1, 16);
  p.feed.rock_size_m = f.number("rock_size_mm", 5, 300, "mm", u::mm);
  p.feed.seed = static_cast<unsigned long long>(f.integer_or("seed", 7, 0, 2147483647));
  p.feed.choke_height_m = f.number_or("choke_height_mm", p.feed.choke_height_m / u::mm, 0, 2000, "mm", u::mm);
  p.feed.max_rate_kg_s = f.number_or("max_rate_kg_s", p.feed.max_rate_kg_s, 0.01, 1e4, "kg/s");
  p.feed.drop_speed_m_s = f.number_or("drop_speed_m_s", p.feed.drop_speed_m_s, 0, 20, "m/s");
  p.feed.max_fed_kg = f.number_or("max_fed_kg", p.feed.max_fed_kg, 0, 1e9, "kg");
  p.feed.prefill = f.boolean_or("prefill", p.feed.prefill);
  p.feed.prefill_max_kg = f.number_or("prefill_max_kg", p.feed.prefill_max_kg, 0, 1e9, "kg");
  if (f.has("rock_density_kg_m3")) p.feed.rock_density = f.number("rock_density_kg_m3", 500, 20000, "kg/m^3");

  if (dem.has("bpm_file")) {
    std::string f = dem.text("bpm_file");
    if (!f.empty() && f[0] != '/') {
      const auto& cfg = dem.file();
      const auto slash = cfg.find_last_of('/');
      if (slash != std::string::npos) f = cfg.substr(0, slash + 1) + f;
    }
    try {
      p.bpm = rocks::load_bpm_model(f);
    } catch (const std::exception& e) {
      dem.fail("bpm_file", e.what());
    }
  } else {
    p.bpm = rocks::bpm_model_from_config(dem.child("bpm"));
  }
  return p;
}

}  // namespace coupling
