#pragma once
// Summary recordings (issue 24): a plant's averaged results per drive speed, as in the paper's Table 5 (mean and
// std of amplitude and power, throughput, specific energy, product sizes), and the same statistics of the model.
//
// YAML:  source: TEXT
//        uncertainty_pct: {QUANTITY: PCT, ...}   standard uncertainty of a plant value; only these are compared
//        rows: [{speed_rpm: R, QUANTITY: VALUE, ...}, ...]
// QUANTITY: the names of `crusher validate` (table5_values in flow_run.hpp): amplitude_x_mm_mean,
// amplitude_x_mm_std, power_kW_mean, power_kW_std, throughput_tph, specific_energy_kWh_per_t, p80_mm,
// passing_12mm_pct, passing_1mm_pct.
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "analysis/param_set.hpp"

namespace analysis {

using Stats = std::map<std::string, double>;

struct SummaryRow {
  double speed_rad_s = 0;
  Stats values;  // plant values given for this speed
};

struct SummaryRecording {
  std::string source, file;
  std::map<std::string, double> uncertainty_pct;  // compared quantities
  std::vector<SummaryRow> rows;
};

const std::vector<std::string>& summary_quantities();
// Throws std::invalid_argument naming the file, the row and the key, and what is accepted.
SummaryRecording read_summary(const std::string& path);
SummaryRecording parse_summary(const std::string& yaml_text, const std::string& name);
std::string summary_yaml(const SummaryRecording& s);  // parse_summary reads it back

// The model's statistics at a drive speed with a parameter set applied.
using SummaryModelFn = std::function<Stats(const ParamSet& p, double speed_rad_s)>;
// The fast mode (mechanism under the chamber flow model, flow_run.hpp) of `config` over `seconds` after `settle_s`;
// the time step divided by the smallest whole n that keeps the config's drive rotation per step (w dt).
SummaryModelFn make_flow_summary_model(const ConfigModel& config, const std::vector<Term>& terms, double seconds,
                                       double settle_s);

}  // namespace analysis
