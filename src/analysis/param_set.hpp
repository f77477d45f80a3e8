#pragma once
// The diagnosis's terms and the model they change (issue 24): an omitted-physics effect (a module of the model
// switched on at its main parameter) or an uncertain value of the config refitted (a miscalibration).
// A parameter set is applied to the run config as YAML key overrides, so any key of the schema can be a term.
#include <yaml-cpp/yaml.h>

#include <map>
#include <string>
#include <vector>

#include "chamber/flow_config.hpp"
#include "mbd/mechanism_params.hpp"

namespace analysis {

struct Term {
  enum Kind { Effect, Miscalibrated };
  Kind kind = Effect;
  std::string name;       // effect name (mbd.effects.<name>) or the config key refitted
  std::string parameter;  // effect: its main parameter's key under the effect; miscalibration: the key
  std::string unit;
  double lo = 0, hi = 1;  // search range, in the key's YAML unit (a scale factor for `scale` terms)
  double nominal = 0;     // the value at which the model is unchanged (effects: 0)
  bool scale = false;     // the value multiplies every element of the key (a list, e.g. absorber stiffness)
  std::string reason;     // why the value is uncertain (from the config)
  std::string section = "mbd";  // effects: the config section holding `effects.<name>` (mbd or flow)
  std::string key() const;  // the full YAML key the value is written to
};

// Term name -> value (the term's unit). A term left out stands at its nominal value.
using ParamSet = std::map<std::string, double>;
std::string to_string(const ParamSet& p);

// A run config (its `base:` chain resolved), re-read with a parameter set applied: the uncertain values and
// the candidate effects of the diagnosis.
class ConfigModel {
 public:
  explicit ConfigModel(const std::string& file);
  static ConfigModel from_mechanism(const mbd::MechanismParams& p);  // an mbd-only config (tests, tools)

  // The terms the config declares uncertain (`diagnosis.uncertain`), checked against the config's keys.
  const std::vector<Term>& uncertain() const { return uncertain_; }
  // The config with `p` applied (terms looked up in `terms`); throws naming an unknown term.
  YAML::Node with(const ParamSet& p, const std::vector<Term>& terms) const;
  mbd::MechanismParams mechanism(const ParamSet& p, const std::vector<Term>& terms) const;
  chamber::FlowRunConfig flow_run(const ParamSet& p, const std::vector<Term>& terms) const;
  const std::string& file() const { return file_; }
  const YAML::Node& root() const { return root_; }
  // The number at a key (`a.b.c` or `a.b.c[i]`) of the resolved config; throws naming the key if absent.
  double number_at(const std::string& key) const;

 private:
  ConfigModel() = default;
  std::string file_;
  YAML::Node root_;
  std::vector<Term> uncertain_;
};

// Sets `key` (`a.b.c`, `a.b.c[i]`) in `root` to v (or multiplies every number under it by v when scale).
void set_key(YAML::Node root, const std::string& key, double v, bool scale = false);

}  // namespace analysis
