#include "chamber/bed_scatter.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace chamber {

double lump_mass(double size_m, double solid_density) {
  return solid_density * (M_PI / 6.0) * size_m * size_m * size_m;
}

double effective_lumps(const double* kg, const std::vector<double>& lump_kg) {
  double M = 0, weighted = 0;  // weighted = sum_j M_j m_j = M sum_j f_j m_j
  for (std::size_t j = 0; j < lump_kg.size(); ++j) {
    M += kg[j];
    weighted += kg[j] * lump_kg[j];
  }
  if (M <= 0 || weighted <= 0) return 0.0;
  return std::max(1.0, M * M / weighted);
}

double bed_pressure_std(double lump_std, double n_eff) {
  return n_eff > 0 ? lump_std / std::sqrt(n_eff) : 0.0;
}

double lump_std_from_replicates(const std::vector<double>& peaks, double n_eff) {
  if (peaks.size() < 2) throw std::invalid_argument("the bed's scatter needs at least two replicate pressings");
  double mean = 0;
  for (double p : peaks) mean += p;
  mean /= double(peaks.size());
  if (!(mean > 0)) throw std::invalid_argument("the replicate pressings' mean peak pressure is not positive");
  double var = 0;
  for (double p : peaks) var += (p - mean) * (p - mean);
  var /= double(peaks.size() - 1);
  return std::sqrt(var) / mean * std::sqrt(n_eff);
}

double ScatterDraws::factor(double rel_std) {
  if (rel_std <= 0) return 1.0;
  const double s2 = std::log1p(rel_std * rel_std);
  return std::exp(std::sqrt(s2) * rng_.normal() - 0.5 * s2);
}

}  // namespace chamber
