#include "analysis/summary_diagnosis.hpp"

#include <chrono>
#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>

#include "analysis/diagnosis.hpp"
#include "analysis/json_text.hpp"

namespace analysis {

namespace {

bool row_significant(const RowComparison& r, double z) {
  return r.dof > 0 && r.chi2 > r.dof + z * std::sqrt(2.0 * r.dof);
}

class SummaryObjective : public Objective {
 public:
  SummaryObjective(const SummaryRecording& data, const SummaryModelFn& model, double z)
      : data_(data), model_(model), z_(z) {}

  const Stats& stats(const ParamSet& p, double speed) {
    auto key = std::make_pair(to_string(p), speed);
    auto it = cache_.find(key);
    if (it != cache_.end()) return it->second;
    ++runs;
    return cache_[key] = model_(p, speed);
  }
  std::vector<RowComparison> compare(const ParamSet& p) {
    std::vector<RowComparison> out;
    for (const auto& row : data_.rows) {
      RowComparison c;
      c.speed_rad_s = row.speed_rad_s;
      c.plant = row.values;
      c.model = stats(p, row.speed_rad_s);
      for (const auto& [q, pct] : data_.uncertainty_pct) {
        if (!row.values.count(q)) continue;
        const double d = row.values.at(q), m = c.model.count(q) ? c.model.at(q) : NAN;
        const double sigma = 0.01 * pct * std::abs(d);
        const double zq = std::isfinite(m) && sigma > 0 ? (m - d) / sigma : 1e6;  // a missing model value: no fit
        c.z[q] = zq;
        c.chi2 += zq * zq;
        ++c.dof;
      }
      out.push_back(c);
    }
    return out;
  }
  double cost(const ParamSet& p) override {
    try {
      double s = 0;
      for (const auto& c : compare(p)) s += c.chi2;
      return std::isfinite(s) ? s : 1e300;
    } catch (const std::exception& e) {
      ++failures;
      last_failure = to_string(p) + ": " + e.what();
      return 1e300;
    }
  }
  Score score(const ParamSet& p) override {
    Score s;
    std::vector<RowComparison> rows;
    try {
      rows = compare(p);
    } catch (const std::exception& e) {
      ++failures;
      last_failure = to_string(p) + ": " + e.what();
      s.cost = s.m2ll = s.excess_train = s.excess_heldout = 1e300;
      s.significant = s.heldout_worse = true;
      return s;
    }
    if (reference_.empty()) reference_ = rows;  // the first score is the unchanged model's
    double num = 0, den = 0;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const auto& r = rows[i];
      s.cost += r.chi2;
      s.n_obs += r.dof;
      s.excess_train += std::max(0.0, r.chi2 - r.dof);
      if (row_significant(r, z_)) s.significant = true;
      const auto& r0 = current_.empty() ? reference_[i] : current_[i];
      if ((row_significant(r, z_) && !row_significant(r0, z_)) || (row_significant(r0, z_) && r.chi2 > r0.chi2 * 1.0001))
        s.heldout_worse = true;
      if (unsteady(r) && !unsteady(r0)) s.heldout_worse = true;
      for (const auto& [q, zq] : r.z) {
        num += zq * zq;
        const double rel = 100.0 / data_.uncertainty_pct.at(q);  // value over its uncertainty
        den += rel * rel;
      }
    }
    s.m2ll = s.cost;  // Gaussian, known uncertainties: -2 ln L = chi-square + const
    s.excess_heldout = s.excess_train;
    s.nrmse_train = s.nrmse_heldout = den > 0 ? std::sqrt(num / den) : 0.0;
    s.birge = s.n_obs > 0 && s.cost > s.n_obs ? std::sqrt(s.cost / s.n_obs) : 1.0;
    return s;
  }
  // A std the plant row gives and that is not compared (its cycle-to-cycle scatter, feed and sensors included) exceeded
  // by the model's: the model has no feed or sensor scatter, so a larger std is its own unsteadiness (a mechanism near
  // a blow-up), not the plant's.
  bool unsteady(const RowComparison& r) const {
    for (const auto& [q, v] : r.plant)
      if (q.size() > 4 && q.compare(q.size() - 4, 4, "_std") == 0 && !data_.uncertainty_pct.count(q) &&
          r.model.count(q) && r.model.at(q) > v)
        return true;
    return false;
  }
  // The rows a new term is judged against: the model with the terms named so far.
  void named(const ParamSet& p) override { current_ = compare(p); }

