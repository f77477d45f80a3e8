#pragma once
// Scatter of a cell's bed pressure from one pressing to the next, from the discreteness of its lumps: the
// nip-scale scatter that a bonded-particle DEM has (the paper's power std, Table 5) and a continuum lacks.
// A bed's pressure at a given compression is carried by its lumps, and lumps differ (shape, flaws, how they lie),
// so a bed of few lumps is stronger or weaker than the mean from one pressing to the next. With each lump carrying
// in proportion to its mass and independently of the others, the bed's relative variance is one lump's over the
// bed's effective number of lumps (the mass-weighted sample size of Gy's sampling theory, variance ~ d^3 / M):
//     sigma_bed^2 = sigma_1^2 / N_eff,   N_eff = M^2 / sum_i m_i^2 = M / sum_j f_j m_j   (at least 1)
// f_j the mass fractions by size class, m_j the mass of a lump of the class's representative size. sigma_1 (the
// material's `scatter.lump_std`) comes from replicate virtual piston-die tests: the relative std of the peak
// pressure between pourings of the same rocks, times sqrt(N_eff) of the die's bed. Never from Table 5.
#include <cstdint>
#include <string>
#include <vector>

#include "rocks/rng.hpp"

namespace chamber {

// Largest lump_std accepted (a lump's share three times its mean on one sigma is already implausible).
constexpr double kMaxLumpStd = 3.0;

// Mass of a lump (a sphere) of size x (m) of solid density rho.
double lump_mass(double size_m, double solid_density);

// N_eff of a bed holding kg[j] of class j, lump_kg[j] the mass of one lump of it: M / sum_j f_j m_j, at least 1
// (a bed lighter than one lump is that lump's); 0 for an empty bed.
double effective_lumps(const double* kg, const std::vector<double>& lump_kg);

// sigma_bed = sigma_1 / sqrt(N_eff) (0 for an empty bed).
double bed_pressure_std(double lump_std, double n_eff);

// sigma_1 from replicate pressings of beds of n_eff lumps: the sample's relative std (n - 1) x sqrt(n_eff).
// std::invalid_argument for fewer than two values or a non-positive mean.
double lump_std_from_replicates(const std::vector<double>& peaks, double n_eff);

// Reproducible factors of mean 1 and a given relative std (lognormal: never negative), one per pressing.
class ScatterDraws {
 public:
  explicit ScatterDraws(std::uint64_t seed) : rng_(seed) {}
  // exp(s z - s^2 / 2), s^2 = ln(1 + rel_std^2); exactly 1 (no draw) for rel_std 0.
  double factor(double rel_std);
  std::string state() const { return rng_.state(); }
  bool set_state(const std::string& s) { return rng_.set_state(s); }

 private:
  rocks::Rng rng_;
};

}  // namespace chamber
