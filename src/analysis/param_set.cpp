#include "analysis/param_set.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/config.hpp"

namespace analysis {

std::string Term::key() const {
  return kind == Effect ? section + ".effects." + name + "." + parameter : name;
}

std::string to_string(const ParamSet& p) {
  std::ostringstream o;
  o.precision(10);
  bool first = true;
  for (const auto& [k, v] : p) {
    o << (first ? "" : ", ") << k << " = " << v;
    first = false;
  }
  return first ? "unchanged" : o.str();
}

namespace {

// "a.b.c[2]" -> {"a","b","c"}, index 2 (-1: none).
std::vector<std::string> split_key(const std::string& key, int& index) {
  std::string k = key;
  index = -1;
  const auto br = k.find('[');
  if (br != std::string::npos) {
    if (k.back() != ']') throw std::invalid_argument("key '" + key + "': an index is written KEY[i]");
    index = std::stoi(k.substr(br + 1, k.size() - br - 2));
    k = k.substr(0, br);
  }
  std::vector<std::string> parts;
  std::stringstream ss(k);
  for (std::string s; std::getline(ss, s, '.');) {
    if (s.empty()) throw std::invalid_argument("key '" + key + "': empty part");
    parts.push_back(s);
  }
  if (parts.empty()) throw std::invalid_argument("empty key");
  return parts;
}

YAML::Node walk(YAML::Node root, const std::vector<std::string>& parts, const std::string& key) {
  YAML::Node n = root;
  for (const auto& s : parts) {
    if (!n.IsMap() || !n[s]) throw std::invalid_argument("key '" + key + "' is not in the config ('" + s + "' missing)");
    n.reset(n[s]);
  }
  return n;
}

void scale_numbers(YAML::Node n, double f) {
  if (n.IsSequence()) {
    for (std::size_t i = 0; i < n.size(); ++i) scale_numbers(n[i], f);
  } else if (n.IsScalar()) {
    n = n.as<double>() * f;
  } else {
    throw std::invalid_argument("a scaled key must hold a number or a list of numbers");
  }
}

double yaml_number(const YAML::Node& n, const std::string& key) {
  try {
    return n.as<double>();
  } catch (const YAML::Exception&) {
    throw std::invalid_argument("key '" + key + "' does not hold a number");
  }
}

}  // namespace

void set_key(YAML::Node root, const std::string& key, double v, bool scale) {
  int index = -1;
  const auto parts = split_key(key, index);
  YAML::Node n = walk(root, parts, key);
  if (index >= 0) {
    if (!n.IsSequence() || index >= static_cast<int>(n.size()))
      throw std::invalid_argument("key '" + key + "': no element " + std::to_string(index));
    YAML::Node e = n[index];
    if (scale) scale_numbers(e, v); else e = v;
    return;
  }
  if (scale) {
    scale_numbers(n, v);
  } else {
    if (!n.IsScalar()) throw std::invalid_argument("key '" + key + "' holds a list; write KEY[i] or use scale");
    n = v;
  }
}

ConfigModel::ConfigModel(const std::string& file) : file_(file) {
  const auto cfg = core::ConfigNode::load_file(file);
  root_ = YAML::Clone(cfg.raw());
  const auto diag = cfg.child_or_empty("diagnosis");
  if (!diag.has("uncertain")) return;
  const YAML::Node u = diag.raw()["uncertain"];
  const std::string where = "config " + file + ": diagnosis.uncertain";
  if (!u.IsMap())
    throw std::invalid_argument(where + " must map each uncertain key to {range: [low, high], reason: TEXT} or "
                                "{scale: [low, high], reason: TEXT}");
  for (const auto& kv : u) {
    Term t;
    t.kind = Term::Miscalibrated;
    t.name = t.parameter = kv.first.as<std::string>();
    const YAML::Node spec = kv.second;
    const std::string at = where + "." + t.name;
    if (!spec.IsMap()) throw std::invalid_argument(at + ": expected {range: [low, high], reason: TEXT}");
    for (const auto& f : spec) {
      const auto k = f.first.as<std::string>();
      if (k != "range" && k != "scale" && k != "reason" && k != "unit")
        throw std::invalid_argument(at + ": unknown field '" + k + "' (accepted: range or scale, reason, unit)");
    }
    if (spec["range"].IsDefined() == spec["scale"].IsDefined())
      throw std::invalid_argument(at + ": give exactly one of range: [low, high] (the value) or scale: [low, high] "
                                  "(a factor on every element)");
    t.scale = spec["scale"].IsDefined();
    const YAML::Node r = t.scale ? spec["scale"] : spec["range"];
    if (!r.IsSequence() || r.size() != 2)
      throw std::invalid_argument(at + ": the range must be [low, high]");
    t.lo = yaml_number(r[0], t.name);
    t.hi = yaml_number(r[1], t.name);
    t.reason = spec["reason"] ? spec["reason"].as<std::string>() : "";
    if (t.reason.empty()) throw std::invalid_argument(at + ": say why the value is uncertain (reason: TEXT)");
    t.unit = spec["unit"] ? spec["unit"].as<std::string>() : (t.scale ? "factor" : "");
    t.nominal = t.scale ? 1.0 : number_at(t.name);
    if (!(t.lo < t.hi) || t.nominal < t.lo || t.nominal > t.hi) {
      std::ostringstream o;
      o << at << ": the range [" << t.lo << ", " << t.hi << "] must be increasing and hold the config's value "
        << t.nominal;
      throw std::invalid_argument(o.str());
    }
    // The key must be one the loaders accept with a value in the range: try both ends.
    for (double v : {t.lo, t.hi}) {
      try {
        mechanism({{t.name, v}}, {t});
        if (root_["flow"]) flow_run({{t.name, v}}, {t});
      } catch (const std::exception& e) {
        throw std::invalid_argument(at + ": the model refuses the range's end " + std::to_string(v) + ": " + e.what());
      }
    }
    uncertain_.push_back(t);
  }
}

ConfigModel ConfigModel::from_mechanism(const mbd::MechanismParams& p) {
  ConfigModel m;
  m.file_ = "<mechanism>";
  m.root_ = YAML::Load(mbd::to_yaml(p));
  return m;
}

double ConfigModel::number_at(const std::string& key) const {
  int index = -1;
  const auto parts = split_key(key, index);
  YAML::Node n = walk(YAML::Clone(root_), parts, key);
  if (index >= 0) {
    if (!n.IsSequence() || index >= static_cast<int>(n.size()))
      throw std::invalid_argument("key '" + key + "': no element " + std::to_string(index));
    return yaml_number(n[index], key);
  }
  return yaml_number(n, key);
}

YAML::Node ConfigModel::with(const ParamSet& p, const std::vector<Term>& terms) const {
  YAML::Node out = YAML::Clone(root_);
  for (const auto& [name, v] : p) {
    const Term* t = nullptr;
    for (const auto& c : terms)
      if (c.name == name) t = &c;
    if (!t) throw std::invalid_argument("no diagnosis term named '" + name + "'");
    if (t->kind == Term::Effect) {
      YAML::Node sec = out[t->section];
      if (!sec.IsMap()) throw std::invalid_argument("effect " + name + ": the config has no " + t->section + ": section");
      // An effect absent from the config is added with its main parameter (the loader fills the rest).
      YAML::Node e = sec["effects"][name];
      e["enabled"] = v != t->nominal;
      e[t->parameter] = v;
    } else {
      set_key(out, t->key(), v, t->scale);
    }
  }
  return out;
}

// The config with the terms is written here, in the keys' own units: no unit-slip bands (a term searched near its
// nominal 0 evaluates values such as 0.15 mm that a band for typed values refuses); the hard ranges still hold.
mbd::MechanismParams ConfigModel::mechanism(const ParamSet& p, const std::vector<Term>& terms) const {
  core::ConfigNode root(with(p, terms), "", file_);
  root.without_unit_slip_checks();
  return mbd::load_mechanism_params(root.child("mbd"));
}

chamber::FlowRunConfig ConfigModel::flow_run(const ParamSet& p, const std::vector<Term>& terms) const {
  core::ConfigNode root(with(p, terms), "", file_);
  root.without_unit_slip_checks();
  chamber::FlowRunConfig c;
  c.mech = mbd::load_mechanism_params(root.child("mbd"));
  c.flow = chamber::load_flow_params(root.child_or_empty("flow"));
  if (root.has("run")) c.run = core::load_run_options(root.child("run"));
  return c;
}

}  // namespace analysis
