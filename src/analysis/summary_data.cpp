#include "analysis/summary_data.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "analysis/flow_run.hpp"
#include "core/units.hpp"

namespace analysis {

const std::vector<std::string>& summary_quantities() {
  static const std::vector<std::string> q = {"amplitude_x_mm_mean", "amplitude_x_mm_std", "power_kW_mean",
                                             "power_kW_std",        "throughput_tph",     "specific_energy_kWh_per_t",
                                             "p80_mm",              "passing_12mm_pct",   "passing_1mm_pct"};
  return q;
}

namespace {
std::string accepted() {
  std::string s;
  for (const auto& q : summary_quantities()) s += (s.empty() ? "" : ", ") + q;
  return s;
}
bool known(const std::string& q) {
  const auto& all = summary_quantities();
  return std::find(all.begin(), all.end(), q) != all.end();
}
double number(const YAML::Node& n, const std::string& where) {
  double v = 0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    throw std::invalid_argument(where + ": not a number");
  }
  if (!std::isfinite(v)) throw std::invalid_argument(where + ": not a finite number");
  return v;
}
}  // namespace

SummaryRecording parse_summary(const std::string& text, const std::string& name) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument(name + ": not valid YAML: " + e.what());
  }
  if (!root.IsMap()) throw std::invalid_argument(name + ": expected a mapping with source, uncertainty_pct and rows");
  SummaryRecording s;
  s.file = name;
  for (const auto& kv : root) {
    const auto k = kv.first.as<std::string>();
    if (k != "source" && k != "uncertainty_pct" && k != "rows")
      throw std::invalid_argument(name + ": unknown key '" + k + "' (accepted: source, uncertainty_pct, rows)");
  }
  if (!root["source"] || root["source"].as<std::string>().empty())
    throw std::invalid_argument(name + ": 'source' must say where the values come from");
  s.source = root["source"].as<std::string>();
  const YAML::Node u = root["uncertainty_pct"];
  if (!u || !u.IsMap() || u.size() == 0)
    throw std::invalid_argument(name + ": 'uncertainty_pct' must map each compared quantity to the standard "
                                "uncertainty of a plant value in percent (accepted quantities: " + accepted() + ")");
  for (const auto& kv : u) {
    const auto q = kv.first.as<std::string>();
    if (!known(q)) throw std::invalid_argument(name + ": uncertainty_pct." + q + ": unknown quantity (accepted: " + accepted() + ")");
    const double pct = number(kv.second, name + ": uncertainty_pct." + q);
    if (!(pct > 0 && pct <= 100)) throw std::invalid_argument(name + ": uncertainty_pct." + q + " must be in (0, 100]");
    s.uncertainty_pct[q] = pct;
  }
  const YAML::Node rows = root["rows"];
  if (!rows || !rows.IsSequence() || rows.size() == 0)
    throw std::invalid_argument(name + ": 'rows' must list one mapping per drive speed (speed_rpm and the values)");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::string at = name + ": rows[" + std::to_string(i) + "]";
    if (!rows[i].IsMap()) throw std::invalid_argument(at + ": expected a mapping (speed_rpm: R, QUANTITY: VALUE)");
    SummaryRow r;
    bool has_speed = false;
    for (const auto& kv : rows[i]) {
      const auto k = kv.first.as<std::string>();
      if (k == "speed_rpm") {
        const double rpm = number(kv.second, at + ".speed_rpm");
        if (!(rpm > 0 && rpm < 5000)) throw std::invalid_argument(at + ".speed_rpm must be in (0, 5000)");
        r.speed_rad_s = rpm * core::units::rpm;
        has_speed = true;
      } else if (known(k)) {
        r.values[k] = number(kv.second, at + "." + k);
      } else {
        throw std::invalid_argument(at + ": unknown key '" + k + "' (accepted: speed_rpm, " + accepted() + ")");
      }
    }
    if (!has_speed) throw std::invalid_argument(at + ": speed_rpm is missing");
    bool compared = false;
    for (const auto& [q, pct] : s.uncertainty_pct) compared |= r.values.count(q) > 0;
    if (!compared) throw std::invalid_argument(at + ": none of the compared quantities (uncertainty_pct) is given");
    for (const auto& prev : s.rows)
      if (std::abs(prev.speed_rad_s - r.speed_rad_s) < 1e-9) throw std::invalid_argument(at + ": a second row for the same speed");
    s.rows.push_back(r);
  }
  return s;
}

SummaryRecording read_summary(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(path + ": cannot open the summary recording");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_summary(ss.str(), path);
}

std::string summary_yaml(const SummaryRecording& s) {
  YAML::Node root;
  root["source"] = s.source;
  for (const auto& [q, pct] : s.uncertainty_pct) root["uncertainty_pct"][q] = pct;
  for (const auto& r : s.rows) {
    YAML::Node row;
    row["speed_rpm"] = r.speed_rad_s / core::units::rpm;
    for (const auto& [q, v] : r.values) row[q] = v;
    root["rows"].push_back(row);
  }
  YAML::Emitter e;
  e.SetDoublePrecision(12);
  e << root;
  return std::string(e.c_str()) + "\n";
}

SummaryModelFn make_flow_summary_model(const ConfigModel& config, const std::vector<Term>& terms, double seconds,
                                       double settle_s) {
  return [config, terms, seconds, settle_s](const ParamSet& p, double speed) {
    auto c = config.flow_run(p, terms);
    // Whole steps per base step, keeping the base config's w dt (the sweep's rule: 0.5 ms at 600 rpm for 1 ms at 400).
    const double wdt = c.mech.drive_speed_rad_s * c.mech.dt_s;
    const int n = std::max(1, static_cast<int>(std::ceil(speed * c.mech.dt_s / wdt - 1e-9)));
    c.mech.dt_s /= n;
    c.mech.drive_speed_rad_s = speed;
    FlowRunOptions o;
    o.duration_s = seconds;
    o.settle_s = settle_s;
    // A feeder below the choke rate: the prefilled charge drains for tens of seconds first (src/chamber/README.md).
    if (c.flow.effects.feed_limited.enabled) o.settle_s = std::max(settle_s, 30.0);
    return table5_values(run_flow(c.mech, c.flow, o));
  };
}

}  // namespace analysis
