#include "analysis/diagnosis.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "analysis/metrics.hpp"
#include "analysis/optimise.hpp"

namespace analysis {

std::vector<Term> default_candidates() {
  // Ranges of the main parameter: from "not there" to well beyond what the mechanism plausibly shows.
  auto effect = [](const char* name, const char* parameter, const char* unit, double hi) {
    Term t;
    t.kind = Term::Effect;
    t.name = name;
    t.parameter = parameter;
    t.unit = unit;
    t.lo = 0.0;
    t.hi = hi;
    return t;
  };
  return {
      effect("joint_friction", "coulomb_Nm", "N m", 2000.0),
      effect("absorber_nonlinearity", "cubic_N_per_m3", "N/m^3", 5e11),
      effect("motor_droop", "droop_rad_s_per_kNm", "rad/s per kN m", 5.0),
      effect("cardan_misalignment", "angle_deg", "deg", 20.0),
  };
}

std::string dataset_label(const Recording& r, double t0, double t1) {
  std::ostringstream o;
  o.precision(3);
  o << r.source << " [" << t0 << ", " << t1 << ") s";
  return o.str();
}

double structured_excess(const Comparison& c) {
  double s = 0;
  for (const auto& e : c.ch)
    if (e.compared) s += std::max(0.0, e.chi2 - e.dof_chi2);
  return s;
}

namespace {

double overall_nrmse(const std::vector<Comparison>& cs) {
  double num = 0, den = 0;
  for (const auto& c : cs)
    for (const auto& e : c.ch) {
      if (!e.compared) continue;  // not recorded, or a set point
      num += e.rss / e.sigma2;
      den += e.tss / e.sigma2;
    }
  return den > 0 ? std::sqrt(num / den) : 0.0;
}
double total_excess(const std::vector<Comparison>& cs) {
  double s = 0;
  for (const auto& c : cs) s += structured_excess(c);
  return s;
}

// The time series as the selection sees them: model runs cached per parameter set and speed; the cost is the
// harmonic-domain chi-square with the non-physical alignment (time offset, sensor gain) refitted each time.
class SeriesObjective : public Objective {
 public:
  SeriesObjective(const ModelFn& model, const DiagnosisOptions& opt, const std::vector<Dataset>& train,
                  const std::vector<Dataset>& heldout, const std::vector<Term>& terms)
      : model_(model), opt_(opt), train_(train), heldout_(heldout) {
    for (const auto& t : terms) nominal_[t.name] = t.nominal;
  }

  const ChannelHarmonics& harmonics(const ParamSet& p_in, double speed) {
    ParamSet p;  // a term at its nominal value is the unchanged model: run it once
    for (const auto& [k, v] : p_in) {
      const auto n = nominal_.find(k);
      if (n == nominal_.end() || v != n->second) p[k] = v;
    }
    auto key = std::make_pair(to_string(p), speed);
    auto it = cache_.find(key);
    if (it != cache_.end()) return it->second;
    Recording run = model_(p, speed, opt_.model_seconds);
    ++runs;
    run.source = "model(" + to_string(p) + ")";
    return cache_[key] = model_harmonics(run);
  }
  double cost(const ParamSet& p) override {
    double s = 0;
    for (const auto& d : train_) {
      try {
        const auto& m = harmonics(p, d.setpoint);
        s += harmonic_cost(d, m, align(d, m));
      } catch (const std::exception& e) {
        ++failures;
        last_failure = to_string(p) + ": " + e.what();
        return 1e300;
      }
    }
    return std::isfinite(s) ? s : 1e300;
  }
  std::vector<Comparison> compare_all(const ParamSet& p, const std::vector<Dataset>& ds, bool aligned = true) {
    std::vector<Comparison> out;
    for (const auto& d : ds) {
      const auto& m = harmonics(p, d.setpoint);
      Alignment a = align(d, m, aligned, aligned);
      out.push_back(compare(d, m, a, d.label));
    }
    return out;
  }
  Score score(const ParamSet& p) override {
    Score s;
    std::vector<Comparison> tr, ho;
    try {
      tr = compare_all(p, train_);
      ho = compare_all(p, heldout_);
    } catch (const std::exception& e) {
      ++failures;
      last_failure = to_string(p) + ": " + e.what();
      s.cost = s.m2ll = 1e300;
      s.excess_train = s.excess_heldout = 1e300;
      s.significant = true;
      return s;
    }
    // -2 ln L with the noise known (recording noise plus the model run's own fluctuation): the harmonic chi-square,
    // the same residual the fits minimise and the excess measures; n = the harmonic coefficients compared.
    double chi2 = 0, dof = 0, chi2_rec = 0;
    for (const auto& c : tr)
      for (const auto& e : c.ch) {
        if (!e.compared) continue;  // not recorded, or a set point
        chi2 += e.chi2;
        dof += e.dof_chi2;
        // Birge ratio: where the model still leaves more harmonic residual than recording noise explains (the
        // model run's own fluctuation, an imperfect effect law), widen sigmas by sqrt(chi2 / dof) (Birge 1932).
        chi2_rec += e.chi2 * e.harmonic_sigma2 / e.sigma2;
      }
    s.m2ll = chi2;
    s.n_obs = dof;
    s.birge = dof > 0 && chi2_rec > dof ? std::sqrt(chi2_rec / dof) : 1.0;
    s.excess_train = total_excess(tr);
    s.excess_heldout = total_excess(ho);
    s.nrmse_train = overall_nrmse(tr);
    s.nrmse_heldout = overall_nrmse(ho);
    for (const auto* set : {&tr, &ho})
      for (const auto& c : *set)
        for (const auto& e : c.ch)
          if (e.compared && residual_significant(e, opt_.z_significance)) s.significant = true;
    s.cost = cost(p);
    return s;
  }

