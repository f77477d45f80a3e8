#include "rocks/taguchi.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

namespace rocks {

const std::vector<std::vector<int>>& l16_array() {
  // Taguchi's standard L16 (4^5); Table 2 assigns normal strength to column 1, shear strength to 2,
  // error to 3, shear stiffness to 4 and bond disk radius to 5.
  static const std::vector<std::vector<int>> a = {
      {1, 1, 1, 1, 1}, {1, 2, 2, 2, 2}, {1, 3, 3, 3, 3}, {1, 4, 4, 4, 4},
      {2, 1, 2, 3, 4}, {2, 2, 1, 4, 3}, {2, 3, 4, 1, 2}, {2, 4, 3, 2, 1},
      {3, 1, 3, 4, 2}, {3, 2, 4, 3, 1}, {3, 3, 1, 2, 4}, {3, 4, 2, 1, 3},
      {4, 1, 4, 2, 3}, {4, 2, 3, 1, 4}, {4, 3, 2, 4, 1}, {4, 4, 1, 3, 2}};
  return a;
}

bool is_orthogonal(const std::vector<std::vector<int>>& runs, int levels) {
  if (runs.empty() || levels < 2) return false;
  const std::size_t cols = runs[0].size();
  for (const auto& r : runs) {
    if (r.size() != cols) return false;
    for (int v : r)
      if (v < 1 || v > levels) return false;
  }
  const std::size_t pairs = static_cast<std::size_t>(levels) * levels;
  if (runs.size() % pairs != 0) return false;
  const std::size_t each = runs.size() / pairs;
  for (std::size_t a = 0; a < cols; ++a)
    for (std::size_t b = a + 1; b < cols; ++b) {
      std::vector<std::size_t> count(pairs, 0);
      for (const auto& r : runs) ++count[(r[a] - 1) * levels + (r[b] - 1)];
      for (std::size_t c : count)
        if (c != each) return false;
    }
  return true;
}

namespace {
// Continued fraction for I_x(a, b) (converges fast for x < (a + 1) / (a + b + 2)).
double beta_cf(double a, double b, double x) {
  const double tiny = 1e-300, eps = 1e-15;
  double c = 1.0, d = 1.0 - (a + b) * x / (a + 1.0);
  if (std::fabs(d) < tiny) d = tiny;
  d = 1.0 / d;
  double h = d;
  for (int m = 1; m <= 10000; ++m) {
    const double m2 = 2.0 * m;
    double aa = m * (b - m) * x / ((a + m2 - 1.0) * (a + m2));  // even step
    d = 1.0 + aa * d;
    if (std::fabs(d) < tiny) d = tiny;
    c = 1.0 + aa / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1.0 / d;
    h *= d * c;
    aa = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1.0));  // odd step
    d = 1.0 + aa * d;
    if (std::fabs(d) < tiny) d = tiny;
    c = 1.0 + aa / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::fabs(del - 1.0) < eps) return h;
  }
  throw std::runtime_error("incomplete_beta: continued fraction did not converge");
}
}  // namespace

double incomplete_beta(double a, double b, double x) {
  if (!(a > 0.0) || !(b > 0.0) || !(x >= 0.0 && x <= 1.0))
    throw std::invalid_argument("incomplete_beta: need a > 0, b > 0 and x in [0, 1]");
  if (x == 0.0 || x == 1.0) return x;
  const double lbt = std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
  const double front = std::exp(lbt);
  if (x < (a + 1.0) / (a + b + 2.0)) return front * beta_cf(a, b, x) / a;
  return 1.0 - front * beta_cf(b, a, 1.0 - x) / b;  // symmetry I_x(a,b) = 1 - I_{1-x}(b,a)
}

double f_distribution_sf(double f, double d1, double d2) {
  if (!(d1 > 0.0) || !(d2 > 0.0)) throw std::invalid_argument("f_distribution_sf: degrees of freedom must be > 0");
  if (std::isnan(f)) return std::numeric_limits<double>::quiet_NaN();
  if (f <= 0.0) return 1.0;
  if (std::isinf(f)) return 0.0;
  // P(F > f) = I_{d2 / (d2 + d1 f)}(d2 / 2, d1 / 2)
  return incomplete_beta(0.5 * d2, 0.5 * d1, d2 / (d2 + d1 * f));
}

