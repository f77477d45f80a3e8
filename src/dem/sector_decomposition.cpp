#include "dem/sector_decomposition.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace dem {

namespace {
constexpr double kTurn = 2.0 * M_PI;

// Azimuth of (x, y) in [a0, a0 + 2 pi).
double azimuth_from(double x, double y, double a0) {
  double a = std::atan2(y, x) - a0;
  a -= kTurn * std::floor(a / kTurn);
  if (a >= kTurn) a = 0;  // round-off of floor
  return a0 + a;
}

// Distance from (x, y, any z) to the half-plane through the z axis at azimuth a (c = cos a, s = sin a).
double to_half_plane(double x, double y, double c, double s) {
  const double along = x * c + y * s;
  return along >= 0 ? std::abs(y * c - x * s) : std::hypot(x, y);
}
}  // namespace

SectorDecomposition::SectorDecomposition(std::vector<double> bounds) : bounds_(std::move(bounds)) {
  if (bounds_.size() < 2)
    throw std::invalid_argument("SectorDecomposition: needs P + 1 >= 2 bounds, got " + std::to_string(bounds_.size()));
  for (std::size_t r = 1; r < bounds_.size(); ++r)
    if (!(bounds_[r] > bounds_[r - 1]) || !std::isfinite(bounds_[r]))
      throw std::invalid_argument("SectorDecomposition: bounds must be finite and strictly ascending");
  if (std::abs(bounds_.back() - bounds_.front() - kTurn) > 1e-12)
    throw std::invalid_argument("SectorDecomposition: the bounds must span one turn (last = first + 2 pi)");
  for (double b : bounds_) cos_.push_back(std::cos(b)), sin_.push_back(std::sin(b));
}

int SectorDecomposition::owner(double x, double y) const {
  if (ranks() == 1 || (x == 0 && y == 0)) return 0;
  const double a = azimuth_from(x, y, bounds_.front());
  const auto it = std::upper_bound(bounds_.begin(), bounds_.end(), a);
  return std::clamp(static_cast<int>(it - bounds_.begin()) - 1, 0, ranks() - 1);
}

double SectorDecomposition::distance(int rank, double x, double y) const {
  if (rank < 0 || rank >= ranks()) throw std::out_of_range("SectorDecomposition::distance: no rank " + std::to_string(rank));
  return ranks() == 1 || owner(x, y) == rank ? 0.0 : boundary_distance(rank, x, y);
}

double SectorDecomposition::boundary_distance(int rank, double x, double y) const {
  return std::min(to_half_plane(x, y, cos_[rank], sin_[rank]), to_half_plane(x, y, cos_[rank + 1], sin_[rank + 1]));
}

SectorDecomposition balanced_sectors(const double* x, const double* y, std::size_t n, int ranks) {
  if (ranks < 1) throw std::invalid_argument("balanced_sectors: ranks must be >= 1, got " + std::to_string(ranks));
  std::vector<double> b(static_cast<std::size_t>(ranks) + 1);
  if (n == 0 || ranks == 1) {
    for (int r = 0; r <= ranks; ++r) b[r] = kTurn * r / ranks;
    return SectorDecomposition(b);
  }
  std::vector<double> a(n);
  for (std::size_t i = 0; i < n; ++i) a[i] = azimuth_from(x[i], y[i], 0.0);
  std::sort(a.begin(), a.end());
  // Start after the widest gap (the wrap-around gap included): the first rank begins at its far side.
  std::size_t first = 0;
  double widest = a[0] + kTurn - a[n - 1];
  for (std::size_t i = 1; i < n; ++i)
    if (a[i] - a[i - 1] > widest) widest = a[i] - a[i - 1], first = i;
  auto at = [&](std::size_t k) { return a[(first + k) % n] + (first + k >= n ? kTurn : 0.0); };  // k-th from start
  b[0] = at(0) - 0.5 * widest;
  for (int r = 1; r < ranks; ++r) {
    const std::size_t k = n * static_cast<std::size_t>(r) / static_cast<std::size_t>(ranks);
    b[r] = k == 0 ? at(0) : 0.5 * (at(k - 1) + at(k));
    if (!(b[r] > b[r - 1])) b[r] = std::nextafter(b[r - 1], INFINITY);  // fewer particles than ranks, or ties
  }
  b[ranks] = b[0] + kTurn;
  for (int r = ranks - 1; r > 0 && !(b[r] < b[r + 1]); --r) b[r] = std::nextafter(b[r + 1], -INFINITY);
  return SectorDecomposition(b);
}

RankLayout rank_layout(const SectorDecomposition& d, const double* x, const double* y, std::size_t n, double reach) {
  if (!(reach >= 0)) throw std::invalid_argument("rank_layout: reach must be >= 0 m");
  const int P = d.ranks();
  RankLayout L;
  L.owner.resize(n);
  L.owned.assign(P, {});
  L.ghosts.assign(P, {});
  for (std::size_t i = 0; i < n; ++i) {
    const int o = d.owner(x[i], y[i]);
    L.owner[i] = o;
    L.owned[o].push_back(static_cast<uint32_t>(i));
    for (int r = 0; r < P; ++r)
      if (r != o && d.boundary_distance(r, x[i], y[i]) < reach) L.ghosts[r].push_back(static_cast<uint32_t>(i));
  }
  return L;
}

}  // namespace dem
