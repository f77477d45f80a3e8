#include "coupling/metaparticle_crushing.hpp"

#include <algorithm>
#include <cmath>

#include "dem/world.hpp"

namespace coupling {

double crushing_force(double d, double tensile_strength) { return M_PI * d * d * tensile_strength / 2.8; }

double CrushingStrength::sigma(double d) const { return k == 0 ? sigma_t : sigma_t * std::pow(d_ref / d, k); }

double CrushingStrength::force(double d) const { return crushing_force(d, sigma(d)); }

double equivalent_diameter(double m, double rho) { return std::cbrt(6.0 * m / (M_PI * rho)); }

// Four equal spheres touching each other and the parent's surface: r_f = r / (1 + sqrt(3/2)), centres at
// r - r_f from the parent's centre along the vertices of a regular tetrahedron.
double fragment_radius(double parent_radius) { return parent_radius / (1.0 + std::sqrt(1.5)); }

FragmentSet tetrahedral_fragments(double parent_radius, const Eigen::Matrix3d& rotation) {
  static const double v[4][3] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  FragmentSet f;
  f.radius = fragment_radius(parent_radius);
  const double d = (parent_radius - f.radius) / std::sqrt(3.0);
  for (int k = 0; k < 4; ++k) f.offset[k] = d * (rotation * Eigen::Vector3d(v[k][0], v[k][1], v[k][2]));
  return f;
}

namespace {
// A mesh contact record of the last step whose particle is still at its index (removals make records stale).
bool current(const dem::Particles& P, const dem::MeshContactRecord& c) {
  const auto i = static_cast<std::size_t>(c.particle_index);
  return i < P.size() && P.id[i] == c.particle_id;
}
}  // namespace

std::vector<std::size_t> crushed_particles(const dem::Particles& P, const std::vector<const dem::MeshContact*>& meshes,
                                           const CrushingStrength& strength, double rho) {
  std::vector<std::size_t> out;
  std::vector<std::pair<std::size_t, double>> load;  // (particle, normal force) per contact with one mesh
  for (const auto* mc : meshes) {
    load.clear();
    for (const auto& c : mc->contacts()) {
      if (current(P, c)) load.emplace_back(static_cast<std::size_t>(c.particle_index), c.normal_force);
    }
    // A sphere pressed across an edge of the tessellation touches two facets: their forces add up.
    std::sort(load.begin(), load.end());
    for (std::size_t a = 0; a < load.size();) {
      std::size_t b = a;
      double f = 0;
      for (; b < load.size() && load[b].first == load[a].first; ++b) f += load[b].second;
      const std::size_t i = load[a].first;
      if (f > strength.force(equivalent_diameter(P.m[i], rho))) out.push_back(i);
      a = b;
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

double equivalent_diametral_load(const double* s6, double r) {
  const double a = s6[0] - s6[1], b = s6[1] - s6[2], c = s6[2] - s6[0];
  const double vm = std::sqrt(0.5 * (a * a + b * b + c * c) + 3.0 * (s6[3] * s6[3] + s6[4] * s6[4] + s6[5] * s6[5]));
  const double pressure = -(s6[0] + s6[1] + s6[2]) / 3.0;  // 2 r F under six equal loads F
  return std::max(vm, pressure) / (2.0 * r);
}

std::vector<std::size_t> crushed_by_stress(const dem::Particles& P, std::vector<double>& s,
                                           const std::vector<const dem::MeshContact*>& meshes,
                                           const CrushingStrength& strength, double rho) {
  s.resize(6 * P.size(), 0.0);
  for (const auto* mc : meshes)
    for (const auto& c : mc->contacts()) {
      if (!current(P, c)) continue;
      const auto i = static_cast<std::size_t>(c.particle_index);
      const Eigen::Vector3d a = -P.r[i] * c.normal;  // arm at the radius, as World::contact_stress
      dem::add_contact_stress(&s[6 * i], a.data(), c.force.data());
    }
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const double* t = &s[6 * i];
    if (t[0] == 0 && t[1] == 0 && t[2] == 0 && t[3] == 0 && t[4] == 0 && t[5] == 0) continue;
    if (equivalent_diametral_load(t, P.r[i]) > strength.force(equivalent_diameter(P.m[i], rho))) out.push_back(i);
  }
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
