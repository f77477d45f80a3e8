#include "core/run_config.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace core {

RunOptions load_run_options(const ConfigNode& run) {
  RunOptions o;
  o.duration_s = run.number("duration_s", 1e-3, 3600, "s");
  o.load = run.choice("load", {"none", "bed", "flow", "dem"});
  o.publish_hz = run.number_or("publish_hz", o.publish_hz, 1, 20000, "Hz");
  o.tf_hz = run.number_or("tf_hz", o.tf_hz, 1, 1000, "Hz");
  o.settle_s = run.number_or("settle_s", o.settle_s, 0, 3600, "s");
  o.warm_start_s = run.number_or("warm_start_s", o.warm_start_s, 0, 600, "s");
  o.checkpoint_every_s = run.number_or("checkpoint_every_s", o.checkpoint_every_s, 0, 3600, "s");
  if (o.settle_s >= o.duration_s && o.duration_s > 0.5) {
    run.fail("settle_s", "must be shorter than run.duration_s (" + std::to_string(o.duration_s) + " s)");
  }
  if (run.has("coupled")) {
    auto c = run.child("coupled");
    o.coupled_warm_start_s = c.number_or("warm_start_s", -1, 0, 600, "s");
    o.coupled_settle_s = c.number_or("settle_s", -1, 0, 3600, "s");
  }
  return o;
}

void apply_coupled_overrides(RunOptions& o) {
  if (o.load != "dem") return;
  if (o.coupled_warm_start_s >= 0) o.warm_start_s = o.coupled_warm_start_s;
  if (o.coupled_settle_s >= 0) o.settle_s = o.coupled_settle_s;
}

CouplingOptions load_coupling_options(const ConfigNode& c) {
  CouplingOptions o;
  o.dt_s = c.number_or("dt_s", o.dt_s, 1e-5, 0.05, "s");
  o.timeout_s = c.number_or("timeout_s", o.timeout_s, 0.1, 3600, "s");
  o.first_timeout_s = c.number_or("first_timeout_s", o.first_timeout_s, 0.1, 7200, "s");
  return o;
}

long coupling_steps(double coupling_dt_s, double mech_dt_s) {
  const double ratio = coupling_dt_s / mech_dt_s;
  const long n = std::max(1L, std::lround(ratio));
  if (std::abs(ratio - n) > 1e-6 * n) {
    const long lo = std::max(1L, static_cast<long>(std::floor(ratio)));
    std::ostringstream s;
    s << "coupling.dt_s = " << coupling_dt_s << " s is " << ratio << " steps of mbd.time_step_s = " << mech_dt_s
      << " s; accepted: a whole number of steps, e.g. " << lo * mech_dt_s << " or " << (lo + 1) * mech_dt_s
      << " s (or a time step that divides the interval)";
    throw ConfigError(s.str());
  }
  return n;
}

}  // namespace core
