#include "chamber/liner_wear.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace chamber {

double wear_depth(const WornLiners& w, double z_lo, double z_hi, double z) {
  const double top = z_lo + w.worn_height_fraction * (z_hi - z_lo);
  if (z >= top) return 0.0;
  if (z <= z_lo) return w.setting_increase_m;
  return w.setting_increase_m * (top - z) / (top - z_lo);
}

core::Profile worn_concave(const core::Profile& c, double z_lo, double z_hi, const WornLiners& w) {
  if (c.size() < 2) throw std::invalid_argument("worn_concave: the concave needs at least 2 points");
  const double top = z_lo + w.worn_height_fraction * (z_hi - z_lo);
  const bool up = c.z.back() > c.z.front();
  const double zmin = std::min(c.z.front(), c.z.back()), zmax = std::max(c.z.front(), c.z.back());
  // 1 / |t_z| of segment i (from vertex i to i + 1).
  auto secant = [&](std::size_t i) {
    const double dz = c.z[i + 1] - c.z[i], dr = c.r[i + 1] - c.r[i];
    return std::hypot(dz, dr) / std::abs(dz);
  };
  core::Profile out;
  auto push = [&](double z, double r, double sec) {
    out.z.push_back(z);
    out.r.push_back(r + wear_depth(w, z_lo, z_hi, z) * sec);
  };
  const std::size_t n = c.size();
  for (std::size_t i = 0; i < n; ++i) {
    // A vertex between two segments takes the mean of their secants (exact on each segment only away from it).
    const double sec = i == 0 ? secant(0) : i + 1 == n ? secant(n - 2) : 0.5 * (secant(i - 1) + secant(i));
    push(c.z[i], c.r[i], sec);
    if (i + 1 == n) break;
    // Breakpoints of the wear inside segment i, in the profile's order.
    double brk[2] = {z_lo, top};
    if (!up) std::swap(brk[0], brk[1]);
    for (double zb : brk) {
      const double a = c.z[i], b = c.z[i + 1];
      const bool inside = up ? (zb > a + 1e-12 && zb < b - 1e-12) : (zb < a - 1e-12 && zb > b + 1e-12);
      if (inside && zb > zmin && zb < zmax) push(zb, c.r[i] + (c.r[i + 1] - c.r[i]) * (zb - a) / (b - a), secant(i));
    }
  }
  return out;
}

}  // namespace chamber
