#pragma once
// The diagnosis on summary recordings (issue 24): the plant's Table-5 statistics per speed against the same
// statistics of the fast model, the residual judged against each value's stated uncertainty, and the terms that
// explain it named by the same forward selection as for time series (selection.hpp).
//
// Every row trains (a handful of numbers per speed leaves nothing to hold out); instead a term must not make any
// row worse: a row consistent with its uncertainty stays so, an inconsistent row's chi-square must not rise, and a
// std the plant gives but that is not compared must not rise above the plant's (the model has no feed or sensor
// scatter: a larger std is its own unsteadiness).
#include <string>
#include <vector>

#include "analysis/selection.hpp"
#include "analysis/summary_data.hpp"

namespace analysis {

struct SummaryDiagnosisOptions {
  SelectionOptions selection = [] {
    SelectionOptions o;
    o.fit_when_consistent = false;  // each fit costs minutes of fast-mode runs
    return o;
  }();
  double z_significance = 5.0;  // a row's chi-square beyond dof + z sqrt(2 dof) is significant
};

struct RowComparison {
  double speed_rad_s = 0;
  Stats plant, model;           // every quantity the plant row gives / the model's values
  Stats z;                      // (model - plant) / uncertainty, compared quantities only
  double chi2 = 0;
  int dof = 0;
};

struct SummaryDiagnosis {
  std::string effect, reason;   // as DiagnosisResult: "none", "unexplained" or the named terms
  SummaryRecording data;
  std::vector<RowComparison> before, after;
  Selection selection;
  int model_runs = 0, model_failures = 0;
  std::string last_model_failure;
  double wall_s = 0;
};

SummaryDiagnosis diagnose_summary(const SummaryRecording& data, const SummaryModelFn& model,
                                  const std::vector<Term>& candidates, const SummaryDiagnosisOptions& opt = {});
std::string summary_diagnosis_json(const SummaryDiagnosis& d);
std::string summary_diagnosis_markdown(const SummaryDiagnosis& d);

}  // namespace analysis
