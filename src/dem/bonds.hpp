#pragma once
// Bonded-particle model state (paper Eq. 20-25): parameters, one flat array of bonds, the break log.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace dem {

struct BondParams {
  double kn = 0;                 // normal stiffness per unit area k_bn (Pa/m)
  double kt = 0;                 // shear stiffness per unit area k_bt (Pa/m)
  double sigma_c = 0;            // tensile strength sigma_bc (Pa)
  double tau_c = 0;              // shear strength tau_bc (Pa)
  double radius_multiplier = 1;  // lambda_b of Eq. 20, used when radius <= 0
  double radius = 0;             // absolute bond radius R_b (m); > 0 overrides the multiplier
  // Optional viscous bond damping (not in the paper): ratio zeta of critical damping applied to the relative
  // normal/shear velocity and relative rotation rates of the pair, c = 2 zeta sqrt(M* k). 0 = undamped.
  // Damping forces are not part of the spring forces that Eq. 24 checks against the strengths.
  double damping = 0;

  void validate() const {
    if (!(kn > 0) || !(kt > 0))
      throw std::invalid_argument("bond stiffness k_bn, k_bt must be > 0 Pa/m (got " + std::to_string(kn) + ", " +
                                  std::to_string(kt) + ")");
    if (!(sigma_c > 0) || !(tau_c > 0))
      throw std::invalid_argument("bond strengths sigma_bc, tau_bc must be > 0 Pa (got " + std::to_string(sigma_c) +
                                  ", " + std::to_string(tau_c) + ")");
    if (!(radius > 0) && !(radius_multiplier > 0))
      throw std::invalid_argument("bond radius: give radius > 0 m or radius_multiplier > 0 (got " +
                                  std::to_string(radius) + ", " + std::to_string(radius_multiplier) + ")");
    if (!(damping >= 0) || damping > 1)
      throw std::invalid_argument("bond damping ratio must be in [0, 1], got " + std::to_string(damping));
  }
};

// One bond between particles i and j (storage indices). Spring state of Eq. 22 as forces/torques acting on j:
// fn: normal force on j along n = (x_j - x_i)/|x_j - x_i| (negative = tension); ft: shear force on j;
// tn: twisting torque on j along n; tt: bending torque on j. Body i gets the opposites.
struct Bond {
  uint32_t i = 0, j = 0;
  double rb = 0, A = 0, J = 0;      // Eq. 20, 23: R_b, A = pi R_b^2, J = pi R_b^4 / 2
  double kn = 0, kt = 0;            // per unit area
  double sigma_c = 0, tau_c = 0;
  double damping = 0;
  double fn = 0, ft[3] = {0, 0, 0};
  double tn = 0, tt[3] = {0, 0, 0};
  char alive = 1;
};

struct BondBreak {
  double t = 0;                     // time of the break (s)
  double x[3] = {0, 0, 0};          // position: the bond centre on the line of centres (m)
  uint64_t id_i = 0, id_j = 0;      // particle ids
  bool tensile = false;             // true: Eq. 25 tensile criterion; false: shear
  bool crushed = false;             // true: removed with a metaparticle crushed to fines (coupling), not by Eq. 25
  double sigma = 0, tau = 0;        // stresses at breakage (Pa)
};

}  // namespace dem