  int runs = 0, failures = 0;
  std::string last_failure;

 private:
  const SummaryRecording& data_;
  const SummaryModelFn& model_;
  double z_;
  std::map<std::pair<std::string, double>, Stats> cache_;
  std::vector<RowComparison> reference_, current_;
};

using json::esc;
using json::num;
void stats_json(std::ostringstream& o, const Stats& s) {
  o << "{";
  bool first = true;
  for (const auto& [k, v] : s) {
    o << (first ? "" : ", ") << "\"" << k << "\": " << num(v);
    first = false;
  }
  o << "}";
}
void rows_json(std::ostringstream& o, const std::vector<RowComparison>& rows) {
  o << "[";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    o << (i ? ",\n      " : "\n      ") << "{\"speed_rpm\": " << num(r.speed_rad_s * 60 / (2 * M_PI))
      << ", \"chi2\": " << num(r.chi2) << ", \"dof\": " << r.dof << ", \"z\": ";
    stats_json(o, r.z);
    o << ", \"plant\": ";
    stats_json(o, r.plant);
    o << ", \"model\": ";
    stats_json(o, r.model);
    o << "}";
  }
  o << "]";
}

}  // namespace

SummaryDiagnosis diagnose_summary(const SummaryRecording& data, const SummaryModelFn& model,
                                  const std::vector<Term>& candidates, const SummaryDiagnosisOptions& opt) {
  const auto wall0 = std::chrono::steady_clock::now();
  SummaryDiagnosis d;
  d.data = data;
  SummaryObjective obj(data, model, opt.z_significance);
  d.before = obj.compare({});
  // Forward selection; each step's row check is against the model with the terms named before it.
  const SelectionOptions& so = opt.selection;
  const Selection sel = forward_select(obj, candidates, so);
  d.selection = sel;
  d.after = obj.compare(sel.fitted);
  const Verdict v = selection_verdict(sel, opt.z_significance, so.bic_threshold, so.min_explained);
  d.effect = v.effect;
  d.reason = v.reason;
  d.model_runs = obj.runs;
  d.model_failures = obj.failures;
  d.last_model_failure = obj.last_failure;
  d.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return d;
}

std::string summary_diagnosis_json(const SummaryDiagnosis& d) {
  std::ostringstream o;
  o << "{\n  \"input\": \"summary\",\n  \"source\": \"" << esc(d.data.source) << "\",\n  \"file\": \""
    << esc(d.data.file) << "\",\n  \"effect\": \"" << esc(d.effect) << "\",\n  \"reason\": \"" << esc(d.reason)
    << "\",\n  \"uncertainty_pct\": ";
  stats_json(o, d.data.uncertainty_pct);
  o << ",\n  \"effects\": [";
  for (std::size_t i = 0; i < d.selection.named.size(); ++i) {
    const auto& c = d.selection.named[i];
    o << (i ? ", " : "") << "{\"name\": \"" << esc(c.term.name) << "\", \"kind\": \""
      << (c.term.kind == Term::Effect ? "omitted_effect" : "miscalibrated") << "\", \"yaml_key\": \""
      << esc(c.term.key()) << "\", \"value\": " << num(c.value) << ", \"std\": " << num(c.sigma)
      << ", \"nominal\": " << num(c.term.nominal) << ", \"unit\": \"" << esc(c.term.unit) << "\"}";
  }
  o << "],\n  \"selection\": [";
  for (std::size_t k = 0; k < d.selection.steps.size(); ++k) {
    const auto& st = d.selection.steps[k];
    o << (k ? ",\n    " : "\n    ") << "{\"step\": " << k + 1 << ", \"why\": \"" << esc(st.why) << "\", \"candidates\": [";
    for (std::size_t i = 0; i < st.fits.size(); ++i) {
      const auto& c = st.fits[i];
      o << (i ? ", " : "") << "{\"name\": \"" << esc(c.term.name) << "\", \"kind\": \""
        << (c.term.kind == Term::Effect ? "omitted_effect" : "miscalibrated") << "\", \"value\": " << num(c.value)
        << ", \"std\": " << num(c.sigma) << ", \"delta_bic\": " << num(c.delta_bic) << ", \"explained\": "
        << num(c.explained_train) << ", \"row_worse\": " << (c.heldout_worse ? "true" : "false")
        << ", \"named\": " << (static_cast<int>(i) == st.chosen ? "true" : "false") << "}";
    }
    o << "]}";
  }
  o << "],\n  \"before\": ";
  rows_json(o, d.before);
  o << ",\n  \"after\": ";
  rows_json(o, d.after);
  o << ",\n  \"model_runs\": " << d.model_runs << ",\n  \"model_failures\": " << d.model_failures
    << ",\n  \"last_model_failure\": \"" << esc(d.last_model_failure) << "\",\n  \"wall_s\": " << num(d.wall_s) << "\n}\n";
  return o.str();
}

