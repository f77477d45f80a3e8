#pragma once
// Mismatch diagnosis (issues 6, 24): locate where a model and recordings differ, name the omitted effects
// among the candidate modules or the config's uncertain values that explain it (forward selection,
// selection.hpp), fit them with the simulation in the loop, show the fit improve.
#include <functional>
#include <string>
#include <vector>

#include "analysis/comparison.hpp"
#include "analysis/selection.hpp"

namespace analysis {

// A candidate omitted effect is a Term (param_set.hpp) of kind Effect; its main parameter's search range is in
// the unit of the YAML key mbd.effects.<name>.<parameter>.
using EffectSpec = Term;
using CandidateResult = TermFit;

// Runs the model with the parameter set `p` (terms at their values, the rest unchanged), the drive set point
// at `speed_rad_s`; returns >= duration_s of steady state.
using ModelFn = std::function<Recording(const ParamSet& p, double speed_rad_s, double duration_s)>;

struct DiagnosisOptions {
  double model_seconds = 3.0;      // steady-state model time per run: 1 s biased a fitted angle by 2 %
                                   // (slow non-periodic content); 3 s by 0.2 %
  double heldout_fraction = 0.4;   // time split when only one recording is given
  int scan_points = 7;             // coarse scan of each main parameter before golden-section search
  double rel_tol = 2e-3;           // golden-section tolerance, fraction of the search range
  double bic_threshold = 10.0;     // a candidate must lower BIC by this much (strong evidence, Kass-Raftery)
  double min_step_explained = 0.2; // ... and remove this fraction of the residual left, training and held out
  double min_explained = 0.5;      // the named terms together remove this fraction, training and held out
  int max_terms = 3;               // forward selection names at most this many terms together
  double z_significance = 5.0;     // chi-square test of the residual against noise, in normal sigmas
  // Drive set point of each recording (the model runs at it; with droop the speed falls below it):
  //  1. setpoints_rad_s[i] for recording i when given (the plant's control system knows them);
  //  2. else a nominal set point within 3 % of the recording's mean speed (e.g. the config's speed);
  //  3. else the mean speed rounded to whole rpm (setpoint_whole_rpm) or the mean speed itself.
  std::vector<double> setpoints_rad_s;
  std::vector<double> nominal_setpoints_rad_s;
  bool setpoint_whole_rpm = true;
};

struct Mismatch {              // one cell of the located residual
  std::string dataset, channel;
  int order = 0;               // harmonic order of the drive frequency; kReportOrders+1 = higher orders
  double excess_chi2 = 0;      // residual power in units of noise, above what noise alone gives
  double share = 0;            // fraction of the total excess
  double nrmse = 0;            // residual / recording at that order
};

struct DiagnosisResult {
  std::string effect;          // "none", "unexplained", or the named terms (selection.hpp effect_label)
  std::string reason;
  int chosen = -1;             // index into candidates of the first named term
  std::vector<TermFit> named;  // every named term with its fitted value (after the joint refit)
  std::vector<SelectionStep> steps;  // the forward selection, step by step
  ParamSet fitted;             // the named terms at their values
  std::vector<Dataset> train, heldout;
  std::vector<Comparison> naive_train;                     // no alignment (tau = 0, gain = 1)
  std::vector<Comparison> before_train, before_heldout;    // unchanged model, aligned
  std::vector<Comparison> after_train, after_heldout;      // with the named terms
  std::vector<TermFit> candidates;                         // the first step's fits (every candidate)
  std::vector<Mismatch> located;                           // ranked, largest first
  double nonphysical_share = 0;    // share of the naive residual removed by time offset and gain
  bool residual_significant = false;
  int model_runs = 0;
  int model_failures = 0;          // runs that threw (counted as a bad fit), and the last message
  std::string last_model_failure;
  double wall_s = 0;
};

std::vector<Term> default_candidates();
std::string dataset_label(const Recording& r, double t0, double t1);

// Recordings: the first is training (with a time split when it is the only one), the rest held out.
// candidates: omitted effects and uncertain values (ConfigModel::uncertain) alike.
DiagnosisResult diagnose(const std::vector<Recording>& recordings, const ModelFn& model,
                         const std::vector<Term>& candidates, const DiagnosisOptions& opt = {});
// Fills effect, chosen, named, steps, fitted, candidates and reason from a selection.
void adopt_selection(DiagnosisResult& r, const Selection& sel, const DiagnosisOptions& opt);

// Excess of a comparison's harmonic residual over noise, summed over channels (chi2 - dof, >= 0).
double structured_excess(const Comparison& c);

std::string diagnosis_json(const DiagnosisResult& r);
std::string diagnosis_markdown(const DiagnosisResult& r);

}  // namespace analysis
