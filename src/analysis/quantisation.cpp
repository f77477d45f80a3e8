#include "analysis/quantisation.hpp"

#include <algorithm>
#include <cmath>

namespace analysis {

double estimate_resolution(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  std::vector<double> s = v;
  std::sort(s.begin(), s.end());
  const double scale = std::max(std::abs(s.front()), std::abs(s.back()));
  const double tiny = 1e-12 * scale;
  double q = 0;
  for (std::size_t i = 1; i < s.size(); ++i) {
    const double step = s[i] - s[i - 1];
    if (step > tiny && (q == 0 || step < q)) q = step;
  }
  return q;
}

double undithered_quantisation_variance(double q, double noise_var) {
  if (!(q > 0)) return 0.0;
  const double pi = 3.14159265358979323846;
  return quantisation_variance(q) * std::exp(-4.0 * pi * pi * std::max(0.0, noise_var) / (q * q));
}

bool constant_within_resolution(const std::vector<double>& v, double q) {
  if (v.empty()) return false;
  std::vector<double> s = v;
  std::sort(s.begin(), s.end());
  const std::size_t n = s.size();
  const double lo = s[n / 100], hi = s[n - 1 - n / 100];
  const double scale = std::max(std::abs(s.front()), std::abs(s.back()));
  return hi - lo <= 2.0 * q * (1 + 1e-9) + 1e-12 * scale;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace analysis
