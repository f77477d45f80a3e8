#include "core/run_config.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/cli_args.hpp"

namespace core {

const Schema<RunOptions>& run_schema() {
  using R = RunOptions;
  static const Schema<RunOptions> s = [] {
    Schema<RunOptions> k;
    k.number("duration_s", "s", 1, 1e-3, 3600, [](R& o) -> double& { return o.duration_s; },
             "simulated time after the start", true)
        .choice("load", {"none", "bed", "flow", "dem"}, [](R& o) -> std::string& { return o.load; },
                "the load on the mantle: idle, equivalent bed, chamber flow model, coupled DEM", true)
        .number("publish_hz", "Hz", 1, 1, 20000, [](R& o) -> double& { return o.publish_hz; },
                "rate of /crusher/test_point and /crusher/drive")
        .number("tf_hz", "Hz", 1, 1, 1000, [](R& o) -> double& { return o.tf_hz; },
                "rate of /tf, the liner markers and the product")
        .number("settle_s", "s", 1, 0, 3600, [](R& o) -> double& { return o.settle_s; },
                "start-up left out of summary.json (shorter than duration_s)")
        .number("warm_start_s", "s", 1, 0, 600, [](R& o) -> double& { return o.warm_start_s; },
                "the mechanism alone before t = 0 (starts at speed, frame settled)")
        .number("checkpoint_every_s", "s", 1, 0, 3600, [](R& o) -> double& { return o.checkpoint_every_s; },
                "coupled and fast (flow) runs: the nodes save their state this often (0: never); `crusher run --resume`")
        .number("coupled.warm_start_s", "s", 1, 0, 600, [](R& o) -> double& { return o.coupled_warm_start_s; },
                "instead of warm_start_s when the load is dem")
        .number("coupled.settle_s", "s", 1, 0, 3600, [](R& o) -> double& { return o.coupled_settle_s; },
                "instead of settle_s when the load is dem")
        .number("coupled.checkpoint_every_s", "s", 1, 0, 3600,
                [](R& o) -> double& { return o.coupled_checkpoint_every_s; },
                "instead of checkpoint_every_s when the load is dem");
    return k;
  }();
  return s;
}

const Schema<CouplingOptions>& coupling_schema() {
  using C = CouplingOptions;
  static const Schema<CouplingOptions> s = [] {
    Schema<CouplingOptions> k;
    k.number("dt_s", "s", 1, 1e-5, 0.05, [](C& o) -> double& { return o.dt_s; },
             "MBD-DEM exchange interval, a whole number of mbd.time_step_s")
        .number("timeout_s", "s", 1, 0.1, 3600, [](C& o) -> double& { return o.timeout_s; },
                "wall time a silent peer is waited for")
        .number("first_timeout_s", "s", 1, 0.1, 7200, [](C& o) -> double& { return o.first_timeout_s; },
                "wall time waited for the peer's first answer (start-up)");
    return k;
  }();
  return s;
}

double checked_duration(const std::string& flag, const std::string& text) {
  for (const auto& e : run_schema().entries())
    if (e.info.name == "duration_s") return parse_number(flag, text, e.info.lo, e.info.hi, "s (run.duration_s)");
  throw std::logic_error("run_schema has no duration_s");
}

RunOptions load_run_options(const ConfigNode& run) {
  RunOptions o;
  run_schema().read(run, o);
  if (o.settle_s >= o.duration_s && o.duration_s > 0.5) {
    run.fail("settle_s", "must be shorter than run.duration_s (" + std::to_string(o.duration_s) + " s)");
  }
  return o;
}

void apply_coupled_overrides(RunOptions& o) {
  if (o.load != "dem") return;
  if (o.coupled_warm_start_s >= 0) o.warm_start_s = o.coupled_warm_start_s;
  if (o.coupled_settle_s >= 0) o.settle_s = o.coupled_settle_s;
  if (o.coupled_checkpoint_every_s >= 0) o.checkpoint_every_s = o.coupled_checkpoint_every_s;
}

CouplingOptions load_coupling_options(const ConfigNode& c) {
  CouplingOptions o;
  coupling_schema().read(c, o);
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
