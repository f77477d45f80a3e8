#include "coupling/metaparticle_crushing.hpp"

#include <algorithm>
#include <cmath>

namespace coupling {

double crushing_force(double d, double tensile_strength) { return M_PI * d * d * tensile_strength / 2.8; }

std::vector<std::size_t> crushed_particles(const dem::Particles& P, const std::vector<const dem::MeshContact*>& meshes,
                                           double tensile_strength) {
  std::vector<std::size_t> out;
  for (const auto* mc : meshes)
    for (const auto& c : mc->contacts()) {
      const auto i = static_cast<std::size_t>(c.particle_index);
      if (i < P.size() && c.normal_force > crushing_force(2.0 * P.r[i], tensile_strength)) out.push_back(i);
    }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<double> progeny_by_class(double mass, double d, const std::vector<double>& sieves, double exponent) {
  std::vector<double> out(sieves.size() + 1, 0.0);
  double below = 0;  // mass passing the previous sieve
  for (std::size_t k = 0; k < sieves.size(); ++k) {
    const double passing = mass * std::pow(std::min(1.0, sieves[k] / d), exponent);
    out[k] = passing - below;
    below = passing;
  }
  out.back() = mass - below;
  return out;
}

}  // namespace coupling
