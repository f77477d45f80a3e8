#pragma once
// A fast-mode run without ROS: the mechanism under the chamber flow model (chamber/flow_load.hpp), with Table 5's
// figures over the window after the settle time. Used by the flow benchmark, `validate` and the 400 rpm calibration.
#include <map>
#include <string>
#include <vector>

#include "analysis/run_metrics.hpp"
#include "chamber/flow_model.hpp"
#include "core/run_config.hpp"
#include "mbd/mechanism_params.hpp"

namespace analysis {

struct FlowRunOptions {
  double duration_s = 10.0;  // recorded after the settle time
  double settle_s = 4.0;     // drive ramp, frame transient and the charge's first pass
  double sample_hz = 500;    // test point and power samples (rounded to whole steps)
  double trace_every_s = 0;  // > 0: a line on stderr this often (charge, flows, nutation, power)
};

struct FlowRunResult {
  RunSignals signals;  // t_s from 0 (the start of the run, settle included)
  RunSummary summary;  // over the window; product = the discharge in the window
  double p80_mm = 0, passing_12mm_pct = 0, passing_1mm_pct = 0;
  double product_compressions = 0;  // mean compression events of the rock discharged in the run
  double chamber_kg = 0;            // charge at the end
  double crushing_kW = 0;           // crushing energy booked by the events in the window, per second
  double extrusion_kW = 0;          // the part of crushing_kW spent pressing rock out at the compaction limit
  double extruded_pct = 0;          // share of the window's product pressed out of the bottom nip (the rest fell out)
  double extruded_gap_mm = 0;       // the mean gap it was pressed out through
  // The liners' metal contact (Eq. 11) over the window: the share of steps in contact and the mean normal force over
  // all steps (a mantle rolling on the concave, not held off by the rock, is in contact every step).
  double contact_pct = 0, contact_kN = 0;
  double friction_kW = 0;           // the rock's friction on the liners (flow.effects.liner_friction), per second
  double mean_spin_rpm = 0;         // the mantle's spin about its axis relative to the concave, over the window
  double mean_nutation_deg = 0;     // over the window
  double wall_s = 0;
  struct Band {  // per height band at the end, over its sectors
    double z_m = 0, gap_min_m = 0, gap_max_m = 0, kg = 0, fill = 0, nipped = 0, compressions = 0;
  };
  std::vector<Band> bands;  // bottom first; fill = mass / loose capacity at the mean gap
};

FlowRunResult run_flow(const mbd::MechanismParams& mech, const chamber::FlowParams& flow, const FlowRunOptions& o);

// The window a config's run reports (`crusher run CONFIG`): run.settle_s, then run.duration_s - settle_s; seconds > 0
// or settle >= 0 override them. std::invalid_argument, naming `who`, when the window is empty. What `validate`,
// `calibrate --flow` and `diagnose --summary` run over, so what is calibrated is what is shown.
FlowRunOptions run_window(const core::RunOptions& run, const std::string& who, double seconds = -1, double settle = -1);

// Table 5's quantities of a run, by the names `validate` and summary recordings use (summary_data.hpp):
// amplitude_x_mm_mean/std, power_kW_mean/std, throughput_tph, specific_energy_kWh_per_t, p80_mm, passing_12mm_pct,
// passing_1mm_pct, plus wall_s, compressions, chamber_kg, nutation_deg, crushing_kW. NaN where a value does not exist.
std::map<std::string, double> table5_values(const FlowRunResult& r);

}  // namespace analysis
