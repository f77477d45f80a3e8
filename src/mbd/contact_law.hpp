#pragma once
// Cone-to-cone contact laws of the paper, SI units (convert Table 1 with mechanism_params).
#include "mbd/mechanism_params.hpp"

namespace mbd {

// Eq. 11: |f_n| = k d^h1 + c sign(d_dot) |d_dot|^h2 d^h3 for indentation d > 0 (0 otherwise).
// The paper's "d/|d_dot|" factor is read as sign(d_dot) (the indentation rate's sign); d_dot > 0 when
// the cones approach. The result is clipped at 0: the cones do not pull on each other.
double normal_force_eq11(const ContactParams& c, double indentation_m, double indentation_rate_m_s);

// Eq. 15: haversine step from (x0, h0) to (x1, h1).
double havsin(double x, double x0, double h0, double x1, double h1);

// Eq. 14: friction coefficient with sign, for relative tangential velocity v (m/s) of body 2 w.r.t.
// body 1: +mu_d for v <= -v_d, -mu_d for v >= v_d, smooth through +-mu_s at +-v_s and 0 at v = 0.
// The friction force on body 2 along the tangent t is f_t = mu(v) |f_n| (Eq. 13).
double friction_coefficient_eq14(double v, double mu_s, double mu_d, double v_s, double v_d);

}  // namespace mbd
