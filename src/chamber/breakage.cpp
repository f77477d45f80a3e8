#include "chamber/breakage.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace chamber {

double critical_compression(const BreakageParams& p, double x) {
  if (x >= p.x_resolved) return p.s_c * std::pow(x / p.x_ref, -p.q);
  return critical_compression(p, p.x_resolved) * std::pow(x / p.x_resolved, -p.q_below);
}

Breakage::Breakage(const std::vector<double>& sieves, const BreakageParams& p) : p_(p) {
  if (sieves.empty()) throw std::invalid_argument("breakage: needs at least one sieve");
  for (std::size_t i = 0; i < sieves.size(); ++i)
    if (!(sieves[i] > 0) || (i > 0 && sieves[i] <= sieves[i - 1]))
      throw std::invalid_argument("breakage: sieves must be positive and strictly ascending");
  if (!(p.s_c > 0) || !(p.m > 0) || p.q < 0 || !(p.x_ref > 0) || p.x_resolved < 0 || p.q_below < 0)
    throw std::invalid_argument(
        "breakage: selection needs s_c > 0, exponent > 0, size_exponent >= 0, x_ref > 0, resolved size >= 0, "
        "size_exponent_below >= 0");
  if (p.phi < 0 || p.phi > 1 || !(p.gamma > 0) || !(p.beta > 0))
    throw std::invalid_argument("breakage: progeny needs phi in [0, 1], gamma > 0, beta > 0");
  const std::size_t K = sieves.size();
  for (std::size_t j = 0; j <= K; ++j) {
    const double lo = j == 0 ? 0.0 : sieves[j - 1], up = j == K ? sieves[K - 1] * std::sqrt(2.0) : sieves[j];
    lo_.push_back(lo);
    up_.push_back(up);
    x_.push_back(j == 0 ? 0.5 * sieves[0] : std::sqrt(lo * up));
    sc_.push_back(critical_compression(p, x_.back()));
  }
  const std::size_t n = x_.size();
  B_.assign(n * n, 0.0);
  auto cum = [&](double x, double y) {
    const double u = std::min(1.0, x / y);
    return p.phi * std::pow(u, p.gamma) + (1.0 - p.phi) * std::pow(u, p.beta);
  };
  for (std::size_t j = 0; j < n; ++j) {
    // Progeny of class j: what passes each lower bound goes below it; the rest stays in class j.
    double above = 1.0;
    for (std::size_t i = j + 1; i-- > 0;) {
      const double below = i == 0 ? 0.0 : cum(lo_[i], up_[j]);
      B_[i * n + j] = above - below;
      above = below;
    }
  }
  work_.resize(n);
}

double Breakage::selection_between(std::size_t j, double s0, double s1) const {
  if (s1 <= s0 || s1 <= 0) return 0.0;
  const double rise = std::pow(s1 / sc_[j], p_.m) - (s0 > 0 ? std::pow(s0 / sc_[j], p_.m) : 0.0);
  return 1.0 - std::exp(-rise);
}

void Breakage::apply_between(double s0, double s1, double* f) const {
  const std::size_t n = x_.size();
  for (std::size_t i = 0; i < n; ++i) work_[i] = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    if (f[j] == 0.0) continue;
    const double broken = selection_between(j, s0, s1) * f[j];
    work_[j] += f[j] - broken;
    for (std::size_t i = 0; i <= j; ++i) work_[i] += b(i, j) * broken;
  }
  for (std::size_t i = 0; i < n; ++i) f[i] = work_[i];
}

}  // namespace chamber
