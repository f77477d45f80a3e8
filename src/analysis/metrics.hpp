#pragma once
// Goodness-of-fit measures and information criteria.
#include <vector>

namespace analysis {

// Normalised root-mean-square error, NRMSE = ||y - yhat|| / ||y - mean(y)|| (as in MATLAB goodnessOfFit
// 'NRMSE' and System Identification 'compare'); 0 = perfect, 1 = no better than the mean.
double nrmse(const std::vector<double>& y, const std::vector<double>& yhat);
// Fit percent = 100 (1 - NRMSE).
inline double fit_percent(double nrmse_value) { return 100.0 * (1.0 - nrmse_value); }
double rms(const std::vector<double>& v);
double mean(const std::vector<double>& v);
double variance(const std::vector<double>& v);  // population variance

// Gaussian-likelihood criteria for independent channels c with n_c residuals and sum of squares
// rss_c, variance of each channel a free parameter: -2 ln L = sum_c n_c ln(rss_c / n_c) (+ const).
// AIC = -2 ln L + 2 k (Akaike 1974); BIC = -2 ln L + k ln(sum n_c) (Schwarz 1978).
double minus_two_log_likelihood(const std::vector<double>& rss, const std::vector<double>& n);
double aic(const std::vector<double>& rss, const std::vector<double>& n, int k);
double bic(const std::vector<double>& rss, const std::vector<double>& n, int k);

}  // namespace analysis
