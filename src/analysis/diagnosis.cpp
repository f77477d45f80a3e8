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

std::vector<EffectSpec> default_candidates() {
  // Ranges of the main parameter: from "not there" to well beyond what the mechanism plausibly shows.
  return {
      {"joint_friction", "coulomb_Nm", "N m", 0.0, 2000.0},
      {"absorber_nonlinearity", "cubic_N_per_m3", "N/m^3", 0.0, 5e11},
      {"motor_droop", "droop_rad_s_per_kNm", "rad/s per kN m", 0.0, 5.0},
      {"cardan_misalignment", "angle_deg", "deg", 0.0, 20.0},
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
  for (const auto& e : c.ch) s += std::max(0.0, e.chi2 - e.dof_chi2);
  return s;
}

namespace {

struct Evaluator {
  const ModelFn& model;
  const DiagnosisOptions& opt;
  std::map<std::tuple<std::string, double, double>, ChannelHarmonics> cache;
  int runs = 0;

  const ChannelHarmonics& harmonics(const std::string& effect_in, double value, double speed) {
    // Every candidate at zero strength is the unchanged model: run it once.
    const std::string effect = value == 0.0 ? "none" : effect_in;
    auto key = std::make_tuple(effect, value, speed);
    auto it = cache.find(key);
    if (it != cache.end()) return it->second;
    Recording run = model(effect, value, speed, opt.model_seconds);
    ++runs;
    run.source = "model(" + effect + ")";
    return cache[key] = model_harmonics(run);
  }
  // Profile cost: nuisance alignment re-fitted for every value.
  // A parameter value at which the model fails (blow-up, stalled drive) is a bad fit, not an error.
  int failures = 0;
  std::string last_failure;
  double cost(const std::string& effect, double value, const std::vector<Dataset>& ds) {
    double s = 0;
    for (const auto& d : ds) {
      try {
        const auto& m = harmonics(effect, value, d.setpoint);
        s += harmonic_cost(d, m, align(d, m));
      } catch (const std::exception& e) {
        ++failures;
        last_failure = effect + " = " + std::to_string(value) + ": " + e.what();
        return 1e300;
      }
    }
    return std::isfinite(s) ? s : 1e300;
  }
  std::vector<Comparison> compare_all(const std::string& effect, double value, const std::vector<Dataset>& ds,
                                      bool aligned = true) {
    std::vector<Comparison> out;
    for (const auto& d : ds) {
      const auto& m = harmonics(effect, value, d.setpoint);
      Alignment a = align(d, m, aligned, aligned);
      out.push_back(compare(d, m, a, d.label));
    }
    return out;
  }
};

double overall_nrmse(const std::vector<Comparison>& cs) {
  double num = 0, den = 0;
  for (const auto& c : cs)
    for (const auto& e : c.ch) {
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
void information(const std::vector<Comparison>& cs, int k, double& aic_out, double& bic_out) {
  std::vector<double> rss, n;
  for (const auto& c : cs)
    for (const auto& e : c.ch) {
      if (!e.compared) continue;  // not recorded, or a set point
      rss.push_back(std::max(e.rss, 1e-300));
      n.push_back(e.n);
    }
  aic_out = aic(rss, n, k);
  bic_out = bic(rss, n, k);
}

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
  Evaluator ev{model, opt, {}, 0};

  // Locate: unchanged model, first without and then with the non-physical alignment.
  r.naive_train = ev.compare_all("none", 0.0, r.train, false);
  r.before_train = ev.compare_all("none", 0.0, r.train);
  r.before_heldout = ev.compare_all("none", 0.0, r.heldout);
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

  // Name: fit each candidate's main parameter on the training data, score by BIC, check held out.
  double aic0, bic0;
  information(r.before_train, 0, aic0, bic0);
  const double excess_train0 = total_excess(r.before_train), excess_held0 = total_excess(r.before_heldout);
  for (const auto& spec : candidates) {
    CandidateResult cr;
    cr.spec = spec;
    auto f = [&](double v) {
      double c = ev.cost(spec.name, v, r.train);
      cr.profile.emplace_back(v, c);
      return c;
    };
    Minimum best = minimise_scan_golden(f, spec.lo, spec.hi, opt.scan_points, opt.rel_tol * (spec.hi - spec.lo));
    cr.value = best.x;
    cr.evaluations = best.evaluations;
    // Uncertainty: cost = chi-square (residuals over noise std), so sigma = sqrt(2 / cost'').
    const double h = std::max(0.01 * (spec.hi - spec.lo), 0.05 * std::abs(best.x));
    const double x0 = std::max(best.x, spec.lo + h);
    const double f0 = x0 == best.x ? best.f : f(x0);
    const double fp = f(x0 + h), fm = f(x0 - h);
    const double curv = (fp - 2.0 * f0 + fm) / (h * h);
    cr.sigma = curv > 0 && curv < 1e290 ? std::sqrt(2.0 / curv) : std::numeric_limits<double>::infinity();
    if (curv > 0 && fp < 1e290 && fm < 1e290) {
      // One Newton step on the parabola through the three points: finer than the golden-section
      // tolerance at the cost of one run.
      const double xn = std::min(spec.hi, std::max(spec.lo, x0 - (fp - fm) / (2.0 * h) / curv));
      if (std::abs(xn - x0) < 2.0 * h) {
        const double fn = f(xn);
        if (fn < best.f) cr.value = xn;
      }
    }
    auto after_train = ev.compare_all(spec.name, cr.value, r.train);
    auto after_held = ev.compare_all(spec.name, cr.value, r.heldout);
    {
      // Birge ratio: where the fitted model still leaves more harmonic residual than recording noise
      // explains (the model run's own fluctuation, an imperfect effect law), widen the uncertainty by
      // sqrt(chi2 / dof) (Birge 1932; the usual reduced-chi-square scaling).
      double chi2 = 0, dof = 0;
      for (const auto& cmp : after_train)
        for (const auto& e : cmp.ch) {
          chi2 += e.chi2 * e.harmonic_sigma2 / e.sigma2;
          dof += e.dof_chi2;
        }
      if (dof > 0 && chi2 > dof) cr.sigma *= std::sqrt(chi2 / dof);
    }
    information(after_train, 1, cr.aic, cr.bic);
    cr.delta_aic = cr.aic - aic0;
    cr.delta_bic = cr.bic - bic0;
    cr.explained_train = excess_train0 > 0 ? 1.0 - total_excess(after_train) / excess_train0 : 0.0;
    cr.explained_heldout = excess_held0 > 0 ? 1.0 - total_excess(after_held) / excess_held0 : 0.0;
    cr.nrmse_train = overall_nrmse(after_train);
    cr.nrmse_heldout = overall_nrmse(after_held);
    r.candidates.push_back(cr);
  }
  int best = -1;
  for (std::size_t i = 0; i < r.candidates.size(); ++i)
    if (best < 0 || r.candidates[i].bic < r.candidates[best].bic) best = static_cast<int>(i);

  std::ostringstream why;
  if (!r.residual_significant) {
    r.effect = "none";
    why << "the residual of the unchanged model, after time offset and sensor gain, is consistent with "
           "sensor noise (chi-square test at "
        << opt.z_significance << " sigma in every channel and data set)";
    if (best >= 0) why << "; best candidate " << r.candidates[best].spec.name << " changes BIC by "
                       << r.candidates[best].delta_bic;
  } else if (best >= 0 && r.candidates[best].delta_bic < -opt.bic_threshold &&
             r.candidates[best].explained_train >= opt.min_explained &&
             r.candidates[best].explained_heldout >= opt.min_explained) {
    r.effect = r.candidates[best].spec.name;
    r.chosen = best;
    why << r.effect << " lowers BIC by " << -r.candidates[best].delta_bic << " and removes "
        << 100 * r.candidates[best].explained_train << " % (training) and "
        << 100 * r.candidates[best].explained_heldout << " % (held out) of the structured residual";
  } else {
    r.effect = "unexplained";
    why << "the residual is significant but no candidate lowers BIC by " << opt.bic_threshold
        << " while removing " << 100 * opt.min_explained << " % of the structured residual on training and "
        << "held-out data";
    if (!r.located.empty())
      why << "; largest unexplained part: " << r.located[0].channel << " order " << r.located[0].order
          << " in " << r.located[0].dataset;
  }
  r.reason = why.str();
  if (r.chosen >= 0) {
    const auto& c = r.candidates[r.chosen];
    r.after_train = ev.compare_all(c.spec.name, c.value, r.train);
    r.after_heldout = ev.compare_all(c.spec.name, c.value, r.heldout);
  } else {
    r.after_train = r.before_train;
    r.after_heldout = r.before_heldout;
  }
  r.model_runs = ev.runs;
  r.model_failures = ev.failures;
  r.last_model_failure = ev.last_failure;
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return r;
}

}  // namespace analysis
