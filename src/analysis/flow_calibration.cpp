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
namespace {
std::size_t concave_end(const mbd::MechanismParams& m, bool top) {
  const auto& cz = m.chamber.concave.z;
  const std::size_t bottom = cz.front() < cz.back() ? 0 : cz.size() - 1;
  return top ? cz.size() - 1 - bottom : bottom;
}
}  // namespace

const std::vector<FlowUnknown>& flow_unknowns() {
  static const std::vector<FlowUnknown> u = {{"static_moment", 50.0, 250.0, 20.0},
                                             {"discharge", -20.0, 20.0, 6.0},
                                             {"feed", -20.0, 20.0, 10.0},
                                             {"bearing_mu", 0.0, 0.05, 0.005}};
  return u;
}

const FlowUnknown& flow_unknown(const std::string& name) {
  std::string accepted;
  for (const auto& u : flow_unknowns()) {
    if (u.name == name) return u;
    accepted += (accepted.empty() ? "" : ", ") + u.name;
  }
  throw std::invalid_argument("flow calibration: unknown '" + name + "' is not one of " + accepted);
}

const std::vector<std::string>& default_flow_unknowns() {
  static const std::vector<std::string> d = {"static_moment", "discharge", "feed"};
  return d;
}

std::vector<std::string> parse_flow_unknowns(const std::string& text) {
  if (text.empty()) return default_flow_unknowns();
  std::vector<std::string> names;
  std::size_t from = 0;
  while (true) {
    const std::size_t comma = text.find(',', from);
    std::string item = text.substr(from, comma == std::string::npos ? std::string::npos : comma - from);
    item.erase(0, item.find_first_not_of(' '));
    item.erase(item.find_last_not_of(' ') + 1);
    names.push_back(flow_unknown(item).name);
    if (comma == std::string::npos) return names;
    from = comma + 1;
  }
}

mbd::MechanismParams apply_flow_unknowns(const mbd::MechanismParams& mech, const std::vector<double>& x,
                                         const std::vector<std::string>& names) {
  if (x.size() != names.size())
    throw std::invalid_argument("apply_flow_unknowns: " + std::to_string(names.size()) + " values expected, got " +
                                std::to_string(x.size()));
  auto m = mech;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string& n = flow_unknown(names[i]).name;
    if (n == "static_moment") m.vibrator_static_moment_kg_m = x[i];
    else if (n == "discharge") m.chamber.concave.r[concave_end(m, false)] += x[i] * 1e-3;
    else if (n == "feed") m.chamber.concave.r[concave_end(m, true)] += x[i] * 1e-3;
    else m.effects.bearing_friction.enabled = true, m.effects.bearing_friction.mu = x[i];
  }
  return m;
}

std::vector<double> flow_unknown_start(const mbd::MechanismParams& mech, const std::vector<std::string>& names) {
  std::vector<double> x;
  for (const auto& name : names) {
    const std::string& n = flow_unknown(name).name;
    if (n == "static_moment") x.push_back(mech.vibrator_static_moment_kg_m);
    else if (n == "bearing_mu") x.push_back(mech.effects.bearing_friction.enabled ? mech.effects.bearing_friction.mu : 0.005);
    else x.push_back(0.0);
  }
  return x;
}

FlowCalibration calibrate_flow_machine(const mbd::MechanismParams& mech400, const chamber::FlowParams& flow,
                                       const FlowRunOptions& o, int evaluations,
                                       const std::function<void(const std::string&)>& progress,
                                       const FlowCalibrationTargets& T, const std::vector<std::string>& names) {
  const double rpm = mech400.drive_speed_rad_s * 60 / (2 * M_PI);
  if (std::fabs(rpm - 400) > 1e-6)
    throw std::invalid_argument("the flow calibration is at 400 rpm only (mbd.drive.speed_rpm is " +
                                std::to_string(rpm) + "); 600 rpm is the validation case");
  if (names.empty() || names.size() > 3)
    throw std::invalid_argument("flow calibration: 1 to 3 unknowns (three targets; the static moment and at most two "
                                "more), got " + std::to_string(names.size()));
  std::vector<FlowUnknown> u;
  for (std::size_t i = 0; i < names.size(); ++i) {
    u.push_back(flow_unknown(names[i]));
    for (std::size_t j = 0; j < i; ++j)
      if (names[j] == names[i]) throw std::invalid_argument("flow calibration: unknown '" + names[i] + "' named twice");
  }
  const auto t0 = std::chrono::steady_clock::now();
  int n = 0;
  auto cost = [&](const std::vector<double>& x) {
    double out = 0;
    for (std::size_t i = 0; i < u.size(); ++i)
      out += std::pow(std::max({0.0, u[i].lo - x[i], x[i] - u[i].hi}) / (u[i].hi - u[i].lo), 2);
    if (out > 0) return 10.0 + 100.0 * out;
    const auto m = apply_flow_unknowns(mech400, x, names);
    std::string values;
    for (std::size_t i = 0; i < u.size(); ++i) {
      char b[64];
      std::snprintf(b, sizeof b, "%s%s %.4g", i ? ", " : "", names[i].c_str(), x[i]);
      values += b;
    }
    char line[400];
    try {
      core::validate_chamber_geometry(m.chamber);
      const auto r = run_flow(m, flow, o);
      const auto& s = r.summary;
      const double a = s.amplitude_x_mm.mean / T.amplitude_mm - 1, p = s.power_kW.mean / T.power_kW - 1,
                   q = s.product->throughput_tph / T.throughput_tph - 1, J = a * a + p * p + q * q;
      std::snprintf(line, sizeof line, "calibrate_flow %3d: %s -> %.3f mm, %.2f kW, %.2f t/h (cost %.4g)", ++n,
                    values.c_str(), s.amplitude_x_mm.mean, s.power_kW.mean, s.product->throughput_tph, J);
      if (progress) progress(line);
      return J;
    } catch (const std::exception& e) {
      std::snprintf(line, sizeof line, "calibrate_flow %3d: %s: %s", ++n, values.c_str(), e.what());
      if (progress) progress(line);
      return 1e6;
    }
  };
  std::vector<double> step;
  for (const auto& v : u) step.push_back(v.step);
  const auto best = nelder_mead(cost, flow_unknown_start(mech400, names), step, 1e-4, evaluations);
  FlowCalibration c;
  c.names = names;
  c.x = best.x;
  c.mech = apply_flow_unknowns(mech400, best.x, names);
  c.run = run_flow(c.mech, flow, o);
  c.cost = best.f;
  c.evaluations = best.evaluations;
  c.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return c;
}

}  // namespace analysis
