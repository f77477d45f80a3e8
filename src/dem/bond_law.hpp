#pragma once
// Incremental bond law, paper Eq. 22-25 (Potyondy-Cundall parallel bond as in EDEM's BPM).
//   dF_n = -k_bn A dU_n, dF_t = -k_bt A dU_t, dT_n = -k_bt J dTheta_n, dT_t = -k_bn (J/2) dTheta_t
// Deviation, documented: Eq. 22 as printed pairs k_bn with twist and k_bt with bending; the physically
// consistent parallel bond (Potyondy & Cundall 2004, EDEM manual) uses shear stiffness for twist (polar J)
// and normal stiffness for bending (I = J/2). We use the latter so bending matches beam theory (EI/L).
// Breakage (Eq. 24-25): sigma = -F_n/A + 2|T_t| R_b / J (tension positive), tau = |F_t|/A + |T_n| R_b / J.
#include <cmath>

#include "dem/bonds.hpp"
#include "dem/hertz_mindlin.hpp"  // lanes

namespace dem {

struct BondOut {
  double f[3];   // force on j (on i: -f)
  double ti[3];  // torque on i
  double tj[3];  // torque on j
  double sigma, tau;
};

// Eq. 22-24 for T = double or Lanes4 (hertz_mindlin.hpp), branch-free. In: geometry and velocities, radii,
// inverse masses and inverse moments of inertia (damping only), per-area stiffnesses, A, J, R_b, damping ratio,
// spring state (fn, ft, tn, tt: on j). Out: the updated spring state in place, the stresses, force on j and
// torques on i and j. The caller decides breakage (Eq. 25) and keeps the old state for a broken bond.
// Forced inline: as a call its ~30 vector arguments go through the stack (bonds 1.45 -> 1.09 s, dem_bench bonded_hex).
template <class T>
__attribute__((always_inline)) inline void bond_law_lanes(
    const T xi[3], const T xj[3], const T vi[3], const T vj[3], const T wi[3], const T wj[3], const T& ri,
    const T& rj, const T& inv_mi, const T& inv_mj, const T& inv_Ii, const T& inv_Ij, const T& kn, const T& kt,
    const T& A, const T& J, const T& rb, const T& damping, bool with_damping, double dt, T& fn, T ft[3], T& tn,
    T tt[3], T& sigma, T& tau, T f[3], T ti[3], T tj[3]) {
  using lanes::abs;
  using lanes::sqrt;
  T n[3] = {xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]};
  const T d = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  const T inv_d = 1.0 / d;
  n[0] *= inv_d; n[1] *= inv_d; n[2] *= inv_d;
  // contact point splits the centre distance in the ratio of the radii
  const T ci = d * ri / (ri + rj), cj = d - ci;
  // velocity of j's material point at the bond centre relative to i's: v_j + w_j x (-cj n) - v_i - w_i x (ci n)
  const T vr[3] = {vj[0] - cj * (wj[1] * n[2] - wj[2] * n[1]) - vi[0] - ci * (wi[1] * n[2] - wi[2] * n[1]),
                   vj[1] - cj * (wj[2] * n[0] - wj[0] * n[2]) - vi[1] - ci * (wi[2] * n[0] - wi[0] * n[2]),
                   vj[2] - cj * (wj[0] * n[1] - wj[1] * n[0]) - vi[2] - ci * (wi[0] * n[1] - wi[1] * n[0])};
  const T vn = vr[0] * n[0] + vr[1] * n[1] + vr[2] * n[2];
  const T vt[3] = {vr[0] - vn * n[0], vr[1] - vn * n[1], vr[2] - vn * n[2]};
  const T wr[3] = {wj[0] - wi[0], wj[1] - wi[1], wj[2] - wi[2]};
  const T wn = wr[0] * n[0] + wr[1] * n[1] + wr[2] * n[2];
  const T wt[3] = {wr[0] - wn * n[0], wr[1] - wn * n[1], wr[2] - wn * n[2]};

