#include "rocks/bpm_config.hpp"

#include <sstream>

#include "core/units.hpp"

namespace rocks {

using namespace core::units;

dem::BondParams BondSettings::params() const {
  dem::BondParams p;
  p.kn = kn;
  p.kt = kt;
  p.sigma_c = sigma_c;
  p.tau_c = tau_c;
  p.radius = 0.0;
  p.radius_multiplier = disk_radius / reference_radius;  // Eq. 20: R_b = lambda_b min(r_i, r_j)
  p.damping = damping;
  p.validate();
  return p;
}

// Plausible bands (core::Schema::plausible, issue 22): a value inside a key's range but ~1000x off is a unit slip.
// Stiffness per area k_bn, k_bt: Table 2 100-200 GPa/m, Table 4 400 GPa/m, shipped 16-500; 1e4 GPa/m, 25x Table 4's,
// needs a 5x shorter step than its 3e-7 s (dt ~ 1/sqrt(k)); a slip of MPa/m for GPa/m lands above it.
// Strengths: Table 2 9-25 MPa; 0.1 MPa (a weak rock's tensile strength) to 1 GPa (above the strongest rock's UCS).
// Radii: from 0.05 mm, the smallest metaparticle (bpm.metaparticles' range), so 10-50 mm given in metres is caught.
using core::kMetresForMm;

const core::Schema<BondSettings>& bond_schema() {
  using B = BondSettings;
  static const core::Schema<BondSettings> s = [] {
    core::Schema<BondSettings> k;
    k.number("normal_stiffness_GPa_per_m", "GPa/m", GPa_per_m, 1.0, 1e5, [](B& b) -> double& { return b.kn; },
             "bond normal stiffness k_bn (Eq. 21)", true)
        .plausible(1, 1e4, "", "MPa/m given for GPa/m?")
        .number("shear_stiffness_GPa_per_m", "GPa/m", GPa_per_m, 1.0, 1e5, [](B& b) -> double& { return b.kt; },
                "bond shear stiffness k_bt", true)
        .plausible(1, 1e4, "", "MPa/m given for GPa/m?")
        .number("normal_strength_MPa", "MPa", MPa, 0.01, 1e4, [](B& b) -> double& { return b.sigma_c; },
                "bond normal strength sigma_bc (Eq. 24)", true)
        .plausible(0.1, 1000, "GPa given for MPa?", "kPa given for MPa?")
        .number("shear_strength_MPa", "MPa", MPa, 0.01, 1e4, [](B& b) -> double& { return b.tau_c; },
                "bond shear strength tau_bc", true)
        .plausible(0.1, 1000, "GPa given for MPa?", "kPa given for MPa?")
        .number("bond_disk_radius_mm", "mm", mm, 0.01, 100.0, [](B& b) -> double& { return b.disk_radius; },
                "bond disk radius of a reference-size pair (Eq. 20)", true)
        .plausible(0.05, 100, kMetresForMm, "")
        .number("reference_radius_mm", "mm", mm, 0.01, 100.0, [](B& b) -> double& { return b.reference_radius; },
                "particle radius that gets the full disk radius", true)
        .plausible(0.05, 100, kMetresForMm, "")
        .number("damping", "", 1, 0.0, 1.0, [](B& b) -> double& { return b.damping; },
                "bond damping, ratio of critical (0: undamped, Eq. 22)");
    return k;
  }();
  return s;
}

const core::Schema<PackingOptions>& packing_schema() {
  using O = PackingOptions;
  static const core::Schema<PackingOptions> s = [] {
    core::Schema<PackingOptions> k;
    k.number("density", "", 1, 0.3, 0.70, [](O& o) -> double& { return o.density; },
             "solid fraction the packing reaches", true)
        .integer("seed", 0, 2000000000L, [](O& o) -> unsigned long long& { return o.seed; }, "packing seed", true)
        .number("bond_gap_ratio", "", 1, 0.0, 0.5, [](O& o) -> double& { return o.bond_gap_ratio; },
                "pairs with a surface gap up to this x the smaller radius are bonded", true);
    return k;
  }();
  return s;
}

BondSettings bond_settings_from_config(const core::ConfigNode& b) { return bond_schema().read(b); }

PackingOptions packing_from_config(const core::ConfigNode& p) { return packing_schema().read(p); }

BpmModel bpm_model_from_config(const core::ConfigNode& b) {
  BpmModel m;
  const auto mp = b.child("metaparticles");
  m.metaparticles = SizeDistribution::from_config(mp);
  YAML::Emitter e;
  e << YAML::Flow << mp.raw();
  m.metaparticles_yaml = e.c_str();
  m.packing = packing_from_config(b.child("packing"));
  m.bond = bond_settings_from_config(b.child("bond"));
  try {
    m.bond.params();
  } catch (const std::invalid_argument& ex) {
    throw core::ConfigError("config " + b.file() + ": " + b.path() + ".bond: " + ex.what());
  }
  return m;
}

BpmModel load_bpm_model(const std::string& file) {
  const auto root = core::ConfigNode::load_file(file);
  BpmModel m = bpm_model_from_config(root.child("bpm"));
  root.finish();
  return m;
}

std::string bpm_model_yaml(const BpmModel& m, int indent) {
  YAML::Node bpm;
  bpm["packing"] = packing_schema().write(m.packing);
  bpm["packing"].SetStyle(YAML::EmitterStyle::Flow);
  bpm["bond"] = bond_schema().write(m.bond);
  YAML::Emitter e;
  e << bpm;
  const std::string s(indent, ' ');
  std::ostringstream o;
  o << s << "metaparticles: " << m.metaparticles_yaml << "\n";
  std::istringstream lines(e.c_str());
  for (std::string l; std::getline(lines, l);) o << s << l << "\n";
  return o.str();
}

}  // namespace rocks
