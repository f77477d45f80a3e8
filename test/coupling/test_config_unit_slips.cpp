// Issue 22: dem keys given in the wrong unit (inside their ranges but ~1000x off) are refused as a unit slip by the
// plausible bands of coupling/chamber_params.cpp, naming the key and the likely unit.
#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "../common/unit_slips.hpp"
#include "core/config.hpp"
#include "small_chamber.hpp"

namespace {

// The error of loading quick_demo.yaml's dem section with `from` replaced by `to` ("" when it loads).
std::string error_with(const std::string& from, const std::string& to) {
  const std::string text = test_slips::replaced(test_chamber::quick_demo_text(), from, to, "quick_demo.yaml");
  try {
    test_chamber::chamber_params_of(text);
    return "";
  } catch (const core::ConfigError& e) {
    return e.what();
  }
}

using test_slips::Slip;

TEST(DemConfig, UnitSlipsAreRefusedNamingTheKeyAndTheLikelyUnit) {
  const Slip slips[] = {
      {"discharge_below_mm: 40", "discharge_below_mm: 0.04", "dem.discharge_below_mm", "metres given for mm?"},
      {"sieves_mm: [1, 2, 4, 8, 12, 16, 22.4, 31.5, 40, 50, 63]", "sieves_mm: [0.016, 0.0224, 0.0315, 0.05]",
       "dem.sieves_mm", "metres given for mm?"},
      {"choke_height_mm: 80", "choke_height_mm: 0.08", "dem.feed.choke_height_mm", "metres given for mm?"},
      {"tensile_strength_MPa: 3.77", "tensile_strength_MPa: 0.02", "dem.crushing.tensile_strength_MPa",
       "GPa given for MPa?"},
      {"tensile_strength_MPa: 3.77", "tensile_strength_MPa: 500", "dem.crushing.tensile_strength_MPa",
       "kPa given for MPa?"},
      // Slips that fall outside the key's range: refused by it, the band names the slip.
      {"sieves_mm: [1, 2, 4, 8, 12, 16, 22.4, 31.5, 40, 50, 63]",
       "sieves_mm: [0.001, 0.002, 0.004, 0.008, 0.012, 0.016, 0.0224, 0.0315, 0.04, 0.05, 0.063]", "dem.sieves_mm",
       "metres given for mm?"},
      {"rock_size_mm: 50", "rock_size_mm: 0.05", "dem.feed.rock_size_mm", "metres given for mm?"},
      {"tensile_strength_MPa: 3.77", "tensile_strength_MPa: 0.00377", "dem.crushing.tensile_strength_MPa",
       "GPa given for MPa?"},
      {"    prefill: true", "    rock_density_kg_m3: 2.65\n    prefill: true", "dem.feed.rock_density_kg_m3",
       "g/cm^3 given for kg/m^3?"},
  };
  test_slips::expect_slips_named(slips, error_with);
  // Sensible values at the bands' ends pass: no discharge margin, no choke feeding, a 20 um sieve, a weak rock.
  EXPECT_EQ(error_with("discharge_below_mm: 40", "discharge_below_mm: 0"), "");
  EXPECT_EQ(error_with("choke_height_mm: 80", "choke_height_mm: 0"), "");
  EXPECT_EQ(error_with("sieves_mm: [1, 2, 4,", "sieves_mm: [0.02, 2, 4,"), "");
  EXPECT_EQ(error_with("tensile_strength_MPa: 3.77", "tensile_strength_MPa: 0.2"), "");
}

// The bpm keys inside the dem section (dem.bpm: quick_demo's own rock model) get the bands of rocks/bpm_config.cpp.
TEST(DemConfig, BpmUnitSlipsInTheDemSectionAreRefusedByName) {
  const Slip slips[] = {
      {"normal_stiffness_GPa_per_m: 40", "normal_stiffness_GPa_per_m: 40000", "dem.bpm.bond.normal_stiffness_GPa_per_m",
       "MPa/m given for GPa/m?"},
      {"normal_strength_MPa: 25", "normal_strength_MPa: 0.025", "dem.bpm.bond.normal_strength_MPa",
       "GPa given for MPa?"},
      {"sd_mm: 0.7", "sd_mm: 0.0007", "dem.bpm.metaparticles.coarse.sd_mm", "metres given for mm?"},
      {"mean_radius_mm: 7", "mean_radius_mm: 0.007", "dem.bpm.metaparticles.coarse.mean_radius_mm",
       "metres given for mm?"},
  };
  test_slips::expect_slips_named(slips, error_with);
}

}  // namespace