std::string summary_diagnosis_markdown(const SummaryDiagnosis& d) {
  std::ostringstream o;
  o << std::setprecision(4);
  o << "# Mismatch diagnosis on summary data\n\nData: " << d.data.file << " (" << d.data.source << ").\n\n";
  o << "**Result: `" << d.effect << "`** — " << d.reason << ".\n\n";
  for (const auto& c : d.selection.named)
    o << "- " << (c.term.kind == Term::Effect ? "omitted effect" : "miscalibrated value") << " `" << c.term.key()
      << "` " << (c.term.scale ? "scaled by " : "= ") << c.value << " ± " << c.sigma << " " << c.term.unit << "\n";
  o << "\n## Plant and model (z = (model - plant) / uncertainty; compared values only)\n\n"
       "| speed (rpm) | quantity | plant | model before | z before | model after | z after |\n|---|---|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < d.before.size(); ++i) {
    const auto& b = d.before[i];
    const auto& a = d.after[i];
    for (const auto& [q, v] : b.plant) {
      o << "| " << b.speed_rad_s * 60 / (2 * M_PI) << " | " << q << " | " << v << " | "
        << (b.model.count(q) ? b.model.at(q) : NAN) << " | ";
      if (b.z.count(q)) o << b.z.at(q); else o << "not compared";
      o << " | " << (a.model.count(q) ? a.model.at(q) : NAN) << " | ";
      if (a.z.count(q)) o << a.z.at(q); else o << "not compared";
      o << " |\n";
    }
  }
  for (std::size_t k = 0; k < d.selection.steps.size(); ++k) {
    const auto& st = d.selection.steps[k];
    o << "\n## Selection step " << k + 1 << "\n\n| candidate | kind | fitted value | ΔBIC | residual removed | a row worse |\n"
         "|---|---|---|---|---|---|\n";
    for (const auto& c : st.fits)
      o << "| " << c.term.name << " | " << (c.term.kind == Term::Effect ? "omitted effect" : "uncertain value") << " | "
        << c.value << " ± " << c.sigma << " " << c.term.unit << " | " << c.delta_bic << " | "
        << 100 * c.explained_train << " % | " << (c.heldout_worse ? "yes" : "no") << " |\n";
    o << "\nDecision: " << st.why << ".\n";
  }
  if (!d.selection.steps.empty())
    o << "\nA row worse: a row consistent with its uncertainty no longer is, an inconsistent row's chi-square rises, or a\n"
         "std the plant gives and that is not compared rises above the plant's (the model has no feed or sensor scatter).\n";
  o << "\nModel runs: " << d.model_runs << ", wall time " << d.wall_s << " s.\n";
  return o.str();
}

}  // namespace analysis
