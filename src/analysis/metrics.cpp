#include "analysis/metrics.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace analysis {

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / v.size();
}
double variance(const std::vector<double>& v) {
  const double m = mean(v);
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return v.empty() ? 0.0 : s / v.size();
}
double rms(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return v.empty() ? 0.0 : std::sqrt(s / v.size());
}

double nrmse(const std::vector<double>& y, const std::vector<double>& yhat) {
  if (y.size() != yhat.size() || y.empty())
    throw std::invalid_argument("nrmse: signals must be non-empty and of equal length");
  const double m = mean(y);
  double num = 0, den = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    num += (y[i] - yhat[i]) * (y[i] - yhat[i]);
    den += (y[i] - m) * (y[i] - m);
  }
  if (den <= 0) return num <= 0 ? 0.0 : std::numeric_limits<double>::infinity();
  return std::sqrt(num / den);
}

double minus_two_log_likelihood(const std::vector<double>& rss, const std::vector<double>& n) {
  if (rss.size() != n.size()) throw std::invalid_argument("likelihood: rss and n differ in length");
  double s = 0;
  for (std::size_t c = 0; c < rss.size(); ++c) {
    if (!(rss[c] > 0) || !(n[c] > 0)) throw std::invalid_argument("likelihood: rss and n must be positive");
    s += n[c] * std::log(rss[c] / n[c]);
  }
  return s;
}
double aic(const std::vector<double>& rss, const std::vector<double>& n, int k) {
  return minus_two_log_likelihood(rss, n) + 2.0 * k;
}
double bic(const std::vector<double>& rss, const std::vector<double>& n, int k) {
  double N = 0;
  for (double x : n) N += x;
  return minus_two_log_likelihood(rss, n) + k * std::log(N);
}

}  // namespace analysis
