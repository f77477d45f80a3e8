#pragma once
// The `run:` and `coupling:` sections of a run configuration, shared by mbd_node and dem_node.
#include <string>

#include "core/config.hpp"
#include "core/config_schema.hpp"

namespace core {

struct RunOptions {
  double duration_s = 10.0;   // simulated time after the start
  std::string load = "bed";   // none | bed | flow | dem
  double publish_hz = 500;    // test point and drive samples (every one goes to the bag)
  double tf_hz = 50;          // tf and liner markers
  double settle_s = 1.0;      // start-up transient excluded from summary.json
  double warm_start_s = 0.0;  // mechanism alone (idle for dem runs) before t = 0: starts at speed, frame settled
  double checkpoint_every_s = 0.0;  // coupled and fast runs: save the state this often (simulated s; 0 = never)
  // Optional `run.coupled:` mapping: warm_start_s / settle_s / checkpoint_every_s used instead of the above when the
  // load is dem (a full-machine coupled run costs days per simulated second: it starts at speed, settles briefly and
  // saves its state often; a fast run saves it every second or so, each checkpoint costs it ~10 ms).
  double coupled_warm_start_s = -1, coupled_settle_s = -1, coupled_checkpoint_every_s = -1;  // < 0: not given
};

struct CouplingOptions {
  double dt_s = 1e-3;         // coupling interval (the paper's EDEM-RecurDyn exchange: 1000 Hz, Table 4)
  double timeout_s = 30.0;    // a silent peer stops the run after this wall time
  double first_timeout_s = 300.0;  // first answer (peer start-up: packing, meshing)
};

// The keys of `run:` and `coupling:` (config_schema.hpp); the loaders below read through them.
const Schema<RunOptions>& run_schema();
const Schema<CouplingOptions>& coupling_schema();

RunOptions load_run_options(const ConfigNode& run);            // the `run:` mapping
// A duration given outside the config (`crusher run --duration`, the nodes' ~duration), as text: a number of
// seconds in run.duration_s's range, else std::invalid_argument naming `flag`, the value and the range.
double checked_duration(const std::string& flag, const std::string& text);
// After any override of `load`: a dem run takes run.coupled's warm_start_s, settle_s and checkpoint_every_s where given.
void apply_coupled_overrides(RunOptions& o);
CouplingOptions load_coupling_options(const ConfigNode& coupling);  // the `coupling:` mapping (may be empty)
// Mechanism steps per coupling interval: coupling.dt_s must be a whole number (>= 1) of mbd.time_step_s, to 1e-6;
// else throws ConfigError naming both keys, the ratio and the nearest accepted intervals.
long coupling_steps(double coupling_dt_s, double mech_dt_s);

}  // namespace core
