#pragma once
// The diagnosis's model: the mechanism (src/mbd) with the equivalent material-bed load, one candidate
// effect switched on at a given main-parameter value, the drive set to reproduce a measured mean speed.
#include <string>

#include "analysis/diagnosis.hpp"
#include "analysis/param_set.hpp"
#include "chamber/flow_model.hpp"
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
// Terms for the bearing, drive and chamber modules (bearing_friction mu 0-0.1, drive_efficiency efficiency 0.5-1
// (nominal 1), feed_limited max_feed_tph 20-200 (nominal 200: above both choke-fed rates, off), worn_liners
// setting_increase_mm 0-30, squeeze_flow escape_length_mm 0-15, liner_friction wall_friction 0-0.7), with their plausible ranges; not in mbd_candidates(). The chamber ones act in flow runs
// only (section "flow"); a feed-limited flow run needs a settle of ~30 s (src/chamber/README.md).
std::vector<Term> module_candidates();
// The diagnosis's effect candidates: for time series (the mechanism under the bed load: mbd_candidates() plus
// bearing_friction and drive_efficiency) and for summaries (the fast mode: those plus the chamber's feed_limited,
// worn_liners, squeeze_flow and liner_friction).
std::vector<Term> series_candidates();
std::vector<Term> summary_candidates();
// The omitted-physics modules, one list: config section ("mbd" or "flow"; keys <section>.effects.<name>), name, the
// test file of its law, and whether it is on in given parameters. The names below, validate's list of the laws a model
// turns on and the diagnosis's switches follow it.
struct EffectModule {
  const char* section;
  const char* name;
  const char* test;
  bool (*enabled)(const mbd::MechanismParams&, const chamber::FlowParams&);
};
const std::vector<EffectModule>& effect_modules();
// The mechanism's effects with_effect accepts, comma separated (mbd.effects.<name>).
std::string mbd_effect_names();
// base with `effect` enabled at main-parameter `value` (YAML units, as in EffectSpec); "none" returns
// base with every effect off. Main parameters: joint_friction coulomb_Nm, absorber_nonlinearity cubic_N_per_m3,
// motor_droop droop_rad_s_per_kNm, cardan_misalignment angle_deg, bearing_friction mu, drive_efficiency efficiency
// (the effect's other parameters keep base's values). Throws std::invalid_argument for an unknown effect name.
mbd::MechanismParams with_effect(const mbd::MechanismParams& base, const std::string& effect, double value);
// The chamber flow model's effects (flow.effects.<name>; they act in flow runs only), comma separated, and whether
// `effect` is one of them.
std::string flow_effect_names();
bool is_flow_effect(const std::string& effect);
// base with the chamber effect `effect` enabled at main-parameter `value` (YAML units): feed_limited max_feed_tph,
// worn_liners setting_increase_mm, squeeze_flow escape_length_mm, liner_friction wall_friction (the others keep base's values); "none" or a mechanism effect: every chamber effect
// off. Throws std::invalid_argument for an unknown name. with_effect refuses a chamber effect by name (it has nothing
// to switch on in the mechanism): give the mechanism "none" and the flow parameters the effect.
chamber::FlowParams with_flow_effect(const chamber::FlowParams& base, const std::string& effect, double value);
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
