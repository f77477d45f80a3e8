// Calibration of the flow mode's machine unknowns at 400 rpm ONLY (analysis/flow_calibration.hpp: by default the
// vibrator's static moment and the concave's radius at the discharge and at the feed opening; --unknowns names up to
// three of static_moment, discharge, feed, bearing_mu), against Table 5's EXP 400 rpm amplitude, power and throughput.
//   calibrate_flow --config launch_free_configs/gyp1200_400rpm.yaml --out DIR [--evaluations N] [--seconds S]
//                  [--settle S]
// The figures fitted are those `crusher run CONFIG` and `crusher validate` report: over the config's run window
// (--settle default run.settle_s, --seconds run.duration_s - settle_s), so what is calibrated is what is shown; a
// machine whose motion is irregular needs that window long (src/chamber/README.md: 36 s at 400 rpm).
// Writes DIR/calibration_flow.json (fitted values, what each sets, the figures reached) and DIR/calibrated_mbd.yaml
// (the mbd: section with the fitted values).
#include <sys/stat.h>

#include <chrono>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "analysis/flow_run.hpp"
#include "analysis/flow_calibration.hpp"
#include "chamber/flow_config.hpp"
#include "core/cli_args.hpp"
#include "core/run_config.hpp"

namespace {
const analysis::FlowCalibrationTargets kTargets;
const double kAmp = kTargets.amplitude_mm, kPower = kTargets.power_kW, kTph = kTargets.throughput_tph;

void usage() {
  std::cerr << "usage: calibrate_flow --config CONFIG_400RPM.yaml --out DIR [--evaluations N] [--seconds S] "
               "[--settle S] [--unknowns NAME,NAME,NAME]\n  --unknowns: up to three of static_moment, discharge, feed, "
               "bearing_mu (default: the config's flow.calibration_unknowns)\n";
}
}  // namespace

int main(int argc, char** argv) {
  std::string config, out;
  int evals = 60;
  std::vector<std::string> unknowns;  // empty: the config's flow.calibration_unknowns
  double seconds = -1, settle = -1;  // < 0: the config's run window
  try {
    core::CliArgs args(argc, argv);
    while (args.next()) {
      const std::string a = args.flag();
      if (a == "-h" || a == "--help") return usage(), 0;
      else if (a == "--config") config = args.value();
      else if (a == "--out") out = args.value();
      else if (a == "--evaluations") evals = static_cast<int>(args.number(4, 10000));
      else if (a == "--seconds") seconds = args.number(0.5, 1000);
      else if (a == "--settle") settle = args.number(0, 1000);
      else if (a == "--unknowns") {
        const std::string v = args.value();  // "": the config's, as without the flag
        unknowns = v.empty() ? std::vector<std::string>{} : analysis::parse_flow_unknowns(v);
      }
      else throw std::invalid_argument("unknown argument '" + a + "'");
    }
    if (config.empty() || out.empty()) throw std::invalid_argument("--config and --out are required");
  } catch (const std::exception& e) {
    std::cerr << "calibrate_flow: " << e.what() << "\n";
    usage();
    return 2;
  }
  try {
    const auto cfg = chamber::load_flow_run_config(config);
    const auto& mech0 = cfg.mech;
    const auto& flow = cfg.flow;
    const analysis::FlowRunOptions o = analysis::run_window(cfg.run, config, seconds, settle);
    if (unknowns.empty()) unknowns = analysis::parse_flow_unknowns(flow.calibration_unknowns);
    const auto cal = analysis::calibrate_flow_machine(
        mech0, flow, o, evals, [](const std::string& l) { std::fprintf(stderr, "%s\n", l.c_str()); }, {}, unknowns);
    ::mkdir(out.c_str(), 0755);
    const auto& mech = cal.mech;
    const auto& r = cal.run;
    const double wall = cal.wall_s;
    const auto& s = r.summary;
    std::ofstream j(out + "/calibration_flow.json");
    j.precision(8);
    j << "{\n  \"config\": \"" << config << "\",\n  \"calibrated_at_rpm\": 400,\n"
      << "  \"targets\": {\"amplitude_x_mm\": " << kAmp << ", \"power_kW\": " << kPower << ", \"throughput_tph\": " << kTph
      << "},\n  \"parameters\": {\n"
      << "    \"mbd.vibrator.static_moment_kg_m\": " << mech.vibrator_static_moment_kg_m << ",\n"
      << "    \"mbd.chamber.concave_r_mm\": [" << mech.chamber.concave.r.front() * 1e3 << ", "
      << mech.chamber.concave.r.back() * 1e3 << "],\n"
      << "    \"mbd.effects.bearing_friction.mu\": "
      << (mech.effects.bearing_friction.enabled ? std::to_string(mech.effects.bearing_friction.mu) : "null")
      << "\n  },\n  \"unknowns\": [";
    for (std::size_t i = 0; i < unknowns.size(); ++i) j << (i ? ", " : "") << "\"" << unknowns[i] << "\"";
    j << "],\n"
      << "  \"reached\": {\"amplitude_x_mm\": " << s.amplitude_x_mm.mean << ", \"power_kW\": " << s.power_kW.mean
      << ", \"throughput_tph\": " << s.product->throughput_tph << ", \"specific_energy_kWh_per_t\": "
      << (s.product->throughput_tph > 0 ? std::to_string(s.power_kW.mean / s.product->throughput_tph) : "null")
      << ", \"p80_mm\": " << (r.p80_mm > 0 ? std::to_string(r.p80_mm) : "null") << "},\n"
      << "  \"cost\": " << cal.cost << ",\n  \"evaluations\": " << cal.evaluations << ",\n  \"wall_s\": " << wall << "\n}\n";
    std::ofstream(out + "/calibrated_mbd.yaml") << mbd::to_yaml(mech);
    std::printf("calibrated at 400 rpm in %d runs (%.0f s): static moment %.2f kg m, concave_r_mm [%.1f, %.1f]%s\n",
                cal.evaluations, wall, mech.vibrator_static_moment_kg_m, mech.chamber.concave.r.front() * 1e3,
                mech.chamber.concave.r.back() * 1e3,
                mech.effects.bearing_friction.enabled
                    ? (", bearing_friction mu " + std::to_string(mech.effects.bearing_friction.mu)).c_str() : "");
    std::printf("reached: amplitude %.3f mm (%.2f), power %.2f kW (%.1f), throughput %.2f t/h (%.1f)\n",
                s.amplitude_x_mm.mean, kAmp, s.power_kW.mean, kPower, s.product->throughput_tph, kTph);
  } catch (const std::exception& e) {
    std::cerr << "calibrate_flow: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
