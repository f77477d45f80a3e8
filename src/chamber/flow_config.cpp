#include "chamber/flow_config.hpp"

#include <cmath>
#include <sstream>

#include "core/units.hpp"

namespace chamber {

namespace u = core::units;

FlowMaterial flow_material_from_config(const core::ConfigNode& n, const FlowMaterial& base) {
  FlowMaterial m = base;
  m.solid_density = n.number_or("solid_density_kg_m3", m.solid_density, 500, 20000, "kg/m^3");
  m.loose_fraction = n.number_or("loose_solid_fraction", m.loose_fraction, 0.2, 0.8, "");
  if (n.has("pressure")) {
    auto p = n.child("pressure");
    m.modulus_Pa = p.number_or("modulus_MPa", m.modulus_Pa / u::MPa, 0.01, 1e5, "MPa", u::MPa);
    m.exponent = p.number_or("exponent", m.exponent, 1, 6, "");
    m.rebound = p.number_or("rebound", m.rebound, 0.01, 1, "");
    m.max_compression = p.number_or("max_compression", m.max_compression, 0.05, 0.8, "");
  }
  auto& b = m.breakage;
  if (n.has("selection")) {
    auto s = n.child("selection");
    b.s_c = s.number_or("s_c", b.s_c, 1e-3, 10, "");
    b.m = s.number_or("exponent", b.m, 0.1, 10, "");
    b.q = s.number_or("size_exponent", b.q, 0, 5, "");
    b.x_ref = s.number_or("x_ref_mm", b.x_ref / u::mm, 0.01, 1000, "mm", u::mm);
    b.x_resolved = s.number_or("resolved_mm", b.x_resolved / u::mm, 0, 1000, "mm", u::mm);
    b.q_below = s.number_or("size_exponent_below", b.q_below, 0, 5, "");
  }
  if (n.has("progeny")) {
    auto p = n.child("progeny");
    b.phi = p.number_or("phi", b.phi, 0, 1, "");
    b.gamma = p.number_or("gamma", b.gamma, 0.01, 10, "");
    b.beta = p.number_or("beta", b.beta, 0.01, 20, "");
  }
  return m;
}

FlowMaterial load_flow_material(const std::string& file) {
  auto root = core::ConfigNode::load_file(file);
  FlowMaterial m = flow_material_from_config(root.child("flow_material"));
  root.finish();
  return m;
}

FlowParams load_flow_params(const core::ConfigNode& f) {
  FlowParams p;
  if (f.has("material_file")) {
    std::string file = f.text("material_file");
    if (!file.empty() && file[0] != '/') {
      const auto slash = f.file().find_last_of('/');
      if (slash != std::string::npos) file = f.file().substr(0, slash + 1) + file;
    }
    p.material = load_flow_material(file);
  }
  if (f.has("material")) p.material = flow_material_from_config(f.child("material"), p.material);
  p.bands = f.integer_or("bands", p.bands, 2, 400);
  p.sectors = f.integer_or("sectors", p.sectors, 1, 360);
  if (f.has("sieves_mm")) {
    p.sieves_m = f.numbers("sieves_mm", 0.01, 1000, "mm", u::mm);
    for (std::size_t i = 1; i < p.sieves_m.size(); ++i)
      if (p.sieves_m[i] <= p.sieves_m[i - 1]) f.fail("sieves_mm", "sizes must be strictly ascending");
    p.feed_passing = default_feed_passing(p.sieves_m);  // on the new sieves, unless given below
  }
  if (f.has("feed_passing_pct")) {
    p.feed_passing = f.numbers("feed_passing_pct", 0, 100, "%", 0.01, static_cast<int>(p.sieves_m.size()));
    for (std::size_t i = 1; i < p.feed_passing.size(); ++i)
      if (p.feed_passing[i] < p.feed_passing[i - 1]) f.fail("feed_passing_pct", "must not fall from sieve to sieve");
  }
  p.prefill = f.boolean_or("prefill", p.prefill);
  p.compaction_memory = f.boolean_or("compaction_memory", p.compaction_memory);
  return p;
}

FlowRunConfig load_flow_run_config(const std::string& file) {
  auto root = core::ConfigNode::load_file(file);
  FlowRunConfig c;
  c.mech = mbd::load_mechanism_params(root.child("mbd"));
  c.flow = load_flow_params(root.child_or_empty("flow"));
  c.run = core::load_run_options(root.child("run"));
  core::load_coupling_options(root.child_or_empty("coupling"));
  root.ignore("dem");
  root.finish();
  return c;
}

std::string flow_material_yaml(const FlowMaterial& m) {
  std::ostringstream y;
  y.precision(10);
  const auto& b = m.breakage;
  y << "flow_material:\n"
    << "  solid_density_kg_m3: " << m.solid_density << "\n"
    << "  loose_solid_fraction: " << m.loose_fraction << "\n"
    << "  pressure: {modulus_MPa: " << m.modulus_Pa / u::MPa << ", exponent: " << m.exponent
    << ", rebound: " << m.rebound << ", max_compression: " << m.max_compression << "}\n"
    << "  selection: {s_c: " << b.s_c << ", exponent: " << b.m << ", size_exponent: " << b.q
    << ", x_ref_mm: " << b.x_ref / u::mm << ", resolved_mm: " << b.x_resolved / u::mm
    << ", size_exponent_below: " << b.q_below << "}\n"
    << "  progeny: {phi: " << b.phi << ", gamma: " << b.gamma << ", beta: " << b.beta << "}\n";
  return y.str();
}

}  // namespace chamber
