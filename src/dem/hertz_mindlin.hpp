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

// Lane helpers: the law below is written once for T = double and for a vector of 4 doubles (GCC vector
// extension), which World::pair_forces uses to evaluate 4 contacts at a time.
typedef double Lanes4 __attribute__((vector_size(32)));
namespace lanes {
inline double sqrt(double x) { return std::sqrt(x); }
inline double abs(double x) { return std::fabs(x); }
inline double select(bool c, double a, double b) { return c ? a : b; }
inline Lanes4 sqrt(Lanes4 x) {
#if defined(__AVX__)
  return __builtin_ia32_sqrtpd256(x);
#else
  return Lanes4{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
#endif
}
inline Lanes4 abs(Lanes4 x) { return x < 0.0 ? -x : x; }
template <class M>
inline Lanes4 select(M c, Lanes4 a, Lanes4 b) { return c ? a : b; }
inline bool any(bool c) { return c; }
template <class M>
inline bool any(const M& c) { return (c[0] | c[1] | c[2] | c[3]) != 0; }
}  // namespace lanes

// Eq. 16-19 + CDT rolling friction, the same arithmetic in every lane (one branch: any lane sliding). Pair properties as
// arguments; sqrt_kt_kn = sqrt(4 G*/E*). Outputs: fn (signed normal force), f (total), ft, troll.
template <class T>
inline void hertz_mindlin_lanes(const T& delta, const T n[3], const T vrel[3], const T wrel[3], const T& r_eff,
                                const T& m_eff, const T& E_star, const T& G_star, const T& beta,
                                const T& sqrt_kt_kn, const T& friction, const T& mu_r, double dt, T hist[3],
                                T& fn_out, T f[3], T ft[3], T troll[3]) {
  using lanes::abs;
  using lanes::select;
  using lanes::sqrt;
  constexpr double k56 = 1.8257418583505538;  // 2 sqrt(5/6)
  const T zero = T{} * 0.0, one = zero + 1.0;
  const T sqrt_rd = sqrt(r_eff * delta);
  // Eq. 16: k_n = 2 E* sqrt(r* d), F_ns = 4/3 E* sqrt(r*) d^1.5 = 2/3 k_n d, F_nd = -2 sqrt(5/6) xi sqrt(M* k_n) v_n
  const T kn = 2.0 * E_star * sqrt_rd;
  const T vn = vrel[0] * n[0] + vrel[1] * n[1] + vrel[2] * n[2];  // < 0 when approaching
  const T cn = k56 * beta * sqrt(m_eff * kn);
  const T fn = (2.0 / 3.0) * kn * delta - cn * vn;
  // tangential relative velocity
  const T vt0 = vrel[0] - vn * n[0], vt1 = vrel[1] - vn * n[1], vt2 = vrel[2] - vn * n[2];
  // project the spring onto the current tangent plane (as LAMMPS/LIGGGHTS; the length change is second order
  // in the rotation per step)
  const T hn = hist[0] * n[0] + hist[1] * n[1] + hist[2] * n[2];
  T h0 = hist[0] - hn * n[0], h1 = hist[1] - hn * n[1], h2 = hist[2] - hn * n[2];
  h0 += vt0 * dt; h1 += vt1 * dt; h2 += vt2 * dt;
  // Eq. 18: k_t = 8 G* sqrt(r* d), F_t = -k_t d_t - 2 sqrt(5/6) xi sqrt(M* k_t) v_t
  // k_t / k_n = 4 G*/E*, so sqrt(M* k_t) = sqrt(M* k_n) sqrt(4 G*/E*)
  const T kt = 8.0 * G_star * sqrt_rd;
  const T ct = cn * sqrt_kt_kn;
  T ft0 = -kt * h0 - ct * vt0, ft1 = -kt * h1 - ct * vt1, ft2 = -kt * h2 - ct * vt2;
  // Eq. 19: Coulomb cap; the spring is reset to the length that gives the capped force
  const T ft_mag2 = ft0 * ft0 + ft1 * ft1 + ft2 * ft2;
  const T fmax = friction * abs(fn);
  const auto capped = ft_mag2 > fmax * fmax;
  if (lanes::any(capped)) {  // sliding in some lane
    const T s = select(capped, fmax / sqrt(ft_mag2), one);
    ft0 *= s; ft1 *= s; ft2 *= s;
    const auto reset = capped & (kt > 0.0);
    const T ik = one / kt;
    h0 = select(reset, -(ft0 + ct * vt0) * ik, h0);
    h1 = select(reset, -(ft1 + ct * vt1) * ik, h1);
    h2 = select(reset, -(ft2 + ct * vt2) * ik, h2);
  }
  hist[0] = h0; hist[1] = h1; hist[2] = h2;
  fn_out = fn;
  ft[0] = ft0; ft[1] = ft1; ft[2] = ft2;
  f[0] = fn * n[0] + ft0; f[1] = fn * n[1] + ft1; f[2] = fn * n[2] + ft2;
  // CDT rolling friction (rolling_friction_cdt.hpp): T_r = -mu_r r* |F_n| w_rel / |w_rel|
  const T w2 = wrel[0] * wrel[0] + wrel[1] * wrel[1] + wrel[2] * wrel[2];
  const T sr = select((w2 > 0.0) & (mu_r > 0.0), -mu_r * r_eff * abs(fn) / sqrt(w2), zero);
  troll[0] = sr * wrel[0]; troll[1] = sr * wrel[1]; troll[2] = sr * wrel[2];
}

inline void hertz_mindlin(double delta, const double n[3], const double vrel[3], const double wrel[3],
                          double r_eff, double m_eff, const PairProps& p, double dt, double hist[3],
                          ContactForce& out) {
  const double skk = p.sqrt_kt_kn > 0 ? p.sqrt_kt_kn : std::sqrt(4.0 * p.G_star / p.E_star);
  hertz_mindlin_lanes<double>(delta, n, vrel, wrel, r_eff, m_eff, p.E_star, p.G_star, p.beta, skk, p.friction,
                              p.rolling_friction, dt, hist, out.fn_mag, out.f, out.ft, out.troll);
}

}  // namespace dem