  int runs = 0, failures = 0;
  std::string last_failure;

 private:
  const ModelFn& model_;
  const DiagnosisOptions& opt_;
  const std::vector<Dataset>& train_;
  const std::vector<Dataset>& heldout_;
  std::map<std::string, double> nominal_;  // term name -> the value at which the model is unchanged
  std::map<std::pair<std::string, double>, ChannelHarmonics> cache_;
};

}  // namespace

DiagnosisResult diagnose(const std::vector<Recording>& recordings, const ModelFn& model,
                         const std::vector<EffectSpec>& candidates, const DiagnosisOptions& opt) {
  const auto wall0 = std::chrono::steady_clock::now();
  if (recordings.empty()) throw std::invalid_argument("diagnose: at least one recording is needed");
  DiagnosisResult r;
  // Training and held-out data: the first recording trains; further recordings (other speeds) are held
  // out; a single recording is split in time.
  if (recordings.size() == 1) {
    const auto& rec = recordings[0];
    const double tsplit = rec.t_s.front() + (1.0 - opt.heldout_fraction) * rec.duration_s();
    const double tend = rec.t_s.back() + 1.0;
    r.train.push_back(prepare_dataset(rec.slice(rec.t_s.front(), tsplit), dataset_label(rec, rec.t_s.front(), tsplit)));
    r.heldout.push_back(prepare_dataset(rec.slice(tsplit, tend), dataset_label(rec, tsplit, rec.t_s.back())));
  } else {
    for (std::size_t i = 0; i < recordings.size(); ++i) {
      const auto& rec = recordings[i];
      Dataset d = prepare_dataset(rec, dataset_label(rec, rec.t_s.front(), rec.t_s.back()));
      (i == 0 ? r.train : r.heldout).push_back(std::move(d));
    }
  }
  if (!opt.setpoints_rad_s.empty() && opt.setpoints_rad_s.size() != recordings.size())
    throw std::invalid_argument("diagnose: " + std::to_string(opt.setpoints_rad_s.size()) +
                                " drive set points for " + std::to_string(recordings.size()) +
                                " recordings; give one per recording or none");
  auto setpoint_of = [&](std::size_t i) {
    if (!opt.setpoints_rad_s.empty()) {
      if (!(opt.setpoints_rad_s[i] > 0)) throw std::invalid_argument("diagnose: drive set points must be positive");
      return opt.setpoints_rad_s[i];
    }
    const double mean = recordings[i].mean_speed_rad_s();
    for (double s : opt.nominal_setpoints_rad_s)
      if (std::abs(mean - s) <= 0.03 * s) return s;
    const double rpm = 2 * 3.14159265358979323846 / 60;
    return opt.setpoint_whole_rpm ? std::max(1.0, std::round(mean / rpm)) * rpm : mean;
  };
  if (recordings.size() == 1) {
    for (auto* set : {&r.train, &r.heldout}) for (auto& d : *set) d.setpoint = setpoint_of(0);
  } else {
    r.train[0].setpoint = setpoint_of(0);
    for (std::size_t i = 1; i < recordings.size(); ++i) r.heldout[i - 1].setpoint = setpoint_of(i);
  }
  SeriesObjective ev(model, opt, r.train, r.heldout, candidates);

  // Locate: unchanged model, first without and then with the non-physical alignment.
  r.naive_train = ev.compare_all({}, r.train, false);
  r.before_train = ev.compare_all({}, r.train);
  r.before_heldout = ev.compare_all({}, r.heldout);
  {
    double naive = 0, aligned = 0;
    for (const auto& c : r.naive_train) for (const auto& e : c.ch) naive += std::max(0.0, e.rss / e.sigma2 - e.n);
    for (const auto& c : r.before_train) for (const auto& e : c.ch) aligned += std::max(0.0, e.rss / e.sigma2 - e.n);
    r.nonphysical_share = naive > 0 ? std::max(0.0, (naive - aligned) / naive) : 0.0;
  }
  double excess_total = 0;
  for (const auto* set : {&r.before_train, &r.before_heldout})
    for (const auto& c : *set) {
      for (int ch = 0; ch < kNumChannels; ++ch) {
        const auto& e = c.ch[ch];
        if (residual_significant(e, opt.z_significance)) r.residual_significant = true;
        for (int k = 0; k <= kReportOrders + 1; ++k) {
          // Each order carries 2 chi-square degrees of freedom (1 for the mean; 2 per extra order above 6).
          const int dof = k == 0 ? 1 : (k <= kReportOrders ? 2 : 2 * (kFitOrders - kReportOrders));
          Mismatch m;
          m.dataset = c.label;
          m.channel = kChannelNames[ch];
          m.order = k;
          m.excess_chi2 = std::max(0.0, e.n * e.order_residual_power[k] / e.harmonic_sigma2 - dof);
          m.nrmse = e.order_nrmse[k];
          excess_total += m.excess_chi2;
          r.located.push_back(m);
        }
      }
    }
  for (auto& m : r.located) m.share = excess_total > 0 ? m.excess_chi2 / excess_total : 0.0;
  std::sort(r.located.begin(), r.located.end(),
            [](const Mismatch& a, const Mismatch& b) { return a.excess_chi2 > b.excess_chi2; });

  // Name: forward selection over the candidates (effects and uncertain values), BIC and held-out checks.
  SelectionOptions so;
  so.scan_points = opt.scan_points;
  so.rel_tol = opt.rel_tol;
  so.bic_threshold = opt.bic_threshold;
  so.min_explained = opt.min_explained;
  so.min_step_explained = opt.min_step_explained;
  so.max_terms = opt.max_terms;
  const Selection sel = forward_select(ev, candidates, so);
  adopt_selection(r, sel, opt);
  if (r.effect == "unexplained" && !r.located.empty())
    r.reason += "; largest unexplained part: " + r.located[0].channel + " order " +
                std::to_string(r.located[0].order) + " in " + r.located[0].dataset;
  r.after_train = ev.compare_all(r.fitted, r.train);
  r.after_heldout = ev.compare_all(r.fitted, r.heldout);
  r.model_runs = ev.runs;
  r.model_failures = ev.failures;
  r.last_model_failure = ev.last_failure;
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return r;
}

void adopt_selection(DiagnosisResult& r, const Selection& sel, const DiagnosisOptions& opt) {
  r.steps = sel.steps;
  r.named = sel.named;
  r.fitted = sel.fitted;
  r.candidates = sel.steps.empty() ? std::vector<TermFit>{} : sel.steps.front().fits;
  r.residual_significant = sel.before.significant;
  r.chosen = sel.steps.empty() ? -1 : sel.steps.front().chosen;
  const Verdict v = selection_verdict(sel, opt.z_significance, opt.bic_threshold, opt.min_explained);
  r.effect = v.effect;
  r.reason = v.reason;
}

}  // namespace analysis
