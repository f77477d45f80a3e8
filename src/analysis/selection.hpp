#pragma once
// Forward selection of the diagnosis's terms (issue 24): fit each candidate term on the training data with the
// terms already named held at their values, name the best by BIC if it also removes enough of the structured
// residual on training and held-out data, refit, and repeat while another term is still needed; together the named
// terms must explain most of the residual, or none is named. Before an
// omitted effect is named, a refit of the config's uncertain values (a miscalibration) that explains the residual
// about as well (BIC within the threshold) is preferred: no new physics is claimed where a value explains it.
#include <string>
#include <utility>
#include <vector>

#include "analysis/param_set.hpp"

namespace analysis {

// What a parameter set does on the data (the diagnosis's time series or its summary statistics).
struct Score {
  double cost = 0;                 // training cost the fits minimise: chi-square against the data's uncertainty
  double m2ll = 0;                 // -2 ln L of the training data (up to a constant), for AIC and BIC
  double n_obs = 0;                // observations behind m2ll (BIC's ln n)
  double excess_train = 0;         // structured residual beyond noise (chi-square minus its dof, >= 0)
  double excess_heldout = 0;
  double nrmse_train = 0, nrmse_heldout = 0;
  double birge = 1;                // sqrt(chi2 / dof) of the training residual where above 1: widens sigmas
  bool significant = false;        // is the residual still more than noise (train or held out)?
  bool heldout_worse = false;      // summaries: a data row got worse beyond its noise
};

class Objective {
 public:
  virtual ~Objective() = default;
  virtual double cost(const ParamSet& p) = 0;  // 1e300 where the model fails (a bad fit, not an error)
  virtual Score score(const ParamSet& p) = 0;
  virtual void named(const ParamSet& /*p*/) {}  // the selection named a term: p is the model from now on
};

struct SelectionOptions {
  int scan_points = 7;          // coarse scan of each term's range before golden-section search
  double rel_tol = 2e-3;        // golden-section tolerance, fraction of the range
  double bic_threshold = 10.0;  // a term must lower BIC by this much (strong evidence, Kass-Raftery)
  double min_step_explained = 0.2;  // ... and remove this fraction of the residual left, training and held out
  double min_explained = 0.5;   // together the named terms remove this fraction, training and held out
  bool fit_when_consistent = true;  // fit the candidates for the report even when the residual is noise
  int max_terms = 3;            // at most this many terms named together
};

struct TermFit {
  Term term;
  double value = 0, sigma = 0;  // fitted value and its 1-sigma uncertainty (cost curvature, Birge-widened)
  double aic = 0, bic = 0, delta_aic = 0, delta_bic = 0;  // delta: against the model before this step
  double explained_train = 0, explained_heldout = 0;     // fraction of the step's structured residual removed
  double nrmse_train = 0, nrmse_heldout = 0;
  bool heldout_worse = false;
  bool qualifies = false;       // meets the BIC, explained and held-out criteria
  int evaluations = 0;
  std::vector<std::pair<double, double>> profile;  // (value, cost) points seen
};

struct SelectionStep {
  std::vector<TermFit> fits;    // every candidate not yet named, fitted on top of the named ones
  int chosen = -1;              // index into fits, -1: none qualified (selection ends)
  std::string why;              // the decision in words
};

struct Selection {
  std::vector<SelectionStep> steps;
  std::vector<TermFit> named;   // in the order named, values after the final joint refit
  ParamSet fitted;              // the named terms at their values
  Score before, after;          // unchanged model, and with the named terms
  double explained_train = 0, explained_heldout = 0;  // by the terms together
  std::vector<TermFit> partial; // terms found that together explain too little (then none is named)
};

// Fits `term` on top of `fixed` (its range scanned, then golden-section, then a Newton step on the curvature).
TermFit fit_term(Objective& obj, const Term& term, const ParamSet& fixed, const Score& before, int k_before,
                 const SelectionOptions& opt);
// Refits the named terms together (Nelder-Mead over their ranges); updates their values, sigmas and `fixed`.
void joint_refit(Objective& obj, std::vector<TermFit>& named, ParamSet& fixed, const SelectionOptions& opt);
Selection forward_select(Objective& obj, const std::vector<Term>& terms, const SelectionOptions& opt);
// The named terms in words: "none" for none, effect names and "miscalibrated" once for refitted values,
// joined by " + " (e.g. "miscalibrated", "joint_friction + motor_droop").
std::string effect_label(const std::vector<TermFit>& named);

// The selection's verdict in words: effect "none" (residual within noise), "unexplained" (no term, or the terms
// together fall short of min_explained) or effect_label of the named terms; reason says why, step by step.
struct Verdict {
  std::string effect, reason;
};
Verdict selection_verdict(const Selection& sel, double z_significance, double bic_threshold, double min_explained);

}  // namespace analysis
