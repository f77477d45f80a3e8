#pragma once
// Calibration of the flow mode's machine unknowns at 400 rpm ONLY (the 600 rpm case stays a validation), fitted by
// Nelder-Mead to Table 5's EXP 400 rpm amplitude, power and throughput with the chamber flow model as the load, within
// plausible ranges (outside them the cost rises steeply). Three unknowns, by default the vibrator's static moment and
// the concave's radius at the discharge and at the feed opening (the paper gives neither the static moment nor the
// chamber profile or CSS). Accepted names (FlowUnknown):
//   static_moment  kg m, 50-250 (a GYP1200's unbalance)
//   discharge      mm, change of the concave radius at its lower end, within 20 mm of the config's
//   feed           mm, the same at its upper end (the feed opening)
//   bearing_mu     the Coulomb friction of the vibrator's bushing and the spherical support (mbd effects
//                  bearing_friction, turned on; the paper's joint friction, Eq. 1), 0-0.05 (oiled bronze, mixed film)
// Used by `crusher calibrate --flow` and by `validate --rock-spread`, which repeats it for each jackknife material.
#include <functional>
#include <string>
#include <vector>

#include "analysis/flow_run.hpp"

namespace analysis {

// Table 5, EXP 400 rpm: the calibration's targets.
struct FlowCalibrationTargets {
  double amplitude_mm = 5.46, power_kW = 76.8, throughput_tph = 80.8;
};

struct FlowUnknown {
  std::string name;
  double lo, hi, step;  // plausible range and the simplex's first step, in the unit above
};
// The accepted unknowns (above); std::invalid_argument naming an unknown name and the accepted ones.
const std::vector<FlowUnknown>& flow_unknowns();
const FlowUnknown& flow_unknown(const std::string& name);
const std::vector<std::string>& default_flow_unknowns();  // static_moment, discharge, feed
// A config's flow.calibration_unknowns ("a,b,c"; "": the default), each name checked (std::invalid_argument naming it).
std::vector<std::string> parse_flow_unknowns(const std::string& text);

// The unknowns' values x (in the order of `names`) applied to a mechanism; radius changes relative to its own radii
// (the 400 and 600 rpm configs share the chamber). The config's values as x: flow_unknown_start.
mbd::MechanismParams apply_flow_unknowns(const mbd::MechanismParams& mech, const std::vector<double>& x,
                                         const std::vector<std::string>& names = default_flow_unknowns());
std::vector<double> flow_unknown_start(const mbd::MechanismParams& mech, const std::vector<std::string>& names);

struct FlowCalibration {
  std::vector<std::string> names;  // the unknowns
  std::vector<double> x;           // their fitted values (apply_flow_unknowns)
  mbd::MechanismParams mech;       // the 400 rpm mechanism with x applied
  FlowRunResult run;               // at x
  double cost = 0.0;               // sum of squared relative errors of the three targets
  int evaluations = 0;
  double wall_s = 0.0;
};

// Throws std::invalid_argument unless mech400 drives at 400 rpm, or for an unknown name, a repeated one or more than
// three (the protocol: the static moment and at most two more). `progress` (optional) gets a line per run.
FlowCalibration calibrate_flow_machine(const mbd::MechanismParams& mech400, const chamber::FlowParams& flow,
                                       const FlowRunOptions& o, int evaluations,
                                       const std::function<void(const std::string&)>& progress = {},
                                       const FlowCalibrationTargets& targets = {},
                                       const std::vector<std::string>& names = default_flow_unknowns());

}  // namespace analysis
