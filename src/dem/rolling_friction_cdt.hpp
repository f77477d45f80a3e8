#pragma once
// Rolling friction, constant directional torque (CDT) model as in LIGGGHTS' rolling_friction cdt:
//   T_r = -mu_r r* |F_n| w_rel / |w_rel|   (torque on body i; body j gets -T_r)
#include <cmath>

namespace dem {

inline void rolling_torque_cdt(double mu_r, double r_eff, double fn_abs, const double wrel[3], double out[3]) {
  const double w2 = wrel[0] * wrel[0] + wrel[1] * wrel[1] + wrel[2] * wrel[2];
  if (mu_r <= 0.0 || w2 <= 0.0) {
    out[0] = out[1] = out[2] = 0.0;
    return;
  }
  const double s = -mu_r * r_eff * fn_abs / std::sqrt(w2);
  out[0] = s * wrel[0];
  out[1] = s * wrel[1];
  out[2] = s * wrel[2];
}

}  // namespace dem