std::vector<std::vector<double>> marginal_means(const std::vector<std::vector<int>>& runs,
                                                const std::vector<double>& y, int levels) {
  if (runs.size() != y.size() || runs.empty())
    throw std::invalid_argument("marginal_means: one response per run needed");
  const std::size_t cols = runs[0].size();
  std::vector<std::vector<double>> mean(cols, std::vector<double>(levels, 0.0));
  for (std::size_t c = 0; c < cols; ++c) {
    std::vector<int> n(levels, 0);
    for (std::size_t r = 0; r < runs.size(); ++r) {
      const int l = runs[r].at(c);
      if (l < 1 || l > levels) throw std::invalid_argument("marginal_means: level out of range");
      mean[c][l - 1] += y[r];
      ++n[l - 1];
    }
    for (int l = 0; l < levels; ++l) mean[c][l] = n[l] ? mean[c][l] / n[l] : std::numeric_limits<double>::quiet_NaN();
  }
  return mean;
}

AnovaTable anova(const std::vector<std::vector<int>>& runs, const std::vector<double>& y,
                 const std::vector<std::string>& names, const std::vector<int>& error_columns, int levels) {
  if (runs.size() != y.size() || runs.size() < 2) throw std::invalid_argument("anova: one response per run, >= 2 runs");
  const std::size_t cols = runs[0].size();
  if (names.size() != cols) throw std::invalid_argument("anova: one name per column");
  for (int e : error_columns)
    if (e < 0 || e >= static_cast<int>(cols)) throw std::invalid_argument("anova: error column out of range");
  AnovaTable t;
  const double n = static_cast<double>(y.size());
  for (double v : y) t.grand_mean += v / n;
  double sst = 0.0;
  for (double v : y) sst += (v - t.grand_mean) * (v - t.grand_mean);
  t.total = {"Total", static_cast<int>(y.size()) - 1, sst, 0, 0, 1};
  const auto means = marginal_means(runs, y, levels);
  double ss_factors = 0.0;
  int df_factors = 0;
  for (std::size_t c = 0; c < cols; ++c) {
    bool is_error = false;
    for (int e : error_columns) is_error |= (e == static_cast<int>(c));
    if (is_error) continue;
    std::vector<int> cnt(levels, 0);
    for (const auto& r : runs) ++cnt[r[c] - 1];
    AnovaRow row;
    row.source = names[c];
    for (int l = 0; l < levels; ++l)
      if (cnt[l]) {
        row.ss += cnt[l] * (means[c][l] - t.grand_mean) * (means[c][l] - t.grand_mean);
        ++row.df;
      }
    row.df -= 1;
    row.ms = row.df > 0 ? row.ss / row.df : 0.0;
    ss_factors += row.ss;
    df_factors += row.df;
    t.factors.push_back(row);
  }
  t.error.source = "Error";
  t.error.df = t.total.df - df_factors;
  t.error.ss = std::max(0.0, sst - ss_factors);
  t.error.ms = t.error.df > 0 ? t.error.ss / t.error.df : std::numeric_limits<double>::quiet_NaN();
  for (auto& row : t.factors) {
    if (t.error.df > 0 && t.error.ms > 0.0) {
      row.F = row.ms / t.error.ms;
      row.p = f_distribution_sf(row.F, row.df, t.error.df);
    } else {
      row.F = row.p = std::numeric_limits<double>::quiet_NaN();
    }
  }
  return t;
}

std::string format_anova(const AnovaTable& t, const std::string& response) {
  std::ostringstream s;
  char buf[256];
  s << "ANOVA: " << response << "\n";
  std::snprintf(buf, sizeof buf, "%-28s %3s %14s %14s %10s %8s\n", "Source", "DF", "SS", "MS", "F", "p");
  s << buf;
  for (const auto& r : t.factors) {
    std::snprintf(buf, sizeof buf, "%-28s %3d %14.6g %14.6g %10.4g %8.4f\n", r.source.c_str(), r.df, r.ss, r.ms, r.F,
                  r.p);
    s << buf;
  }
  std::snprintf(buf, sizeof buf, "%-28s %3d %14.6g %14.6g\n", "Error", t.error.df, t.error.ss, t.error.ms);
  s << buf;
  std::snprintf(buf, sizeof buf, "%-28s %3d %14.6g\n", "Total", t.total.df, t.total.ss);
  s << buf;
  return s.str();
}

}  // namespace rocks
