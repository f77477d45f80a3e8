#pragma once
// Hertz-Mindlin no-slip contact with damping, paper Eq. 16-19, plus CDT rolling friction.
// One function for particle-particle and particle-wall/triangle contacts (a wall has infinite mass and
// radius: pass r_eff = r_i, m_eff = m_i).
//
// Conventions (body i is the particle, body j the other particle or the wall):
//   delta  overlap > 0 (m)
//   n      unit normal pointing from j towards i (a positive normal force pushes i along +n)
//   vrel   velocity of i's surface minus j's surface at the contact point,
//          e.g. v_i + w_i x (-a_i n) - v_j - w_j x (a_j n), a_i, a_j = centre-to-contact distances
//   wrel   w_i - w_j (for a wall: w_i)
//   hist   tangential spring displacement (m), in/out; zero it for a new contact; kept in the tangent plane
// Output (on body i; body j gets the opposite force and rolling torque; the caller adds the lever-arm
// torques a x F itself):
//   f      total contact force on i = fn_mag * n + ft
//   ft     tangential part, |ft| <= mu |fn_mag| (Eq. 19)
//   troll  rolling-friction torque on i
#include <cmath>

#include "dem/materials.hpp"
#include "dem/rolling_friction_cdt.hpp"

namespace dem {

struct ContactForce {
  double fn_mag;    // signed normal force along n (Eq. 16: elastic + damping; may be slightly negative near separation)
  double f[3];      // total force on i
  double ft[3];     // tangential force on i
  double troll[3];  // rolling torque on i
};

inline void hertz_mindlin(double delta, const double n[3], const double vrel[3], const double wrel[3],
                          double r_eff, double m_eff, const PairProps& p, double dt, double hist[3],
                          ContactForce& out) {
  constexpr double k56 = 1.8257418583505538;  // 2 sqrt(5/6)
  const double sqrt_rd = std::sqrt(r_eff * delta);
  // Eq. 16: k_n = 2 E* sqrt(r* d), F_ns = 4/3 E* sqrt(r*) d^1.5 = 2/3 k_n d, F_nd = -2 sqrt(5/6) xi sqrt(M* k_n) v_n
  const double kn = 2.0 * p.E_star * sqrt_rd;
  const double vn = vrel[0] * n[0] + vrel[1] * n[1] + vrel[2] * n[2];  // < 0 when approaching
  const double cn = k56 * p.beta * std::sqrt(m_eff * kn);
  const double fn = (2.0 / 3.0) * kn * delta - cn * vn;
  // tangential relative velocity
  const double vt0 = vrel[0] - vn * n[0], vt1 = vrel[1] - vn * n[1], vt2 = vrel[2] - vn * n[2];
  // project the spring onto the current tangent plane (as LAMMPS/LIGGGHTS; the length change is second order
  // in the rotation per step)
  const double hn = hist[0] * n[0] + hist[1] * n[1] + hist[2] * n[2];
  double h0 = hist[0] - hn * n[0], h1 = hist[1] - hn * n[1], h2 = hist[2] - hn * n[2];
  h0 += vt0 * dt; h1 += vt1 * dt; h2 += vt2 * dt;
  // Eq. 18: k_t = 8 G* sqrt(r* d), F_t = -k_t d_t - 2 sqrt(5/6) xi sqrt(M* k_t) v_t
  // k_t / k_n = 4 G*/E*, so sqrt(M* k_t) = sqrt(M* k_n) sqrt(4 G*/E*)
  const double kt = 8.0 * p.G_star * sqrt_rd;
  const double ct = cn * (p.sqrt_kt_kn > 0 ? p.sqrt_kt_kn : std::sqrt(4.0 * p.G_star / p.E_star));
  double ft0 = -kt * h0 - ct * vt0, ft1 = -kt * h1 - ct * vt1, ft2 = -kt * h2 - ct * vt2;
  // Eq. 19: Coulomb cap; the spring is reset to the length that gives the capped force
  const double ft_mag2 = ft0 * ft0 + ft1 * ft1 + ft2 * ft2;
  const double fmax = p.friction * std::fabs(fn);
  if (ft_mag2 > fmax * fmax) {
    const double s = fmax / std::sqrt(ft_mag2);
    ft0 *= s; ft1 *= s; ft2 *= s;
    if (kt > 0.0) {
      const double ik = 1.0 / kt;
      h0 = -(ft0 + ct * vt0) * ik; h1 = -(ft1 + ct * vt1) * ik; h2 = -(ft2 + ct * vt2) * ik;
    }
  }
  hist[0] = h0; hist[1] = h1; hist[2] = h2;
  out.fn_mag = fn;
  out.ft[0] = ft0; out.ft[1] = ft1; out.ft[2] = ft2;
  out.f[0] = fn * n[0] + ft0; out.f[1] = fn * n[1] + ft1; out.f[2] = fn * n[2] + ft2;
  rolling_torque_cdt(p.rolling_friction, r_eff, std::fabs(fn), wrel, out.troll);
}

}  // namespace dem
