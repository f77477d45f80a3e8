#include "analysis/selection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "analysis/optimise.hpp"

namespace analysis {

namespace {
double information(const Score& s, int k, bool bayes) {
  return s.m2ll + (bayes ? k * std::log(std::max(1.0, s.n_obs)) : 2.0 * k);
}
}  // namespace

TermFit fit_term(Objective& obj, const Term& term, const ParamSet& fixed, const Score& before, int k_before,
                 const SelectionOptions& opt) {
  TermFit tf;
  tf.term = term;
  auto at = [&](double v) {
    ParamSet p = fixed;
    p[term.name] = v;
    return p;
  };
  auto f = [&](double v) {
    const double c = obj.cost(at(v));
    tf.profile.emplace_back(v, c);
    return c;
  };
  const double lo = term.lo, hi = term.hi, span = hi - lo;
  Minimum best = minimise_scan_golden(f, lo, hi, opt.scan_points, opt.rel_tol * span);
  tf.value = best.x;
  // Uncertainty: cost = chi-square, so sigma = sqrt(2 / cost'').
  const double h = std::max(0.01 * span, 0.05 * std::abs(best.x - term.nominal));
  const double x0 = std::min(std::max(best.x, lo + h), hi - h);
  const double f0 = x0 == best.x ? best.f : f(x0);
  const double fp = f(x0 + h), fm = f(x0 - h);
  const double curv = (fp - 2.0 * f0 + fm) / (h * h);
  tf.sigma = curv > 0 && curv < 1e290 ? std::sqrt(2.0 / curv) : std::numeric_limits<double>::infinity();
  if (curv > 0 && fp < 1e290 && fm < 1e290) {
    // One Newton step on the parabola through the three points: finer than the golden-section tolerance.
    const double xn = std::min(hi, std::max(lo, x0 - (fp - fm) / (2.0 * h) / curv));
    if (std::abs(xn - x0) < 2.0 * h && f(xn) < best.f) tf.value = xn;
  }
  tf.evaluations = static_cast<int>(tf.profile.size());
  const Score s = obj.score(at(tf.value));
  tf.sigma *= s.birge;
  tf.aic = information(s, k_before + 1, false);
  tf.bic = information(s, k_before + 1, true);
  tf.delta_aic = tf.aic - information(before, k_before, false);
  tf.delta_bic = tf.bic - information(before, k_before, true);
  tf.explained_train = before.excess_train > 0 ? 1.0 - s.excess_train / before.excess_train : 0.0;
  tf.explained_heldout = before.excess_heldout > 0 ? 1.0 - s.excess_heldout / before.excess_heldout : 0.0;
  tf.nrmse_train = s.nrmse_train;
  tf.nrmse_heldout = s.nrmse_heldout;
  tf.heldout_worse = s.heldout_worse;
  tf.qualifies = tf.delta_bic < -opt.bic_threshold && tf.explained_train >= opt.min_step_explained &&
                 tf.explained_heldout >= opt.min_step_explained && !s.heldout_worse;
  return tf;
}

void joint_refit(Objective& obj, std::vector<TermFit>& named, ParamSet& fixed, const SelectionOptions& opt) {
  const std::size_t n = named.size();
  auto value = [&](std::size_t i, double u) {
    const Term& t = named[i].term;
    return t.lo + std::min(1.0, std::max(0.0, u)) * (t.hi - t.lo);
  };
  auto set_of = [&](const std::vector<double>& u) {
    ParamSet p = fixed;
    for (std::size_t i = 0; i < n; ++i) p[named[i].term.name] = value(i, u[i]);
    return p;
  };
  std::vector<double> u0(n), step(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Term& t = named[i].term;
    u0[i] = (named[i].value - t.lo) / (t.hi - t.lo);
    step[i] = std::max(0.02, std::min(0.2, std::isfinite(named[i].sigma) ? 3.0 * named[i].sigma / (t.hi - t.lo) : 0.2));
  }
  auto f = [&](const std::vector<double>& u) {
    double penalty = 0;  // outside [0, 1]: the clamped value's cost, rising with the distance
    for (double x : u) penalty += x < 0 ? -x : (x > 1 ? x - 1 : 0);
    return obj.cost(set_of(u)) * (1.0 + penalty);
  };
  const core::MinimumN m = core::nelder_mead(f, u0, step, 0.5, 60 * static_cast<int>(n));
  const ParamSet best = set_of(m.x);
  const Score s = obj.score(best);
  for (std::size_t i = 0; i < n; ++i) {
    TermFit& tf = named[i];
    tf.value = best.at(tf.term.name);
    // Conditional 1-sigma from the cost's curvature in this term with the others at their values.
    const double h = 0.01 * (tf.term.hi - tf.term.lo);
    const double x0 = std::min(std::max(tf.value, tf.term.lo + h), tf.term.hi - h);
    ParamSet p = best;
    p[tf.term.name] = x0;
    const double f0 = obj.cost(p);
    p[tf.term.name] = x0 + h;
    const double fp = obj.cost(p);
    p[tf.term.name] = x0 - h;
    const double fm = obj.cost(p);
    const double curv = (fp - 2.0 * f0 + fm) / (h * h);
    tf.sigma = (curv > 0 && curv < 1e290 ? std::sqrt(2.0 / curv) : std::numeric_limits<double>::infinity()) * s.birge;
  }
  fixed = best;
}

Selection forward_select(Objective& obj, const std::vector<Term>& terms, const SelectionOptions& opt) {
  Selection sel;
  sel.before = obj.score({});
  Score current = sel.before;
  ParamSet fixed;
  std::vector<std::size_t> named_index;  // into terms
  // The first step's candidates are fitted even when the residual is noise (the report shows them).
  for (int k = 0; k < opt.max_terms && ((k == 0 && opt.fit_when_consistent) || current.significant); ++k) {
    SelectionStep step;
    for (std::size_t i = 0; i < terms.size(); ++i)
      if (!fixed.count(terms[i].name)) step.fits.push_back(fit_term(obj, terms[i], fixed, current, k, opt));
    int best_effect = -1, best_mis = -1;
    for (std::size_t i = 0; i < step.fits.size(); ++i) {
      const auto& f = step.fits[i];
      if (!f.qualifies) continue;
      int& b = f.term.kind == Term::Effect ? best_effect : best_mis;
      if (b < 0 || f.bic < step.fits[b].bic) b = static_cast<int>(i);
    }
    std::ostringstream why;
    why.precision(3);
    if (!current.significant) {
      why << "the residual of the unchanged model is consistent with the data's noise";
    } else if (best_mis >= 0 && (best_effect < 0 || step.fits[best_mis].bic <= step.fits[best_effect].bic + opt.bic_threshold)) {
      step.chosen = best_mis;
      why << "the refit of " << step.fits[best_mis].term.name << " explains it";
      if (best_effect >= 0)
        why << " about as well as the best omitted effect, " << step.fits[best_effect].term.name << " (BIC "
            << step.fits[best_mis].bic - step.fits[best_effect].bic << " from it, within " << opt.bic_threshold
            << "): no new physics is claimed";
    } else if (best_effect >= 0) {
      step.chosen = best_effect;
      why << step.fits[best_effect].term.name << " explains it";
      if (best_mis >= 0)
        why << " better than any refit of an uncertain value (the best, " << step.fits[best_mis].term.name
            << ", is " << step.fits[best_mis].bic - step.fits[best_effect].bic << " higher in BIC)";
    } else {
      why << "no " << (k ? "further " : "") << "term lowers BIC by " << opt.bic_threshold << " while removing "
          << 100 * opt.min_step_explained << " % of the structured residual left on training and held-out data";
    }
    step.why = why.str();
    const int chosen = step.chosen;
    sel.steps.push_back(step);
    if (chosen < 0) break;
    const TermFit& c = sel.steps.back().fits[chosen];
    for (std::size_t i = 0; i < terms.size(); ++i)
      if (terms[i].name == c.term.name) named_index.push_back(i);
    fixed[c.term.name] = c.value;
    sel.named.push_back(c);
    // Joint refit of every named term (Nelder-Mead on the terms' ranges scaled to [0, 1]): the terms' effects are
    // correlated, so refitting one at a time leaves a bias that a spurious extra term would then absorb.
    if (sel.named.size() > 1) joint_refit(obj, sel.named, fixed, opt);
    obj.named(fixed);
    current = obj.score(fixed);
  }
  sel.fitted = fixed;
  sel.after = current;
  // Together the named terms must remove min_explained of the residual, training and held out; else none is named.
  sel.explained_train = sel.before.excess_train > 0 ? 1.0 - current.excess_train / sel.before.excess_train : 0.0;
  sel.explained_heldout = sel.before.excess_heldout > 0 ? 1.0 - current.excess_heldout / sel.before.excess_heldout : 0.0;
  if (!sel.named.empty() && (sel.explained_train < opt.min_explained || sel.explained_heldout < opt.min_explained)) {
    sel.partial = sel.named;
    sel.named.clear();
    sel.fitted.clear();
    sel.after = sel.before;
  }
  return sel;
}

std::string effect_label(const std::vector<TermFit>& named) {
  std::string out;
  bool mis = false;
  for (const auto& t : named) {
    if (t.term.kind == Term::Miscalibrated) {
      if (mis) continue;
      mis = true;
    }
    out += (out.empty() ? "" : " + ") + (t.term.kind == Term::Effect ? t.term.name : std::string("miscalibrated"));
  }
  return out.empty() ? "none" : out;
}

Verdict selection_verdict(const Selection& sel, double z_significance, double bic_threshold, double min_explained) {
  Verdict v;
  const std::vector<TermFit> none;
  const auto& first = sel.steps.empty() ? none : sel.steps.front().fits;
  std::ostringstream why;
  why.precision(3);
  if (!sel.before.significant) {
    v.effect = "none";
    why << "the residual of the unchanged model, after the non-physical differences, is consistent with the "
           "data's noise (chi-square test at "
        << z_significance << " sigma in every channel and data set)";
    int best = -1;
    for (std::size_t i = 0; i < first.size(); ++i)
      if (best < 0 || first[i].bic < first[best].bic) best = static_cast<int>(i);
    if (best >= 0) why << "; best candidate " << first[best].term.name << " changes BIC by " << first[best].delta_bic;
  } else if (sel.named.empty()) {
    v.effect = "unexplained";
    if (sel.partial.empty()) {
      why << "the residual is significant but no candidate lowers BIC by " << bic_threshold
          << " while removing part of the structured residual on training and held-out data";
    } else {
      why << "the residual is significant; the best terms (";
      for (std::size_t i = 0; i < sel.partial.size(); ++i) why << (i ? ", " : "") << sel.partial[i].term.name;
      why << ") together remove " << 100 * sel.explained_train << " % (training) and "
          << 100 * sel.explained_heldout << " % (held out) of it, less than " << 100 * min_explained << " %";
    }
  } else {
    v.effect = effect_label(sel.named);
    for (std::size_t k = 0; k < sel.steps.size(); ++k) {
      const auto& st = sel.steps[k];
      if (st.chosen < 0) {
        why << "; then " << st.why;
        continue;
      }
      const auto& c = st.fits[st.chosen];
      why << (k ? "; then " : "") << c.term.name << " lowers BIC by " << -c.delta_bic << " and removes "
          << 100 * c.explained_train << " % (training) and " << 100 * c.explained_heldout
          << " % (held out) of the structured residual (" << st.why << ")";
    }
    if (sel.after.significant) why << "; a significant residual remains";
  }
  v.reason = why.str();
  return v;
}

}  // namespace analysis
