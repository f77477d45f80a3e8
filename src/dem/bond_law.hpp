#pragma once
// Incremental bond law, paper Eq. 22-25 (Potyondy-Cundall parallel bond as in EDEM's BPM).
//   dF_n = -k_bn A dU_n, dF_t = -k_bt A dU_t, dT_n = -k_bt J dTheta_n, dT_t = -k_bn (J/2) dTheta_t
// Deviation, documented: Eq. 22 as printed pairs k_bn with twist and k_bt with bending; the physically
// consistent parallel bond (Potyondy & Cundall 2004, EDEM manual) uses shear stiffness for twist (polar J)
// and normal stiffness for bending (I = J/2). We use the latter so bending matches beam theory (EI/L).
// Breakage (Eq. 24-25): sigma = -F_n/A + 2|T_t| R_b / J (tension positive), tau = |F_t|/A + |T_n| R_b / J.
#include <cmath>

#include "dem/bonds.hpp"

namespace dem {

struct BondOut {
  double f[3];   // force on j (on i: -f)
  double ti[3];  // torque on i
  double tj[3];  // torque on j
  double sigma, tau;
};

// xi, xj: centres; vi, vj, wi, wj: (half-step) velocities; ri, rj radii; inverse masses and inverse moments
// of inertia (used by the optional damping only). Updates the spring state of b by one step dt and writes the
// force/torques. Returns 0 if intact, 1 if broken in tension, 2 if broken in shear (then out is zero and the
// spring state is left as it was).
inline int bond_update(Bond& b, const double xi[3], const double xj[3], const double vi[3], const double vj[3],
                       const double wi[3], const double wj[3], double ri, double rj, double inv_mi, double inv_mj,
                       double inv_Ii, double inv_Ij, double dt, BondOut& out) {
  double n[3] = {xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]};
  const double d = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  const double inv_d = 1.0 / d;
  n[0] *= inv_d; n[1] *= inv_d; n[2] *= inv_d;
  // contact point splits the centre distance in the ratio of the radii
  const double ci = d * ri / (ri + rj), cj = d - ci;
  // velocity of j's material point at the bond centre relative to i's: v_j + w_j x (-cj n) - v_i - w_i x (ci n)
  const double vr[3] = {vj[0] - cj * (wj[1] * n[2] - wj[2] * n[1]) - vi[0] - ci * (wi[1] * n[2] - wi[2] * n[1]),
                        vj[1] - cj * (wj[2] * n[0] - wj[0] * n[2]) - vi[1] - ci * (wi[2] * n[0] - wi[0] * n[2]),
                        vj[2] - cj * (wj[0] * n[1] - wj[1] * n[0]) - vi[2] - ci * (wi[0] * n[1] - wi[1] * n[0])};
  const double vn = vr[0] * n[0] + vr[1] * n[1] + vr[2] * n[2];
  const double vt[3] = {vr[0] - vn * n[0], vr[1] - vn * n[1], vr[2] - vn * n[2]};
  const double wr[3] = {wj[0] - wi[0], wj[1] - wi[1], wj[2] - wi[2]};
  const double wn = wr[0] * n[0] + wr[1] * n[1] + wr[2] * n[2];
  const double wt[3] = {wr[0] - wn * n[0], wr[1] - wn * n[1], wr[2] - wn * n[2]};

  // keep the shear force and bending torque in the current tangent plane (projection; the length change is
  // second order in the rotation per step)
  auto to_plane = [&n](double* v) {
    const double vn_ = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
    v[0] -= vn_ * n[0]; v[1] -= vn_ * n[1]; v[2] -= vn_ * n[2];
  };
  double ft[3] = {b.ft[0], b.ft[1], b.ft[2]};
  double tt[3] = {b.tt[0], b.tt[1], b.tt[2]};
  to_plane(ft);
  to_plane(tt);
  // Eq. 22-23 increments
  const double knA = b.kn * b.A, ktA = b.kt * b.A, ktJ = b.kt * b.J, knI = b.kn * 0.5 * b.J;
  const double fn = b.fn - knA * vn * dt;
  const double tn = b.tn - ktJ * wn * dt;
  for (int k = 0; k < 3; ++k) {
    ft[k] -= ktA * vt[k] * dt;
    tt[k] -= knI * wt[k] * dt;
  }
  // Eq. 24
  const double ft_mag = std::sqrt(ft[0] * ft[0] + ft[1] * ft[1] + ft[2] * ft[2]);
  const double tt_mag = std::sqrt(tt[0] * tt[0] + tt[1] * tt[1] + tt[2] * tt[2]);
  // sigma = -F_n/A + 2 |T_t| R/J, tau = |F_t|/A + |T_n| R/J over the common denominator A J (one division)
  const double iAJ = 1.0 / (b.A * b.J), rA = b.rb * b.A;
  const double sigma = (-fn * b.J + 2.0 * tt_mag * rA) * iAJ;
  const double tau = (ft_mag * b.J + std::fabs(tn) * rA) * iAJ;
  out.sigma = sigma;
  out.tau = tau;
  // Eq. 25
  if (sigma >= b.sigma_c || tau >= b.tau_c) {
    for (int k = 0; k < 3; ++k) out.f[k] = out.ti[k] = out.tj[k] = 0.0;
    return sigma >= b.sigma_c ? 1 : 2;
  }
  b.fn = fn;
  b.tn = tn;
  for (int k = 0; k < 3; ++k) { b.ft[k] = ft[k]; b.tt[k] = tt[k]; }

  double f[3], tj[3];
  for (int k = 0; k < 3; ++k) {
    f[k] = fn * n[k] + ft[k];
    tj[k] = tn * n[k] + tt[k];
  }
  if (b.damping > 0.0) {  // optional viscous damping (BondParams::damping)
    const double M = 1.0 / (inv_mi + inv_mj), I = 1.0 / (inv_Ii + inv_Ij);
    const double z2 = 2.0 * b.damping;
    const double cn = z2 * std::sqrt(M * knA), ct = z2 * std::sqrt(M * ktA);
    const double crn = z2 * std::sqrt(I * ktJ), crt = z2 * std::sqrt(I * knI);
    for (int k = 0; k < 3; ++k) {
      f[k] -= cn * vn * n[k] + ct * vt[k];
      tj[k] -= crn * wn * n[k] + crt * wt[k];
    }
  }
  // torque of the force about each centre: force on j acts at -cj n from j, -f at +ci n from i
  const double cfx = n[1] * f[2] - n[2] * f[1], cfy = n[2] * f[0] - n[0] * f[2], cfz = n[0] * f[1] - n[1] * f[0];
  out.f[0] = f[0]; out.f[1] = f[1]; out.f[2] = f[2];
  out.tj[0] = tj[0] - cj * cfx; out.tj[1] = tj[1] - cj * cfy; out.tj[2] = tj[2] - cj * cfz;
  out.ti[0] = -tj[0] - ci * cfx; out.ti[1] = -tj[1] - ci * cfy; out.ti[2] = -tj[2] - ci * cfz;
  return 0;
}

}  // namespace dem
