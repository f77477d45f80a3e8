#include "chamber/mixture_packing.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace chamber {
namespace {
void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("mixture packing: " + what);
}
}  // namespace

MixturePacking::MixturePacking(const std::vector<double>& sizes_m, double beta, double compaction_index)
    : n_(sizes_m.size()), beta_(beta), K_(compaction_index) {
  require(n_ > 0 && n_ <= kMaxClasses, "needs 1 to " + std::to_string(kMaxClasses) + " size classes");
  for (double d : sizes_m) require(d > 0 && std::isfinite(d), "class sizes must be > 0");
  require(beta > 0 && beta < 1, "beta (one size's virtual packing) must be in (0, 1)");
  require(compaction_index > 0 && std::isfinite(compaction_index), "the compaction index K must be > 0");
  m_.assign(n_ * n_, 0.0);
  for (std::size_t i = 0; i < n_; ++i)
    for (std::size_t j = 0; j < n_; ++j) {
      const double di = sizes_m[i], dj = sizes_m[j];
      if (dj > di) {  // coarser: its wall loosens the packing of class i near it
        const double b = 1.0 - std::pow(1.0 - di / dj, 1.50);
        m_[i * n_ + j] = (1.0 - beta) * (1.0 - b);
      } else if (dj < di) {  // finer: it pushes class i's grains apart
        const double a = std::sqrt(1.0 - std::pow(1.0 - dj / di, 1.02));
        m_[i * n_ + j] = 1.0 - a;
      }  // the same size: no interaction
    }
}

double MixturePacking::fraction(const double* kg, double guess) const {
  double total = 0;
  for (std::size_t i = 0; i < n_; ++i) total += kg[i];
  require(total > 0, "the mixture needs mass");
  // c_i = 1 / gamma_i and w_i = y_i / beta of the classes present.
  double cc[kMaxClasses], ww[kMaxClasses];
  double c_max = 0, w_max = 0, w_sum = 0;
  std::size_t present = 0;
  for (std::size_t i = 0; i < n_; ++i) {
    if (kg[i] <= 0) continue;
    double s = 0;
    for (std::size_t j = 0; j < n_; ++j) s += m_[i * n_ + j] * kg[j];
    cc[present] = (1.0 - s / total) / beta_;
    ww[present] = kg[i] / (total * beta_);
    if (cc[present] > c_max) c_max = cc[present], w_max = ww[present];
    w_sum += ww[present];
    ++present;
  }
  // f(x) = sum w_i / (x - c_i) - K, x = 1 / Phi > c_max: decreasing and convex, its root within [c_max + w_max / K,
  // c_max + sum w / K]. Newton from a guess, kept inside the bracket (from the left of the root it climbs monotonically).
  double lo = c_max + w_max / K_, hi = c_max + w_sum / K_;
  double x = guess > 0 && 1.0 / guess > lo && 1.0 / guess < hi ? 1.0 / guess : lo;
  for (int it = 0; it < 100; ++it) {
    double f = -K_, df = 0;
    for (std::size_t i = 0; i < present; ++i) {
      const double r = 1.0 / (x - cc[i]);
      f += ww[i] * r;
      df -= ww[i] * r * r;
    }
    if (f == 0) return 1.0 / x;
    (f > 0 ? lo : hi) = x;
    double next = x - f / df;
    if (!(next >= lo && next <= hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - x) <= 1e-13 * x) return 1.0 / next;
    x = next;
  }
  return 1.0 / x;
}

double MixturePacking::beta_for(const std::vector<double>& sizes_m, double compaction_index,
                                const std::vector<double>& kg, double fraction) {
  require(kg.size() == sizes_m.size(), "the reference mixture needs one mass per class");
  require(fraction > 0 && fraction < 1, "the reference packing must be in (0, 1)");
  auto packs = [&](double beta) { return MixturePacking(sizes_m, beta, compaction_index).fraction(kg.data()); };
  double lo = 1e-6, hi = 1.0 - 1e-9;
  require(packs(hi) > fraction, "no beta below 1 packs the reference mixture that densely");
  for (int it = 0; it < 200 && hi - lo > 1e-15; ++it) {
    const double mid = 0.5 * (lo + hi);
    (packs(mid) < fraction ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

std::vector<double> even_size_mixture(const std::vector<double>& lower_m, const std::vector<double>& upper_m, double lo_m,
                                      double hi_m) {
  require(lower_m.size() == upper_m.size(), "class bounds differ in number");
  require(lo_m > 0 && hi_m > lo_m, "the reference sizes need 0 < min < max");
  std::vector<double> kg;
  for (std::size_t j = 0; j < lower_m.size(); ++j)
    kg.push_back(std::max(0.0, std::min(upper_m[j], hi_m) - std::max(lower_m[j], lo_m)) / (hi_m - lo_m));
  return kg;
}

}  // namespace chamber
