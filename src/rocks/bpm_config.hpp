#pragma once
// The calibrated bonded-particle model as a crusher run uses it (launch_free_configs/bpm_calibrated.yaml):
// metaparticle sizes, packing and the bond parameters of Eq. 20-25. The parameters belong together:
// bond strengths calibrated for one metaparticle size are not valid for another (coarse-graining).
//
// YAML (mapping "bpm"):
//   metaparticles: {preset: paper_bimodal} or explicit modes (SizeDistribution::from_config)
//   packing: {density: 0.62, seed: 1, bond_gap_ratio: 0.1}
//   bond:
//     normal_stiffness_GPa_per_m, shear_stiffness_GPa_per_m   (k_bn, k_bt; Table 2 uses k_bn = 2.5 k_bt)
//     normal_strength_MPa, shear_strength_MPa                 (sigma_bc, tau_bc)
//     bond_disk_radius_mm, reference_radius_mm                (Eq. 20: lambda_b = disk / reference, so a pair
//                                                              of reference-size particles gets the disk radius)
//     damping                                                 (ratio of critical, 0 = undamped as in Eq. 22)
// The calibration tool writes its provenance (DOE result, confirmation figures) as comments above.
#include <string>

#include "core/config.hpp"
#include "core/config_schema.hpp"
#include "dem/bonds.hpp"
#include "rocks/packing.hpp"
#include "rocks/size_distribution.hpp"

namespace rocks {

struct BondSettings {
  double kn = 400e9, kt = 160e9;      // Pa/m
  double sigma_c = 25e6, tau_c = 9e6; // Pa
  double disk_radius = 3.1e-3;        // m (Table 2 "bond disk radius")
  double reference_radius = 3.0e-3;   // m: radius of the particle pair that gets the full disk radius
  double damping = 0.0;
  dem::BondParams params() const;     // radius_multiplier = disk_radius / reference_radius
};

struct BpmModel {
  SizeDistribution metaparticles = SizeDistribution::preset("paper_bimodal");
  std::string metaparticles_yaml = "{preset: paper_bimodal}";  // as read, to write back
  PackingOptions packing;
  BondSettings bond;
};

// The keys of bpm.bond and bpm.packing (core/config_schema.hpp); bpm.metaparticles: metaparticles_schema()
// (size_distribution.hpp).
const core::Schema<BondSettings>& bond_schema();
const core::Schema<PackingOptions>& packing_schema();
BondSettings bond_settings_from_config(const core::ConfigNode& bond);
PackingOptions packing_from_config(const core::ConfigNode& packing);
// Reads a "bpm" mapping (e.g. embedded in a dem_node config); the caller runs finish().
BpmModel bpm_model_from_config(const core::ConfigNode& bpm);
// Reads the "bpm" mapping of a file such as launch_free_configs/bpm_calibrated.yaml (finish() checked).
BpmModel load_bpm_model(const std::string& file);
// YAML text of the bpm mapping (without the calibration block), indented by `indent` spaces.
std::string bpm_model_yaml(const BpmModel& m, int indent = 2);

}  // namespace rocks
