// Issue 22: bpm keys given in the wrong unit (inside their ranges but ~1000x off) are refused as a unit slip by the
// plausible bands of rocks/bpm_config.cpp and rocks/size_distribution.cpp, naming the key and the likely unit.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "../common/unit_slips.hpp"
#include "core/config.hpp"
#include "rocks/bpm_config.hpp"

namespace {

// The error of reading launch_free_configs/bpm_calibrated.yaml with `from` replaced by `to` ("" when it loads).
std::string error_with(const std::string& from, const std::string& to) {
  const std::string text = test_slips::replaced(test_slips::source_text("launch_free_configs/bpm_calibrated.yaml"),
                                                from, to, "bpm_calibrated.yaml");
  try {
    const auto root = core::ConfigNode::load_string(text, "bpm_calibrated+test");
    rocks::bpm_model_from_config(root.child("bpm"));
    return "";
  } catch (const core::ConfigError& e) {
    return e.what();
  }
}

TEST(BpmConfig, UnitSlipsAreRefusedNamingTheKeyAndTheLikelyUnit) {
  const test_slips::Slip slips[] = {
      {"normal_stiffness_GPa_per_m: 500", "normal_stiffness_GPa_per_m: 50000", "bpm.bond.normal_stiffness_GPa_per_m",
       "MPa/m given for GPa/m?"},
      {"shear_stiffness_GPa_per_m: 200", "shear_stiffness_GPa_per_m: 20000", "bpm.bond.shear_stiffness_GPa_per_m",
       "MPa/m given for GPa/m?"},
      {"normal_strength_MPa: 21.0065001", "normal_strength_MPa: 0.021", "bpm.bond.normal_strength_MPa",
       "GPa given for MPa?"},
      {"shear_strength_MPa: 13.44416007", "shear_strength_MPa: 0.013", "bpm.bond.shear_strength_MPa",
       "GPa given for MPa?"},
      {"normal_strength_MPa: 21.0065001", "normal_strength_MPa: 2100", "bpm.bond.normal_strength_MPa",
       "kPa given for MPa?"},
      {"bond_disk_radius_mm: 3.3", "bond_disk_radius_mm: 0.033", "bpm.bond.bond_disk_radius_mm",
       "metres given for mm?"},
      {"reference_radius_mm: 3", "reference_radius_mm: 0.03", "bpm.bond.reference_radius_mm", "metres given for mm?"},
      {"{preset: crusher_coarse}", "{coarse: {mean_radius_mm: 6, sd_mm: 0.00105}}", "bpm.metaparticles.coarse.sd_mm",
       "metres given for mm?"},
      {"{preset: crusher_coarse}",
       "{coarse: {mean_radius_mm: 6, sd_mm: 1.05}, fine: {mean_radius_mm: 2, sd_mm: 0.00045}, "
       "coarse_volume_fraction: 0.7}",
       "bpm.metaparticles.fine.sd_mm", "metres given for mm?"},
      // Slips that fall outside the key's range: refused by it, the band names the slip.
      {"normal_stiffness_GPa_per_m: 500", "normal_stiffness_GPa_per_m: 500000", "bpm.bond.normal_stiffness_GPa_per_m",
       "MPa/m given for GPa/m?"},
      {"shear_strength_MPa: 13.44416007", "shear_strength_MPa: 13444", "bpm.bond.shear_strength_MPa",
       "kPa given for MPa?"},
      {"bond_disk_radius_mm: 3.3", "bond_disk_radius_mm: 0.0033", "bpm.bond.bond_disk_radius_mm",
       "metres given for mm?"},
      {"{preset: crusher_coarse}", "{coarse: {mean_radius_mm: 0.006, sd_mm: 1.05}}",
       "bpm.metaparticles.coarse.mean_radius_mm", "metres given for mm?"},
  };
  test_slips::expect_slips_named(slips, error_with);
  // Sensible values pass: the shipped file, Table 4's 400 GPa/m, a weak rock's 0.5 MPa bonds, mono-sized spheres.
  EXPECT_EQ(error_with("damping: 0", "damping: 0"), "");
  EXPECT_EQ(error_with("normal_stiffness_GPa_per_m: 500", "normal_stiffness_GPa_per_m: 400"), "");
  EXPECT_EQ(error_with("shear_strength_MPa: 13.44416007", "shear_strength_MPa: 0.5"), "");
  EXPECT_EQ(error_with("{preset: crusher_coarse}", "{coarse: {mean_radius_mm: 3, sd_mm: 0}}"), "");
}

}  // namespace
