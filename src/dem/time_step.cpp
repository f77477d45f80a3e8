#include "dem/time_step.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace dem {

double rayleigh_time_step(double radius, const Material& m) { return rayleigh_time_step(radius, m.density, m); }

double rayleigh_time_step(double radius, double rho, const Material& m) {
  return M_PI * radius * std::sqrt(rho / m.G) / (0.1631 * m.nu + 0.8766);
}

double rayleigh_time_step(const Particles& p, const MaterialTable& mats) {
  double dt = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Material& m = mats.material(p.material[i]);
    // the particle's own density (from its mass) may differ from the material's; use the particle's
    const double rho = p.m[i] / (4.0 / 3.0 * M_PI * p.r[i] * p.r[i] * p.r[i]);
    dt = std::min(dt, rayleigh_time_step(p.r[i], rho, m));
  }
  return dt;
}

double bond_time_step(const Particles& p, const std::vector<Bond>& bonds) {
  const std::size_t n = p.size();
  std::vector<double> kt(n, 0.0), kr(n, 0.0);
  for (const Bond& b : bonds) {
    if (!b.alive) continue;
    const double d = std::sqrt(std::pow(p.x[b.j] - p.x[b.i], 2) + std::pow(p.y[b.j] - p.y[b.i], 2) +
                               std::pow(p.z[b.j] - p.z[b.i], 2));
    const double ci = d * p.r[b.i] / (p.r[b.i] + p.r[b.j]), cj = d - ci;
    const double ktr = std::max(b.kn, b.kt) * b.A;
    kt[b.i] += ktr;
    kt[b.j] += ktr;
    const double krot = b.kn * 0.5 * b.J + b.kt * b.J;
    kr[b.i] += krot + b.kt * b.A * ci * ci;
    kr[b.j] += krot + b.kt * b.A * cj * cj;
  }
  double dt = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    if (kt[i] > 0) dt = std::min(dt, std::sqrt(p.m[i] / kt[i]));
    if (kr[i] > 0) dt = std::min(dt, std::sqrt(1.0 / (p.inv_I[i] * kr[i])));
  }
  return dt;
}

TimeStepCheck check_time_step(double dt, const Particles& p, const MaterialTable& mats,
                              const std::vector<Bond>& bonds, double max_rayleigh_fraction) {
  TimeStepCheck c;
  c.dt = dt;
  c.rayleigh = rayleigh_time_step(p, mats);
  c.bond = bond_time_step(p, bonds);
  c.rayleigh_fraction = max_rayleigh_fraction;
  std::ostringstream os;
  os << "DEM time step " << dt << " s: Hertz (Rayleigh) critical step " << c.rayleigh << " s (accepted up to "
     << max_rayleigh_fraction << " of it = " << max_rayleigh_fraction * c.rayleigh << " s), bond critical step "
     << c.bond << " s";
  c.ok = dt > 0 && dt <= max_rayleigh_fraction * c.rayleigh && dt <= c.bond;
  if (!c.ok) os << ": unstable, choose dt <= " << std::min(max_rayleigh_fraction * c.rayleigh, c.bond) << " s";
  c.message = os.str();
  return c;
}

}  // namespace dem
