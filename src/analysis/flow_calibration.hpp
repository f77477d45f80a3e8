#pragma once
// Calibration of the flow mode's machine unknowns at 400 rpm ONLY (the 600 rpm case stays a validation): the
// vibrator's static moment and the concave's radius at the discharge and at the feed opening (the paper gives neither
// the static moment nor the chamber profile or CSS), fitted by Nelder-Mead to Table 5's EXP 400 rpm amplitude, power
// and throughput with the chamber flow model as the load, within plausible ranges: static moment 50-250 kg m, each
// radius within 20 mm of the config's. Used by `crusher calibrate --flow` and by `validate --rock-spread`, which
// repeats the calibration for each jackknife material.
#include <functional>
#include <string>
#include <vector>

#include "analysis/flow_run.hpp"

namespace analysis {

// Table 5, EXP 400 rpm: the calibration's targets.
struct FlowCalibrationTargets {
  double amplitude_mm = 5.46, power_kW = 76.8, throughput_tph = 80.8;
};

// x = (static moment kg m, concave radius change at the discharge mm, at the feed opening mm), applied to a mechanism
// (the changes relative to its own radii: the 400 and 600 rpm configs share the chamber).
mbd::MechanismParams apply_flow_unknowns(const mbd::MechanismParams& mech, const std::vector<double>& x);

struct FlowCalibration {
  std::vector<double> x;       // the fitted unknowns (apply_flow_unknowns)
  mbd::MechanismParams mech;   // the 400 rpm mechanism with x applied
  FlowRunResult run;           // at x
  double cost = 0.0;           // sum of squared relative errors of the three targets
  int evaluations = 0;
  double wall_s = 0.0;
};

// Throws std::invalid_argument unless mech400 drives at 400 rpm. `progress` (optional) gets a line per evaluation.
FlowCalibration calibrate_flow_machine(const mbd::MechanismParams& mech400, const chamber::FlowParams& flow,
                                       const FlowRunOptions& o, int evaluations,
                                       const std::function<void(const std::string&)>& progress = {},
                                       const FlowCalibrationTargets& targets = {});

}  // namespace analysis
