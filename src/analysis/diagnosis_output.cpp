// diagnosis.json and report.md writers for the mismatch diagnosis.
#include <cmath>
#include <iomanip>
#include <sstream>

#include "analysis/json_text.hpp"
#include "analysis/diagnosis.hpp"
#include "analysis/inputs_report.hpp"

namespace analysis {
namespace {

using json::esc;
using json::num;
std::string arr(const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + num(v[i]);
  return s + "]";
}

void comparison_json(std::ostringstream& o, const Comparison& c) {
  o << "{\"dataset\": \"" << esc(c.label) << "\", \"nrmse\": " << num(c.nrmse_overall)
    << ", \"fit_percent\": " << num(c.fit_percent_overall) << ", \"time_offset_s\": " << num(c.alignment.tau_s)
    << ", \"gain\": " << num(c.alignment.gain) << ", \"period_s\": " << num(c.alignment.period_s)
    << ", \"window_t0_s\": " << arr(c.window_t0_s) << ", \"channels\": {";
  bool first_ch = true;
  for (int ch = 0; ch < kNumChannels; ++ch) {
    const auto& e = c.ch[ch];
    if (!e.compared) continue;  // not recorded or a set point: see "inputs"
    o << (first_ch ? "" : ", ") << "\"" << kChannelNames[ch] << "\": {\"nrmse\": " << num(e.nrmse)
      << ", \"fit_percent\": " << num(e.fit_percent) << ", \"noise_std\": " << num(std::sqrt(e.sigma2))
      << ", \"chi2\": " << num(e.chi2) << ", \"chi2_dof\": " << e.dof_chi2
      << ", \"order_nrmse\": " << arr(e.order_nrmse)
      << ", \"order_residual_power\": " << arr(e.order_residual_power)
      << ", \"order_recording_power\": " << arr(e.order_recording_power)
      << ", \"window_rms_over_noise\": " << arr(e.window_rms_over_sigma) << "}";
    first_ch = false;
  }
  o << "}}";
}
void comparisons_json(std::ostringstream& o, const std::vector<Comparison>& cs) {
  o << "[";
  for (std::size_t i = 0; i < cs.size(); ++i) {
    if (i) o << ", ";
    comparison_json(o, cs[i]);
  }
  o << "]";
}
std::vector<const Dataset*> datasets_of(const DiagnosisResult& r) {
  std::vector<const Dataset*> out;
  for (const auto* set : {&r.train, &r.heldout})
    for (const auto& d : *set) out.push_back(&d);
  return out;
}
double mean_nrmse(const std::vector<Comparison>& cs) {
  double s = 0;
  for (const auto& c : cs) s += c.nrmse_overall;
  return cs.empty() ? 0.0 : s / cs.size();
}

}  // namespace

std::string diagnosis_json(const DiagnosisResult& r) {
  std::ostringstream o;
  o << "{\n  \"effect\": \"" << r.effect << "\",\n  \"reason\": \"" << esc(r.reason) << "\",\n";
  o << "  \"candidates_considered\": [";
  for (std::size_t i = 0; i < r.candidates.size(); ++i) o << (i ? ", " : "") << "\"" << esc(r.candidates[i].term.name) << "\"";
  o << "],\n  \"parameters\": {";
  for (std::size_t i = 0; i < r.named.size(); ++i) {
    const auto& c = r.named[i];
    o << (i ? ", " : "") << "\"" << esc(c.term.parameter) << "\": {\"value\": " << num(c.value) << ", \"std\": "
      << num(c.sigma) << ", \"unit\": \"" << esc(c.term.unit) << "\", \"yaml_key\": \"" << esc(c.term.key()) << "\""
      << (c.term.scale ? ", \"scale_factor\": true" : "") << "}";
  }
  o << "},\n  \"effects\": [";
  for (std::size_t i = 0; i < r.named.size(); ++i) {
    const auto& c = r.named[i];
    o << (i ? ", " : "") << "{\"name\": \"" << esc(c.term.name) << "\", \"kind\": \""
      << (c.term.kind == Term::Effect ? "omitted_effect" : "miscalibrated") << "\", \"yaml_key\": \""
      << esc(c.term.key()) << "\", \"value\": " << num(c.value) << ", \"std\": " << num(c.sigma)
      << ", \"nominal\": " << num(c.term.nominal) << ", \"unit\": \"" << esc(c.term.unit) << "\", \"reason\": \""
      << esc(c.term.reason) << "\"}";
  }
  o << "],\n  \"selection\": [";
  for (std::size_t k = 0; k < r.steps.size(); ++k) {
    const auto& st = r.steps[k];
    o << (k ? ",\n    " : "\n    ") << "{\"step\": " << k + 1 << ", \"named\": "
      << (st.chosen >= 0 ? "\"" + esc(st.fits[st.chosen].term.name) + "\"" : std::string("null"))
      << ", \"why\": \"" << esc(st.why) << "\"}";
  }
  o << "],\n  \"residual_significant\": " << (r.residual_significant ? "true" : "false")
    << ",\n  \"nonphysical_share\": " << num(r.nonphysical_share) << ",\n  \"nonphysical\": [";
  bool first = true;
  for (const auto* set : {&r.before_train, &r.before_heldout})
    for (const auto& c : *set) {
      o << (first ? "" : ", ") << "{\"dataset\": \"" << esc(c.label) << "\", \"time_offset_s\": "
        << num(c.alignment.tau_s) << ", \"time_offset_modulo_s\": " << num(c.alignment.period_s)
        << ", \"displacement_gain\": " << num(c.alignment.gain) << "}";
      first = false;
    }
  o << "],\n  \"drive\": [";
  first = true;
  for (const auto* set : {&r.train, &r.heldout})
    for (const auto& d : *set) {
      o << (first ? "" : ", ") << "{\"dataset\": \"" << esc(d.label) << "\", \"mean_speed_rad_s\": "
        << num(d.mean_speed) << ", \"setpoint_rad_s\": " << num(d.setpoint) << ", \"fundamental_rad_s\": "
        << num(d.omega) << "}";
      first = false;
    }
  o << "],\n  \"inputs\": " << inputs_json(datasets_of(r)) << ",\n  \"located\": [";
  for (std::size_t i = 0; i < r.located.size() && i < 15; ++i) {
    const auto& m = r.located[i];
    o << (i ? ",\n    " : "\n    ") << "{\"dataset\": \"" << esc(m.dataset) << "\", \"channel\": \"" << m.channel
      << "\", \"order\": " << (m.order <= kReportOrders ? std::to_string(m.order) : "\"7-12\"")
      << ", \"excess_chi2\": " << num(m.excess_chi2) << ", \"share\": " << num(m.share)
      << ", \"nrmse\": " << num(m.nrmse) << "}";
  }
  o << "],\n  \"candidates\": [";
  for (std::size_t i = 0; i < r.candidates.size(); ++i) {
    const auto& c = r.candidates[i];
    o << (i ? ",\n    " : "\n    ") << "{\"effect\": \"" << esc(c.term.name) << "\", \"kind\": \""
      << (c.term.kind == Term::Effect ? "omitted_effect" : "miscalibrated") << "\", \"parameter\": \""
      << esc(c.term.parameter) << "\", \"unit\": \"" << esc(c.term.unit) << "\", \"value\": " << num(c.value)
      << ", \"std\": " << num(c.sigma) << ", \"search_range\": [" << num(c.term.lo) << ", " << num(c.term.hi)
      << "], \"aic\": " << num(c.aic) << ", \"bic\": " << num(c.bic) << ", \"delta_aic\": " << num(c.delta_aic)
      << ", \"delta_bic\": " << num(c.delta_bic) << ", \"explained_train\": " << num(c.explained_train)
      << ", \"explained_heldout\": " << num(c.explained_heldout) << ", \"nrmse_train\": " << num(c.nrmse_train)
      << ", \"nrmse_heldout\": " << num(c.nrmse_heldout) << ", \"model_evaluations\": " << c.evaluations << "}";
  }
  o << "],\n  \"metrics\": {\n    \"before\": {\"train_nrmse\": " << num(mean_nrmse(r.before_train))
    << ", \"heldout_nrmse\": " << num(mean_nrmse(r.before_heldout)) << ",\n      \"train\": ";
  comparisons_json(o, r.before_train);
  o << ",\n      \"heldout\": ";
  comparisons_json(o, r.before_heldout);
  o << "},\n    \"after\": {\"train_nrmse\": " << num(mean_nrmse(r.after_train))
    << ", \"heldout_nrmse\": " << num(mean_nrmse(r.after_heldout)) << ",\n      \"train\": ";
  comparisons_json(o, r.after_train);
  o << ",\n      \"heldout\": ";
  comparisons_json(o, r.after_heldout);
  o << "},\n    \"naive_train\": ";
  comparisons_json(o, r.naive_train);
  o << "\n  },\n  \"model_failures\": " << r.model_failures << ",\n  \"last_model_failure\": \""
    << esc(r.last_model_failure) << "\",\n  \"model_runs\": " << r.model_runs << ",\n  \"wall_s\": " << num(r.wall_s) << "\n}\n";
  return o.str();
}

std::string diagnosis_markdown(const DiagnosisResult& r) {
  std::ostringstream o;
  o << std::setprecision(3);
  o << "# Mismatch diagnosis\n\n";
  o << "**Result: `" << r.effect << "`** — " << r.reason << ".\n\n";
  for (const auto& c : r.named) {
    o << (c.term.kind == Term::Effect ? "Omitted effect" : "Miscalibrated value") << ": `" << c.term.key()
      << "` " << (c.term.scale ? "scaled by " : "= ") << c.value << " ± " << c.sigma << " " << c.term.unit
      << " (1 sigma, from the curvature of the cost";
    if (c.term.kind == Term::Miscalibrated) o << "; the config's value " << c.term.nominal << ", uncertain because: " << c.term.reason;
    o << ").\n\n";
  }
  if (!r.named.empty()) o << "`fitted.yaml` holds the model with these values.\n\n";
  o << inputs_markdown(datasets_of(r));
  o << "## Non-physical differences (removed before judging the physics)\n\n";
  o << "| data set | time offset (s, modulo one drive period) | displacement sensor gain |\n|---|---|---|\n";
  for (const auto* set : {&r.before_train, &r.before_heldout})
    for (const auto& c : *set)
      o << "| " << c.label << " | " << c.alignment.tau_s << " (period " << c.alignment.period_s << ") | "
        << c.alignment.gain << " |\n";
  o << "\nTime offset and gain account for " << 100 * r.nonphysical_share
    << " % of the raw mismatch of the training data.\n\n";
  o << "## Where the model and the recording differ (unchanged model, aligned)\n\n";
  o << "Ranked by residual power in units of sensor noise (order k = k times the drive frequency; "
       "order 0 = mean).\n\n| data set | channel | order | share of mismatch | NRMSE at that order |\n|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < r.located.size() && i < 8; ++i) {
    const auto& m = r.located[i];
    if (m.share < 0.01) break;
    o << "| " << m.dataset << " | " << m.channel << " | "
      << (m.order <= kReportOrders ? std::to_string(m.order) : std::string("7-12")) << " | "
      << 100 * m.share << " % | " << m.nrmse << " |\n";
  }
  for (std::size_t k = 0; k < r.steps.size(); ++k) {
    o << "\n## Selection step " << k + 1 << (k ? " (on top of the terms named before)" : ": every candidate alone")
      << "\n\n| candidate | kind | fitted value | ΔAIC | ΔBIC | structured residual removed (train / held out) |\n"
         "|---|---|---|---|---|---|\n";
    for (const auto& c : r.steps[k].fits)
      o << "| " << c.term.name << " | " << (c.term.kind == Term::Effect ? "omitted effect" : "uncertain value")
        << " | " << c.term.parameter << (c.term.scale ? " x " : " = ") << c.value << " ± " << c.sigma << " "
        << c.term.unit << " | " << c.delta_aic << " | " << c.delta_bic << " | " << 100 * c.explained_train
        << " % / " << 100 * c.explained_heldout << " %" << (c.heldout_worse ? " (a held-out row worse)" : "")
        << " |\n";
    o << "\nDecision: " << r.steps[k].why << ".\n";
  }
  o << "\nNegative ΔBIC favours the term; below -10 is strong evidence.\n\n";
  o << "## Error before and after\n\nNRMSE per channel (fit percent = 100 (1 - NRMSE)); overall = noise-weighted "
       "over channels; - = not compared.\n\n| data set | | overall | x | y | z | power | speed | ax | ay | az |\n"
       "|---|---|---|---|---|---|---|---|---|---|---|\n";
  auto rows = [&](const std::vector<Comparison>& cs, const char* tag) {
    for (const auto& c : cs) {
      o << "| " << c.label << " | " << tag << " | " << c.nrmse_overall;
      for (const auto& e : c.ch) {
        if (e.compared) o << " | " << e.nrmse;
        else o << " | -";
      }
      o << " |\n";
    }
  };
  rows(r.before_train, "before (train)");
  rows(r.after_train, "after (train)");
  rows(r.before_heldout, "before (held out)");
  rows(r.after_heldout, "after (held out)");
  o << "\nPlots: `overlay_*.png` (recording, model before and after), `residual_spectrum.png` "
       "(residual by harmonic order).\n";
  o << "\nModel runs: " << r.model_runs << ", wall time " << r.wall_s << " s.\n";
  return o.str();
}

}  // namespace analysis
