#pragma once
// The diagnosis's model: the mechanism (src/mbd) with the equivalent material-bed load, one candidate
// effect switched on at a given main-parameter value, the drive set to reproduce a measured mean speed.
#include <string>

#include "analysis/diagnosis.hpp"
#include "analysis/param_set.hpp"
#include "mbd/mechanism_params.hpp"

namespace analysis {

struct MbdModelOptions {
  std::string load = "bed";  // fast MBD-only mode (DESIGN.md: `bed`)
  double settle_s = 4.0;     // discarded start (drive ramp + absorber transient)
  double sample_hz = 1000;
};

// Candidate effects and the search range of each main parameter, in the units of the YAML keys
// mbd.effects.<name>.<parameter>.
std::vector<Term> mbd_candidates();
// base with `effect` enabled at main-parameter `value` (YAML units, as in EffectSpec); "none" returns
// base with every effect off. Throws std::invalid_argument for an unknown effect name.
mbd::MechanismParams with_effect(const mbd::MechanismParams& base, const std::string& effect, double value);
// base driven at `speed_rad_s`, the time step scaled to keep the drive rotation per step (w dt) of the
// base config (the 400 and 600 rpm configs differ so), never above the base step.
mbd::MechanismParams at_speed(const mbd::MechanismParams& base, double speed_rad_s);
// ModelFn over mbd::simulate, drive set point = the requested speed (with motor droop the simulated
// speed falls below it, speed = w0 - droop torque, as on the plant). The parameter set is applied to the
// config (ConfigModel::with): `terms` names what each entry is (candidates and uncertain values).
ModelFn make_mbd_model(const ConfigModel& config, const std::vector<Term>& terms, const MbdModelOptions& opt = {});
// The same over a mechanism without a config file: the effects of mbd_candidates() only.
ModelFn make_mbd_model(const mbd::MechanismParams& base, const MbdModelOptions& opt = {});

}  // namespace analysis