  // keep the shear force and bending torque in the current tangent plane (projection; the length change is
  // second order in the rotation per step)
  const T ftn = ft[0] * n[0] + ft[1] * n[1] + ft[2] * n[2];
  const T ttn = tt[0] * n[0] + tt[1] * n[1] + tt[2] * n[2];
  for (int k = 0; k < 3; ++k) {
    ft[k] -= ftn * n[k];
    tt[k] -= ttn * n[k];
  }
  // Eq. 22-23 increments
  const T knA = kn * A, ktA = kt * A, ktJ = kt * J, knI = kn * 0.5 * J;
  fn = fn - knA * vn * dt;
  tn = tn - ktJ * wn * dt;
  for (int k = 0; k < 3; ++k) {
    ft[k] -= ktA * vt[k] * dt;
    tt[k] -= knI * wt[k] * dt;
  }
  // Eq. 24: sigma = -F_n/A + 2 |T_t| R/J, tau = |F_t|/A + |T_n| R/J over the common denominator A J
  const T ft_mag = sqrt(ft[0] * ft[0] + ft[1] * ft[1] + ft[2] * ft[2]);
  const T tt_mag = sqrt(tt[0] * tt[0] + tt[1] * tt[1] + tt[2] * tt[2]);
  const T iAJ = 1.0 / (A * J), rA = rb * A;
  sigma = (-fn * J + 2.0 * tt_mag * rA) * iAJ;
  tau = (ft_mag * J + abs(tn) * rA) * iAJ;

  T tb[3];
  for (int k = 0; k < 3; ++k) {
    f[k] = fn * n[k] + ft[k];
    tb[k] = tn * n[k] + tt[k];
  }
  if (with_damping) {  // optional viscous damping (BondParams::damping); zero ratio: no change
    const T M = 1.0 / (inv_mi + inv_mj), I = 1.0 / (inv_Ii + inv_Ij);
    const T z2 = 2.0 * damping;
    const T cn = z2 * sqrt(M * knA), ct = z2 * sqrt(M * ktA);
    const T crn = z2 * sqrt(I * ktJ), crt = z2 * sqrt(I * knI);
    for (int k = 0; k < 3; ++k) {
      f[k] -= cn * vn * n[k] + ct * vt[k];
      tb[k] -= crn * wn * n[k] + crt * wt[k];
    }
  }
  // torque of the force about each centre: force on j acts at -cj n from j, -f at +ci n from i
  const T cfx = n[1] * f[2] - n[2] * f[1], cfy = n[2] * f[0] - n[0] * f[2], cfz = n[0] * f[1] - n[1] * f[0];
  tj[0] = tb[0] - cj * cfx; tj[1] = tb[1] - cj * cfy; tj[2] = tb[2] - cj * cfz;
  ti[0] = -tb[0] - ci * cfx; ti[1] = -tb[1] - ci * cfy; ti[2] = -tb[2] - ci * cfz;
}

// Eq. 25 on the stresses of bond_law_lanes: 0 intact, 1 tensile, 2 shear.
inline int bond_break_code(double sigma_c, double tau_c, double sigma, double tau) {
  return sigma >= sigma_c ? 1 : (tau >= tau_c ? 2 : 0);
}
inline int bond_break_code(const Bond& b, double sigma, double tau) {
  return bond_break_code(b.sigma_c, b.tau_c, sigma, tau);
}

// One bond, scalar. xi, xj: centres; vi, vj, wi, wj: (half-step) velocities; ri, rj radii; inverse masses and
// inverse moments of inertia (used by the optional damping only). Updates the spring state of b by one step
// dt and writes the force/torques. Returns 0 if intact, 1 if broken in tension, 2 if broken in shear (then
// out's force and torques are zero and the spring state is left as it was).
inline int bond_update(Bond& b, const double xi[3], const double xj[3], const double vi[3], const double vj[3],
                       const double wi[3], const double wj[3], double ri, double rj, double inv_mi, double inv_mj,
                       double inv_Ii, double inv_Ij, double dt, BondOut& out) {
  double fn = b.fn, tn = b.tn, ft[3] = {b.ft[0], b.ft[1], b.ft[2]}, tt[3] = {b.tt[0], b.tt[1], b.tt[2]};
  bond_law_lanes<double>(xi, xj, vi, vj, wi, wj, ri, rj, inv_mi, inv_mj, inv_Ii, inv_Ij, b.kn, b.kt, b.A, b.J,
                         b.rb, b.damping, b.damping > 0.0, dt, fn, ft, tn, tt, out.sigma, out.tau, out.f, out.ti,
                         out.tj);
  const int code = bond_break_code(b, out.sigma, out.tau);
  if (code) {
    for (int k = 0; k < 3; ++k) out.f[k] = out.ti[k] = out.tj[k] = 0.0;
    return code;
  }
  b.fn = fn;
  b.tn = tn;
  for (int k = 0; k < 3; ++k) { b.ft[k] = ft[k]; b.tt[k] = tt[k]; }
  return 0;
}

}  // namespace dem
