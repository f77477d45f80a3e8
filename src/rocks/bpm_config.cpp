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

BondSettings bond_settings_from_config(const core::ConfigNode& b) {
  BondSettings s;
  s.kn = b.number("normal_stiffness_GPa_per_m", 1.0, 1e5, "GPa/m", GPa_per_m);
  s.kt = b.number("shear_stiffness_GPa_per_m", 1.0, 1e5, "GPa/m", GPa_per_m);
  s.sigma_c = b.number("normal_strength_MPa", 0.01, 1e4, "MPa", MPa);
  s.tau_c = b.number("shear_strength_MPa", 0.01, 1e4, "MPa", MPa);
  s.disk_radius = b.number("bond_disk_radius_mm", 0.01, 100.0, "mm", mm);
  s.reference_radius = b.number("reference_radius_mm", 0.01, 100.0, "mm", mm);
  s.damping = b.number_or("damping", 0.0, 0.0, 1.0, "");
  return s;
}

PackingOptions packing_from_config(const core::ConfigNode& p) {
  PackingOptions o;
  o.density = p.number("density", 0.3, 0.70, "");
  o.seed = static_cast<unsigned long long>(p.integer("seed", 0, 2000000000L));
  o.bond_gap_ratio = p.number("bond_gap_ratio", 0.0, 0.5, "");
  return o;
}

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
  const std::string s(indent, ' ');
  std::ostringstream o;
  o.precision(10);
  o << s << "metaparticles: " << m.metaparticles_yaml << "\n";
  o << s << "packing: {density: " << m.packing.density << ", seed: " << m.packing.seed
    << ", bond_gap_ratio: " << m.packing.bond_gap_ratio << "}\n";
  o << s << "bond:\n";
  o << s << "  normal_stiffness_GPa_per_m: " << m.bond.kn / GPa_per_m << "\n";
  o << s << "  shear_stiffness_GPa_per_m: " << m.bond.kt / GPa_per_m << "\n";
  o << s << "  normal_strength_MPa: " << m.bond.sigma_c / MPa << "\n";
  o << s << "  shear_strength_MPa: " << m.bond.tau_c / MPa << "\n";
  o << s << "  bond_disk_radius_mm: " << m.bond.disk_radius / mm << "\n";
  o << s << "  reference_radius_mm: " << m.bond.reference_radius / mm << "\n";
  o << s << "  damping: " << m.bond.damping << "\n";
  return o.str();
}

}  // namespace rocks
