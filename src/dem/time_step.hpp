#pragma once
// Critical time steps: Rayleigh wave step for Hertz contacts and a sqrt(m/k) step for bonds.
#include <string>

#include "dem/bonds.hpp"
#include "dem/materials.hpp"
#include "dem/particles.hpp"

namespace dem {

// Rayleigh step of one sphere: pi r sqrt(rho/G) / (0.1631 nu + 0.8766)
double rayleigh_time_step(double radius, const Material& m);
// The same for a sphere of its own density rho (a fragment heavier or lighter than its material).
double rayleigh_time_step(double radius, double rho, const Material& m);
// Minimum Rayleigh step over all particles (infinity when empty).
double rayleigh_time_step(const Particles& p, const MaterialTable& mats);
// Minimum over particles of sqrt(m_i / sum k_bn A) and sqrt(I_i / sum(k_bt A c_i^2 + k_bn J/2 + k_bt J)) over
// its intact bonds (the single-degree-of-freedom step 2/omega with omega^2 <= 2 sum k / m, Gershgorin bound).
// Infinity when there are no bonds.
double bond_time_step(const Particles& p, const std::vector<Bond>& bonds);

struct TimeStepCheck {
  double dt = 0, rayleigh = 0, bond = 0, rayleigh_fraction = 0;
  bool ok = true;
  std::string message;
};
// ok when dt <= max_rayleigh_fraction * rayleigh and dt <= bond; the message gives both numbers.
TimeStepCheck check_time_step(double dt, const Particles& p, const MaterialTable& mats,
                              const std::vector<Bond>& bonds, double max_rayleigh_fraction);

}  // namespace dem
