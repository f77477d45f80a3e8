#pragma once
// Taguchi design of experiments for the BPM calibration (paper section 2.4.3-2.4.4, Tables 2-3):
// the standard L16 (4^5) orthogonal array, main-effect ANOVA with an error column, marginal means,
// and the F distribution's p-value via the regularised incomplete beta function.
#include <array>
#include <string>
#include <vector>

namespace rocks {

// Standard L16(4^5) array: 16 runs x 5 columns, levels 1..4 (Taguchi's table, as in Minitab).
const std::vector<std::vector<int>>& l16_array();

// True when every pair of columns contains every pair of levels equally often (and each column is
// balanced). `levels` is the number of levels, numbered 1..levels.
bool is_orthogonal(const std::vector<std::vector<int>>& runs, int levels);

// Regularised incomplete beta function I_x(a, b), a, b > 0, x in [0, 1] (continued fraction,
// modified Lentz method). Throws std::invalid_argument outside the domain.
double incomplete_beta(double a, double b, double x);
// Upper tail P(F > f) of the F distribution with (d1, d2) degrees of freedom.
double f_distribution_sf(double f, double d1, double d2);

struct AnovaRow {
  std::string source;
  int df = 0;
  double ss = 0, ms = 0;
  double F = 0, p = 1;  // F = MS / MS_error, p = P(F(df, df_error) > F); NaN when df_error == 0
};

struct AnovaTable {
  std::vector<AnovaRow> factors;  // in column order, error columns left out
  AnovaRow error;                 // error columns + residual (pooled)
  AnovaRow total;
  double grand_mean = 0;
};

// Main-effect ANOVA. runs[r][c] = level (1..levels) of column c in run r; y[r] the response.
// Each non-error column is a factor with levels-1 DF and SS = sum_l n_l (mean_l - mean)^2; the
// error is SS_total minus the factors' SS (so error columns and replication both land there).
// names has one entry per column. Throws std::invalid_argument on inconsistent sizes.
AnovaTable anova(const std::vector<std::vector<int>>& runs, const std::vector<double>& y,
                 const std::vector<std::string>& names, const std::vector<int>& error_columns, int levels);

// means[c][l] = mean response over runs with column c at level l+1.
std::vector<std::vector<double>> marginal_means(const std::vector<std::vector<int>>& runs,
                                                const std::vector<double>& y, int levels);

// Text rendering of an ANOVA table (DF, SS, MS, F, p).
std::string format_anova(const AnovaTable& t, const std::string& response);

}  // namespace rocks
