#include "chamber/force_map.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace chamber {

namespace {
double overlap(double a0, double a1, double b0, double b1) { return std::max(0.0, std::min(a1, b1) - std::max(a0, b0)); }
}  // namespace

ConcaveForceMap::ConcaveForceMap(const FlowModel& f, const core::Profile& concave, int rings, int sectors)
    : rings_(rings), sectors_(sectors), concave_(concave) {
  if (rings < 1 || sectors < 1 || concave.z.size() < 2)
    throw std::invalid_argument("ConcaveForceMap: needs rings >= 1, sectors >= 1 and a concave profile");
  constexpr double kTwoPi = 6.28318530717958647692;
  const auto [zmin, zmax] = std::minmax_element(concave.z.begin(), concave.z.end());
  const double ring_h = (*zmax - *zmin) / rings, dz = f.band_height();
  const double cell_a = kTwoPi / f.sectors(), area_a = kTwoPi / sectors;
  share_.resize(f.cells());
  for (std::size_t k = 0; k < f.cells(); ++k) {
    const int b = static_cast<int>(k) / f.sectors(), s = static_cast<int>(k) % f.sectors();
    const double z0 = f.band_bottom(b), a0 = s * cell_a;
    for (int r = 0; r < rings; ++r) {
      const double wz = overlap(z0, z0 + dz, *zmax - (r + 1) * ring_h, *zmax - r * ring_h) / dz;
      if (wz <= 0) continue;
      for (int q = 0; q < sectors; ++q) {
        const double wa = overlap(a0, a0 + cell_a, q * area_a, (q + 1) * area_a) / cell_a;
        if (wa > 0) share_[k].emplace_back(r * sectors + q, wz * wa);
      }
    }
  }
}

std::vector<double> ConcaveForceMap::map(const std::vector<double>& per_cell) const {
  if (per_cell.size() != share_.size()) throw std::invalid_argument("ConcaveForceMap::map: one value per flow cell");
  std::vector<double> out(static_cast<std::size_t>(rings_ * sectors_), 0.0);
  for (std::size_t k = 0; k < share_.size(); ++k)
    for (const auto& [area, w] : share_[k]) out[area] += w * per_cell[k];
  return out;
}

Eigen::Vector3d ConcaveForceMap::area_centre(int a) const {
  if (a < 0 || a >= rings_ * sectors_) throw std::invalid_argument("ConcaveForceMap::area_centre: no such area");
  const auto [zmin, zmax] = std::minmax_element(concave_.z.begin(), concave_.z.end());
  const double z = *zmax - (a / sectors_ + 0.5) * (*zmax - *zmin) / rings_;
  const double phi = (a % sectors_ + 0.5) * 6.28318530717958647692 / sectors_, r = concave_.radius_at(z);
  return {r * std::cos(phi), r * std::sin(phi), z};
}

}  // namespace chamber
