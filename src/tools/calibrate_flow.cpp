// Calibration of the flow mode's machine unknowns at 400 rpm ONLY (the 600 rpm case stays a validation): the
// vibrator's static moment and the concave's radius at the discharge and at the feed opening (the paper gives
// neither the static moment nor the chamber profile or CSS), fitted by Nelder-Mead to Table 5's EXP 400 rpm
// amplitude, power and throughput with the chamber flow model as the load, within plausible ranges: static moment
// 50-250 kg m, each radius within 20 mm of the config's.
//   calibrate_flow --config launch_free_configs/gyp1200_400rpm.yaml --out DIR [--evaluations N] [--seconds S]
//                  [--settle S]
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

#include "analysis/flow_run.hpp"
#include "analysis/optimise.hpp"
#include "chamber/flow_config.hpp"
#include "core/cli_args.hpp"
#include "core/run_config.hpp"

namespace {
// Table 5, EXP 400 rpm.
constexpr double kAmp = 5.46, kPower = 76.8, kTph = 80.8;

void usage() {
  std::cerr << "usage: calibrate_flow --config CONFIG_400RPM.yaml --out DIR [--evaluations N] [--seconds S] "
               "[--settle S]\n";
}
}  // namespace

int main(int argc, char** argv) {
  std::string config, out;
  int evals = 60;
  double seconds = 4, settle = 4;
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
    const double rpm = mech0.drive_speed_rad_s * 60 / (2 * M_PI);
    if (std::fabs(rpm - 400) > 1e-6)
      throw std::invalid_argument("calibrate_flow calibrates at 400 rpm only (mbd.drive.speed_rpm is " +
                                  std::to_string(rpm) + "); 600 rpm is the validation case");
    ::mkdir(out.c_str(), 0755);
    const auto& cz = mech0.chamber.concave.z;
    const std::size_t bottom = cz.front() < cz.back() ? 0 : cz.size() - 1, top = cz.size() - 1 - bottom;
    // x = (static moment kg m, concave radius change at the discharge mm, at the feed opening mm)
    auto apply = [&](const std::vector<double>& x) {
      auto m = mech0;
      m.vibrator_static_moment_kg_m = x[0];
      m.chamber.concave.r[bottom] += x[1] * 1e-3;
      m.chamber.concave.r[top] += x[2] * 1e-3;
      return m;
    };
    analysis::FlowRunOptions o;
    o.duration_s = seconds;
    o.settle_s = settle;
    const auto t0 = std::chrono::steady_clock::now();
    int n = 0;
    // Plausible ranges (a GYP1200's unbalance; a chamber that still takes -50 mm feed and discharges a ~10 mm
    // product): outside them the cost rises steeply, so the simplex stays inside.
    const double lo[] = {50.0, -20.0, -20.0}, hi[] = {250.0, 20.0, 20.0};
    auto cost = [&](const std::vector<double>& x) {
      double out = 0;
      for (int i = 0; i < 3; ++i) out += std::pow(std::max({0.0, lo[i] - x[i], x[i] - hi[i]}) / (hi[i] - lo[i]), 2);
      if (out > 0) return 10.0 + 100.0 * out;
      const auto m = apply(x);
      try {
        core::validate_chamber_geometry(m.chamber);
        const auto r = analysis::run_flow(m, flow, o);
        const auto& s = r.summary;
        const double a = s.amplitude_x_mm.mean / kAmp - 1, p = s.power_kW.mean / kPower - 1,
                     q = s.product->throughput_tph / kTph - 1, J = a * a + p * p + q * q;
        std::fprintf(stderr, "calibrate_flow %3d: static moment %.2f kg m, discharge %+.2f mm, feed %+.2f mm -> %.3f mm, "
                     "%.2f kW, %.2f t/h (cost %.4g)\n", ++n, x[0], x[1], x[2], s.amplitude_x_mm.mean, s.power_kW.mean,
                     s.product->throughput_tph, J);
        return J;
      } catch (const std::exception& e) {
        std::fprintf(stderr, "calibrate_flow %3d: %s\n", ++n, e.what());
        return 1e6;
      }
    };
    const auto best = analysis::nelder_mead(cost, {mech0.vibrator_static_moment_kg_m, 0.0, 0.0}, {20.0, 6.0, 10.0},
                                            1e-4, evals);
    const auto mech = apply(best.x);
    const auto r = analysis::run_flow(mech, flow, o);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto& s = r.summary;
    std::ofstream j(out + "/calibration_flow.json");
    j.precision(8);
    j << "{\n  \"config\": \"" << config << "\",\n  \"calibrated_at_rpm\": 400,\n"
      << "  \"targets\": {\"amplitude_x_mm\": " << kAmp << ", \"power_kW\": " << kPower << ", \"throughput_tph\": " << kTph
      << "},\n  \"parameters\": {\n"
      << "    \"mbd.vibrator.static_moment_kg_m\": " << best.x[0] << ",\n"
      << "    \"mbd.chamber.concave_r_mm\": [" << mech.chamber.concave.r.front() * 1e3 << ", "
      << mech.chamber.concave.r.back() * 1e3 << "]\n  },\n"
      << "  \"reached\": {\"amplitude_x_mm\": " << s.amplitude_x_mm.mean << ", \"power_kW\": " << s.power_kW.mean
      << ", \"throughput_tph\": " << s.product->throughput_tph << ", \"specific_energy_kWh_per_t\": "
      << (s.product->throughput_tph > 0 ? std::to_string(s.power_kW.mean / s.product->throughput_tph) : "null")
      << ", \"p80_mm\": " << (r.p80_mm > 0 ? std::to_string(r.p80_mm) : "null") << "},\n"
      << "  \"cost\": " << best.f << ",\n  \"evaluations\": " << best.evaluations << ",\n  \"wall_s\": " << wall << "\n}\n";
    std::ofstream(out + "/calibrated_mbd.yaml") << mbd::to_yaml(mech);
    std::printf("calibrated at 400 rpm in %d runs (%.0f s): static moment %.2f kg m, concave_r_mm [%.1f, %.1f]\n",
                best.evaluations, wall, best.x[0], mech.chamber.concave.r.front() * 1e3,
                mech.chamber.concave.r.back() * 1e3);
    std::printf("reached: amplitude %.3f mm (%.2f), power %.2f kW (%.1f), throughput %.2f t/h (%.1f)\n",
                s.amplitude_x_mm.mean, kAmp, s.power_kW.mean, kPower, s.product->throughput_tph, kTph);
  } catch (const std::exception& e) {
    std::cerr << "calibrate_flow: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
