// The flow mode's 400 rpm calibration (flow_calibration.hpp).
#include "analysis/flow_calibration.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "analysis/optimise.hpp"
#include "core/run_config.hpp"

namespace analysis {

mbd::MechanismParams apply_flow_unknowns(const mbd::MechanismParams& mech, const std::vector<double>& x) {
  if (x.size() != 3) throw std::invalid_argument("apply_flow_unknowns: 3 values (static moment, discharge, feed)");
  auto m = mech;
  const auto& cz = m.chamber.concave.z;
  const std::size_t bottom = cz.front() < cz.back() ? 0 : cz.size() - 1, top = cz.size() - 1 - bottom;
  m.vibrator_static_moment_kg_m = x[0];
  m.chamber.concave.r[bottom] += x[1] * 1e-3;
  m.chamber.concave.r[top] += x[2] * 1e-3;
  return m;
}

FlowCalibration calibrate_flow_machine(const mbd::MechanismParams& mech400, const chamber::FlowParams& flow,
                                       const FlowRunOptions& o, int evaluations,
                                       const std::function<void(const std::string&)>& progress,
                                       const FlowCalibrationTargets& T) {
  const double rpm = mech400.drive_speed_rad_s * 60 / (2 * M_PI);
  if (std::fabs(rpm - 400) > 1e-6)
    throw std::invalid_argument("the flow calibration is at 400 rpm only (mbd.drive.speed_rpm is " +
                                std::to_string(rpm) + "); 600 rpm is the validation case");
  const auto t0 = std::chrono::steady_clock::now();
  int n = 0;
  // Plausible ranges (a GYP1200's unbalance; a chamber that still takes -50 mm feed and discharges a ~10 mm
  // product): outside them the cost rises steeply, so the simplex stays inside.
  const double lo[] = {50.0, -20.0, -20.0}, hi[] = {250.0, 20.0, 20.0};
  auto cost = [&](const std::vector<double>& x) {
    double out = 0;
    for (int i = 0; i < 3; ++i) out += std::pow(std::max({0.0, lo[i] - x[i], x[i] - hi[i]}) / (hi[i] - lo[i]), 2);
    if (out > 0) return 10.0 + 100.0 * out;
    const auto m = apply_flow_unknowns(mech400, x);
    char line[320];
    try {
      core::validate_chamber_geometry(m.chamber);
      const auto r = run_flow(m, flow, o);
      const auto& s = r.summary;
      const double a = s.amplitude_x_mm.mean / T.amplitude_mm - 1, p = s.power_kW.mean / T.power_kW - 1,
                   q = s.product->throughput_tph / T.throughput_tph - 1, J = a * a + p * p + q * q;
      std::snprintf(line, sizeof line, "calibrate_flow %3d: static moment %.2f kg m, discharge %+.2f mm, feed %+.2f mm "
                    "-> %.3f mm, %.2f kW, %.2f t/h (cost %.4g)", ++n, x[0], x[1], x[2], s.amplitude_x_mm.mean,
                    s.power_kW.mean, s.product->throughput_tph, J);
      if (progress) progress(line);
      return J;
    } catch (const std::exception& e) {
      std::snprintf(line, sizeof line, "calibrate_flow %3d: %s", ++n, e.what());
      if (progress) progress(line);
      return 1e6;
    }
  };
  const auto best = nelder_mead(cost, {mech400.vibrator_static_moment_kg_m, 0.0, 0.0}, {20.0, 6.0, 10.0}, 1e-4,
                                evaluations);
  FlowCalibration c;
  c.x = best.x;
  c.mech = apply_flow_unknowns(mech400, best.x);
  c.run = run_flow(c.mech, flow, o);
  c.cost = best.f;
  c.evaluations = best.evaluations;
  c.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return c;
}

}  // namespace analysis
