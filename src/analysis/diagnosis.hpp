#pragma once
// Mismatch diagnosis (issue 6): locate where a model and recordings differ, name the omitted effect
// among the candidate modules, fit it with the simulation in the loop, show the fit improve.
#include <functional>
#include <string>
#include <vector>

#include "analysis/comparison.hpp"

namespace analysis {

// One candidate omitted effect and the search range of its main parameter (in the unit shown, the
// unit of the YAML key mbd.effects.<name>.<parameter>).
struct EffectSpec {
  std::string name, parameter, unit;
  double lo = 0, hi = 1;
};

// Runs the model with `effect` ("none" or a candidate name) whose main parameter is `value`, the drive
// set point at `speed_rad_s`; returns >= duration_s of steady state.
using ModelFn = std::function<Recording(const std::string& effect, double value, double speed_rad_s,
                                        double duration_s)>;

struct DiagnosisOptions {
  double model_seconds = 3.0;      // steady-state model time per run: 1 s biased a fitted angle by 2 %
                                   // (slow non-periodic content); 3 s by 0.2 %
  double heldout_fraction = 0.4;   // time split when only one recording is given
  int scan_points = 7;             // coarse scan of each main parameter before golden-section search
  double rel_tol = 2e-3;           // golden-section tolerance, fraction of the search range
  double bic_threshold = 10.0;     // a candidate must lower BIC by this much (strong evidence, Kass-Raftery)
  double min_explained = 0.5;      // ... and remove this fraction of the structured residual, held out too
  double z_significance = 5.0;     // chi-square test of the residual against noise, in normal sigmas
  // Drive set point of each recording (the model runs at it; with droop the speed falls below it):
  //  1. setpoints_rad_s[i] for recording i when given (the plant's control system knows them);
  //  2. else a nominal set point within 3 % of the recording's mean speed (e.g. the config's speed);
  //  3. else the mean speed rounded to whole rpm (setpoint_whole_rpm) or the mean speed itself.
  std::vector<double> setpoints_rad_s;
  std::vector<double> nominal_setpoints_rad_s;
  bool setpoint_whole_rpm = true;
};

struct CandidateResult {
  EffectSpec spec;
  double value = 0, sigma = 0;     // fitted main parameter and its 1-sigma uncertainty (cost curvature,
                                   // widened by the Birge ratio when the fit leaves excess residual)
  double aic = 0, bic = 0, delta_aic = 0, delta_bic = 0;   // delta: relative to the unchanged model
  double explained_train = 0, explained_heldout = 0;       // fraction of structured residual removed
  double nrmse_train = 0, nrmse_heldout = 0;               // noise-weighted overall NRMSE after fit
  int evaluations = 0;
  std::vector<std::pair<double, double>> profile;          // (value, cost) points seen
};

struct Mismatch {              // one cell of the located residual
  std::string dataset, channel;
  int order = 0;               // harmonic order of the drive frequency; kReportOrders+1 = higher orders
  double excess_chi2 = 0;      // residual power in units of noise, above what noise alone gives
  double share = 0;            // fraction of the total excess
  double nrmse = 0;            // residual / recording at that order
};

struct DiagnosisResult {
  std::string effect;          // a candidate name, "none" or "unexplained"
  std::string reason;
  int chosen = -1;             // index into candidates
  std::vector<Dataset> train, heldout;
  std::vector<Comparison> naive_train;                     // no alignment (tau = 0, gain = 1)
  std::vector<Comparison> before_train, before_heldout;    // unchanged model, aligned
  std::vector<Comparison> after_train, after_heldout;      // chosen (or best) candidate
  std::vector<CandidateResult> candidates;
  std::vector<Mismatch> located;                           // ranked, largest first
  double nonphysical_share = 0;    // share of the naive residual removed by time offset and gain
  bool residual_significant = false;
  int model_runs = 0;
  int model_failures = 0;          // runs that threw (counted as a bad fit), and the last message
  std::string last_model_failure;
  double wall_s = 0;
};

std::vector<EffectSpec> default_candidates();
std::string dataset_label(const Recording& r, double t0, double t1);

// Recordings: the first is training (with a time split when it is the only one), the rest held out.
DiagnosisResult diagnose(const std::vector<Recording>& recordings, const ModelFn& model,
                         const std::vector<EffectSpec>& candidates, const DiagnosisOptions& opt = {});

// Excess of a comparison's harmonic residual over noise, summed over channels (chi2 - dof, >= 0).
double structured_excess(const Comparison& c);

std::string diagnosis_json(const DiagnosisResult& r);
std::string diagnosis_markdown(const DiagnosisResult& r);

}  // namespace analysis
