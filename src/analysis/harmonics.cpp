#include "analysis/harmonics.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>
#include <string>

#include "analysis/optimise.hpp"

namespace analysis {

double Harmonics::amplitude(int k) const { return std::abs(C.at(k)); }
double Harmonics::phase(int k) const { return std::arg(C.at(k)); }
double Harmonics::power(int k) const {
  return k == 0 ? std::norm(C.at(0)) : 0.5 * std::norm(C.at(k));
}
double Harmonics::value(double t, double tau) const {
  double y = C[0].real();
  const double ph = omega * (t - tau);
  // Chebyshev-style recurrence would be faster; direct evaluation keeps it obviously right.
  for (int k = 1; k <= orders(); ++k) y += (C[k] * std::polar(1.0, k * ph)).real();
  return y;
}

Harmonics fit_harmonics(const std::vector<double>& t, const std::vector<double>& y, double omega, int K) {
  if (!(omega > 0)) throw std::invalid_argument("fit_harmonics: fundamental must be positive, got " + std::to_string(omega));
  if (t.size() != y.size()) throw std::invalid_argument("fit_harmonics: t and y differ in length");
  const int p = 2 * K + 1;
  if (static_cast<int>(t.size()) < 2 * p)
    throw std::invalid_argument("fit_harmonics: " + std::to_string(t.size()) + " samples are too few for " +
                                std::to_string(K) + " orders (need " + std::to_string(2 * p) + ")");
  // Normal equations accumulated column by column (p is small, n large); centre time for conditioning.
  Eigen::MatrixXd AtA = Eigen::MatrixXd::Zero(p, p);
  Eigen::VectorXd Aty = Eigen::VectorXd::Zero(p);
  Eigen::VectorXd row(p);
  for (std::size_t i = 0; i < t.size(); ++i) {
    row[0] = 1.0;
    const std::complex<double> e1 = std::polar(1.0, omega * t[i]);
    std::complex<double> e = 1.0;
    for (int k = 1; k <= K; ++k) {
      e *= e1;
      row[2 * k - 1] = e.real();
      row[2 * k] = e.imag();
    }
    AtA.selfadjointView<Eigen::Lower>().rankUpdate(row);
    Aty += row * y[i];
  }
  AtA = AtA.selfadjointView<Eigen::Lower>();
  Eigen::VectorXd x = AtA.ldlt().solve(Aty);
  Harmonics h;
  h.omega = omega;
  h.C.resize(K + 1);
  h.C[0] = x[0];
  for (int k = 1; k <= K; ++k) h.C[k] = std::complex<double>(x[2 * k - 1], -x[2 * k]);
  return h;
}

std::vector<double> harmonic_remainder(const std::vector<double>& t, const std::vector<double>& y,
                                       const Harmonics& h) {
  std::vector<double> r(y.size());
  for (std::size_t i = 0; i < y.size(); ++i) r[i] = y[i] - h.value(t[i]);
  return r;
}

double refine_fundamental(const std::vector<double>& t, const std::vector<const std::vector<double>*>& ys,
                          double omega0, double rel, int K) {
  // Least-squares residual of the harmonic fit, relative to each signal's variance: minimal at the
  // true fundamental whatever the number of periods in the record.
  auto neg_explained = [&](double w) {
    double s = 0;
    for (const auto* y : ys) {
      Harmonics h = fit_harmonics(t, *y, w, K);
      double m = 0, var = 0, rss = 0;
      for (double v : *y) m += v;
      m /= y->size();
      for (std::size_t i = 0; i < y->size(); ++i) {
        const double r = (*y)[i] - h.value(t[i]);
        rss += r * r;
        var += ((*y)[i] - m) * ((*y)[i] - m);
      }
      s += var > 0 ? rss / var : 0.0;
    }
    return s;
  };
  // The explained power peaks within ~1/(duration) of the true frequency: scan finer than that.
  const double T = t.back() - t.front();
  const double width = 2.0 * rel * omega0;
  int n = static_cast<int>(std::ceil(width * T / (2 * M_PI) * 4)) + 1;
  n = std::max(5, std::min(n, 201));
  return minimise_scan_golden(neg_explained, omega0 * (1 - rel), omega0 * (1 + rel), n, 1e-7 * omega0).x;
}

}  // namespace analysis
