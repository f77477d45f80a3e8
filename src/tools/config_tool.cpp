// The config schema from the command line (`crusher config`):
//   config_tool --keys [SECTION]   the key reference (name, unit, range, default, meaning) of every schema section
//   config_tool --json CONFIG      the run config resolved (base chain applied), validated as the nodes read it,
//                                  as JSON, every default filled in (dem.bpm as written)
#include <charconv>
#include <cmath>
#include <iostream>
#include <string>

#include "chamber/flow_config.hpp"
#include "coupling/chamber_params.hpp"
#include "core/config_schema.hpp"
#include "core/run_config.hpp"
#include "mbd/mechanism_params.hpp"
#include "mbd/mechanism_schema.hpp"

namespace {

void usage(std::ostream& o) {
  o << "usage: config_tool --keys [SECTION]   key reference (sections: run, mbd, coupling, flow, flow_material, dem, bpm.packing, bpm.bond, bpm.metaparticles)\n"
       "       config_tool --json CONFIG      the resolved, validated run config as JSON\n";
}

bool keys(const std::string& only) {
  const std::pair<std::string, std::vector<core::KeyInfo>> sections[] = {
      {"run", core::run_schema().keys()},
      {"mbd", mbd::mechanism_schema().keys()},
      {"coupling", core::coupling_schema().keys()},
      {"flow", chamber::flow_schema().keys()},
      {"flow_material", chamber::flow_material_schema().keys()},
      {"dem", coupling::chamber_schema().keys()},
      {"bpm.packing", rocks::packing_schema().keys()},
      {"bpm.bond", rocks::bond_schema().keys()},
      {"bpm.metaparticles", rocks::metaparticles_schema().keys()},
  };
  bool any = false;
  for (const auto& [name, k] : sections) {
    if (!only.empty() && only != name) continue;
    if (!any) std::cout << "key  unit  accepted  default  meaning\n";
    std::cout << core::key_reference(name, k);
    any = true;
  }
  return any;
}

std::string quoted(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += std::string("\\") + c;
    else if (c == '\n') o += "\\n";
    else if (static_cast<unsigned char>(c) < 0x20) o += ' ';
    else o += c;
  }
  return o + "\"";
}

// A plain YAML scalar as JSON: a number, true/false, null, else a string (quoted YAML stays a string).
std::string scalar_json(const YAML::Node& n) {
  const std::string s = n.Scalar();
  if (n.Tag() == "!") return quoted(s);
  if (s == "true" || s == "false") return s;
  if (s == "~" || s == "null" || s.empty()) return "null";
  double v = 0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    return quoted(s);
  }
  if (!std::isfinite(v)) return quoted(s);
  char b[32];
  auto r = std::to_chars(b, b + sizeof b, v);
  return std::string(b, r.ptr);
}

void json(std::ostream& o, const YAML::Node& n, int indent) {
  const std::string pad(indent + 2, ' '), end(indent, ' ');
  if (n.IsMap()) {
    o << "{";
    bool first = true;
    for (const auto& kv : n) {
      o << (first ? "\n" : ",\n") << pad << quoted(kv.first.as<std::string>()) << ": ";
      json(o, kv.second, indent + 2);
      first = false;
    }
    o << (first ? "}" : "\n" + end + "}");
  } else if (n.IsSequence()) {
    o << "[";
    for (std::size_t i = 0; i < n.size(); ++i) {
      o << (i ? ", " : "");
      json(o, n[i], indent + 2);
    }
    o << "]";
  } else if (n.IsScalar()) {
    o << scalar_json(n);
  } else {
    o << "null";
  }
}

// The config checked as mbd_node (and dem_node, when run.load is dem) read it; the schema sections
// written back with their defaults.
YAML::Node resolved_json_tree(const std::string& file) {
  auto root = core::ConfigNode::load_file(file);
  const auto run = core::load_run_options(root.child("run"));
  const auto coupling = core::load_coupling_options(root.child_or_empty("coupling"));
  const auto mech = mbd::load_mechanism_params(root.child("mbd"));
  const auto flow_node = root.child_or_empty("flow");
  const auto flow = chamber::load_flow_params(flow_node);
  coupling::ChamberParams dem;
  if (run.load == "dem")
    dem = coupling::load_chamber_params(root.child("dem"), mech.chamber, mech.floating_cone.com_z_m,
                                        mech.fixed_cone.com_z_m, &flow_node);
  else
    root.ignore("dem");  // dem_node's, read when the load is dem
  root.ignore("diagnosis");  // crusher diagnose's uncertain values, checked by diagnose (analysis/param_set.hpp)
  root.finish();
  if (run.load == "flow") chamber::FlowModel(flow, mech.chamber.mantle, mech.chamber.concave);
  if (run.load == "dem" && dem.fines_flow) chamber::FlowModel(dem.fines, mech.chamber.mantle, mech.chamber.concave);
  mbd::validate(mech, run.load == "bed");
  if (run.load == "dem") core::coupling_steps(coupling.dt_s, mech.dt_s);
  YAML::Node out = YAML::Clone(root.raw());
  out["run"] = core::run_schema().write(run);
  out["mbd"] = mbd::mechanism_schema().write(mech);
  out["coupling"] = core::coupling_schema().write(coupling);
  out["flow"] = chamber::flow_schema().write(flow);
  if (run.load == "dem") out["dem"] = core::merged(out["dem"], coupling::chamber_schema().write(dem));  // bpm as given
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string a = argc > 1 ? argv[1] : "";
  if (a == "-h" || a == "--help") return usage(std::cout), 0;
  if (a == "--keys" && argc <= 3) {
    const std::string only = argc == 3 ? argv[2] : "";
    if (keys(only)) return 0;
    std::cerr << "config: no schema section '" << only << "' (accepted: run, mbd, coupling, flow, flow_material, dem, bpm.packing, bpm.bond, bpm.metaparticles)\n";
    return 2;
  }
  if (a == "--json" && argc == 3) {
    try {
      json(std::cout, resolved_json_tree(argv[2]), 0);
      std::cout << "\n";
      return 0;
    } catch (const std::exception& e) {  // ConfigError, and validate()'s std::invalid_argument
      std::cerr << "config: " << e.what() << "\n";
      return 1;
    }
  }
  usage(std::cerr);
  return 2;
}
