// World::contact_stress: each particle's mean stress x volume from its contacts and bonds (world.hpp).
#include <cmath>
#include <vector>

#include "dem/hertz_mindlin.hpp"
#include "dem/world.hpp"

namespace dem {

void add_contact_stress(double* s, const double a[3], const double f[3]) {
  s[0] += a[0] * f[0];
  s[1] += a[1] * f[1];
  s[2] += a[2] * f[2];
  s[3] += 0.5 * (a[0] * f[1] + a[1] * f[0]);
  s[4] += 0.5 * (a[1] * f[2] + a[2] * f[1]);
  s[5] += 0.5 * (a[2] * f[0] + a[0] * f[2]);
}

void World::contact_stress(std::vector<double>& s) const {
  const std::size_t n = p_.size();
  s.assign(6 * n, 0.0);
  const bool list_valid = istart_.size() == n + 1 && touch_.size() >= npairs_;
  const long np = list_valid ? static_cast<long>(npairs_) : 0;
  // Each touching pair's force and normal (the Hertz force is the cost: in parallel), then the sums in pair order
  // (serial: the same sums, bit for bit, whatever the thread count).
  std::vector<double>& fn = stress_pair_force_;
  std::vector<char>& on = stress_pair_touch_;
  if (fn.size() < 6 * static_cast<std::size_t>(np)) fn.resize(6 * static_cast<std::size_t>(np));
  if (on.size() < static_cast<std::size_t>(np)) on.resize(static_cast<std::size_t>(np));
#pragma omp parallel for num_threads(nt_) schedule(static) if (nt_ > 1 && np >= 1024)
  for (long q = 0; q < np; ++q) {
    on[q] = 0;
    if (!touch_[q]) continue;
    const uint32_t i = pi_[q], j = pj_[q];
    const double dx = p_.x[i] - p_.x[j], dy = p_.y[i] - p_.y[j], dz = p_.z[i] - p_.z[j];
    const double d = std::sqrt(dx * dx + dy * dy + dz * dz), delta = p_.r[i] + p_.r[j] - d;
    if (!(delta > 0) || !(d > 0)) continue;
    const double nrm[3] = {dx / d, dy / d, dz / d}, zero[3] = {0, 0, 0};  // from j towards i
    double hist[3] = {hist_[q][0], hist_[q][1], hist_[q][2]};
    ContactForce cf;
    const double r_eff = p_.r[i] * p_.r[j] / (p_.r[i] + p_.r[j]), m_eff = p_.m[i] * p_.m[j] / (p_.m[i] + p_.m[j]);
    hertz_mindlin(delta, nrm, zero, zero, r_eff, m_eff, prm_.materials.pair(p_.material[i], p_.material[j]), 0.0,
                  hist, cf);
    double* o = &fn[6 * q];
    for (int k = 0; k < 3; ++k) o[k] = cf.f[k], o[3 + k] = nrm[k];
    on[q] = 1;
  }
  for (long q = 0; q < np; ++q) {
    if (!on[q]) continue;
    const uint32_t i = pi_[q], j = pj_[q];
    const double* f = &fn[6 * q];
    const double* nrm = f + 3;
    const double ai = p_.r[i], aj = p_.r[j];  // arms at the radius (world.hpp)
    const double to_ci[3] = {-ai * nrm[0], -ai * nrm[1], -ai * nrm[2]};
    const double to_cj[3] = {aj * nrm[0], aj * nrm[1], aj * nrm[2]};
    const double fj[3] = {-f[0], -f[1], -f[2]};
    add_contact_stress(&s[6 * i], to_ci, f);
    add_contact_stress(&s[6 * j], to_cj, fj);
  }
  sync_bonds();
  for (const Bond& b : bonds_) {
    if (!b.alive) continue;
    const double dx = p_.x[b.j] - p_.x[b.i], dy = p_.y[b.j] - p_.y[b.i], dz = p_.z[b.j] - p_.z[b.i];
    const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (!(d > 0)) continue;
    const double nrm[3] = {dx / d, dy / d, dz / d};  // from i towards j (bond_law.hpp)
    const double ci = p_.r[b.i], cj = p_.r[b.j];  // arms at the radius, as for contacts
    const double fj[3] = {b.fn * nrm[0] + b.ft[0], b.fn * nrm[1] + b.ft[1], b.fn * nrm[2] + b.ft[2]};
    const double fi[3] = {-fj[0], -fj[1], -fj[2]};
    const double to_ci[3] = {ci * nrm[0], ci * nrm[1], ci * nrm[2]};
    const double to_cj[3] = {-cj * nrm[0], -cj * nrm[1], -cj * nrm[2]};
    add_contact_stress(&s[6 * b.i], to_ci, fi);
    add_contact_stress(&s[6 * b.j], to_cj, fj);
  }
}

}  // namespace dem
