#include "analysis/optimise.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace analysis {

Minimum golden_section(const std::function<double(double)>& f, double a, double b, double tol,
                       int max_evaluations) {
  if (!(b > a)) throw std::invalid_argument("golden_section: empty interval");
  const double r = (std::sqrt(5.0) - 1.0) / 2.0;  // 0.618...
  double c = b - r * (b - a), d = a + r * (b - a);
  double fc = f(c), fd = f(d);
  int n = 2;
  while (b - a > tol && n < max_evaluations) {
    if (fc < fd) {
      b = d; d = c; fd = fc;
      c = b - r * (b - a); fc = f(c);
    } else {
      a = c; c = d; fc = fd;
      d = a + r * (b - a); fd = f(d);
    }
    ++n;
  }
  Minimum m;
  m.evaluations = n;
  if (fc < fd) { m.x = c; m.f = fc; } else { m.x = d; m.f = fd; }
  return m;
}

Minimum minimise_scan_golden(const std::function<double(double)>& f, double a, double b, int n, double tol) {
  if (n < 3) throw std::invalid_argument("minimise_scan_golden: need at least 3 scan points");
  std::vector<double> x(n), fx(n);
  int best = 0;
  for (int i = 0; i < n; ++i) {
    x[i] = a + (b - a) * i / (n - 1);
    fx[i] = f(x[i]);
    if (fx[i] < fx[best]) best = i;
  }
  const double lo = x[std::max(best - 1, 0)], hi = x[std::min(best + 1, n - 1)];
  Minimum m = golden_section(f, lo, hi, tol);
  m.evaluations += n;
  if (fx[best] < m.f) { m.x = x[best]; m.f = fx[best]; }
  return m;
}

Minimum minimise_periodic_scan_golden(const std::function<double(double)>& f, double period, int n, double tol) {
  if (n < 3) throw std::invalid_argument("minimise_periodic_scan_golden: need at least 3 scan points");
  if (!(period > 0)) throw std::invalid_argument("minimise_periodic_scan_golden: the period must be positive");
  const double step = period / n;
  int best = 0;
  double fbest = f(0.0);
  for (int i = 1; i < n; ++i) {
    const double v = f(i * step);
    if (v < fbest) fbest = v, best = i;
  }
  Minimum m = golden_section(f, (best - 1) * step, (best + 1) * step, tol);
  m.evaluations += n;
  if (fbest < m.f) { m.x = best * step; m.f = fbest; }
  m.x = std::fmod(std::fmod(m.x, period) + period, period);
  return m;
}

double second_derivative(const std::function<double(double)>& f, double x, double fx, double h) {
  return (f(x + h) - 2.0 * fx + f(x - h)) / (h * h);
}

}  // namespace analysis
