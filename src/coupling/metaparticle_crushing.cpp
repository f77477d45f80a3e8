#include "coupling/metaparticle_crushing.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dem/world.hpp"

namespace coupling {

double crushing_force(double d, double tensile_strength) { return M_PI * d * d * tensile_strength / 2.8; }

double CrushingStrength::sigma(double d) const { return k == 0 ? sigma_t : sigma_t * std::pow(d_ref / d, k); }

double CrushingStrength::force(double d) const { return crushing_force(d, sigma(d)); }

double equivalent_diameter(double m, double rho) { return std::cbrt(6.0 * m / (M_PI * rho)); }

double CrushingStrength::force_of_sphere(double m, double r, double rho) const {
  const double d = equivalent_diameter(m, rho);
  return crushing_force(std::min(d, 2.0 * r), sigma(d));
}

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

double overlap_ratio(const Eigen::Vector3d& x, double r, const Obstacle& o) {
  if (o.r <= 0) return (r - (x - o.c).dot(o.n)) / r;
  return (r + o.r - (x - o.c).norm()) / std::min(r, o.r);
}

PlacedFragments place_fragments(const Eigen::Vector3d& x, double r, const std::vector<Eigen::Matrix3d>& orientations,
                                const std::vector<Obstacle>& obstacles, bool shrink) {
  if (orientations.empty()) throw std::invalid_argument("place_fragments: no orientation to try");
  auto deepest = [&](const FragmentSet& f) {
    double worst = -1e300;
    for (const auto& off : f.offset)
      for (const auto& o : obstacles) worst = std::max(worst, overlap_ratio(x + off, f.radius, o));
    return worst;
  };
  PlacedFragments best;
  best.deepest = 1e300;
  for (const auto& rot : orientations) {
    const FragmentSet f = tetrahedral_fragments(r, rot);
    const double d = obstacles.empty() ? 0.0 : deepest(f);
    if (d < best.deepest) {
      best.set = f;
      best.deepest = d;
    }
  }
  best.deepest = std::max(best.deepest, 0.0);
  const double rf = best.set.radius, b = kFragmentBirthOverlap;
  for (int k = 0; k < 4; ++k) {
    double rb = rf;
    if (shrink) {
      const Eigen::Vector3d xf = x + best.set.offset[k];
      for (const auto& o : obstacles) {
        // Largest radius with overlap <= b x (the smaller radius), from overlap_ratio solved for r.
        if (o.r <= 0) {
          rb = std::min(rb, (xf - o.c).dot(o.n) / (1 - b));
        } else {
          const double d = (xf - o.c).norm();
          rb = std::min(rb, std::min((d - o.r) / (1 - b), d - (1 - b) * o.r));
        }
      }
      rb = std::max(rb, 0.5 * rf);
    }
    best.birth_radius[k] = rb;
  }
  return best;
}

std::vector<PlacedFragments> place_crushed_batch(std::vector<CrushedSphere>& batch, bool shrink) {
  std::vector<PlacedFragments> out(batch.size());
  for (std::size_t n = 0; n < batch.size(); ++n) {
    if (batch[n].turns.empty()) continue;
    out[n] = place_fragments(batch[n].x, batch[n].r, batch[n].turns, batch[n].obstacles, shrink);
    for (std::size_t m : batch[n].crushed_neighbours) {
      if (m <= n || m >= batch.size()) continue;  // an earlier one's fragments are already among n's obstacles
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector3d c = batch[n].x + out[n].set.offset[k];
        batch[m].obstacles.push_back({c, Eigen::Vector3d::Zero(), out[n].birth_radius[k]});
      }
    }
  }
  return out;
}

bool contact_is_current(const dem::Particles& P, const dem::MeshContactRecord& c) {
  const auto i = static_cast<std::size_t>(c.particle_index);
  return i < P.size() && P.id[i] == c.particle_id;
}

std::vector<std::size_t> crushed_particles(const dem::Particles& P, const std::vector<const dem::MeshContact*>& meshes,
                                           const CrushingStrength& strength, double rho) {
  std::vector<std::size_t> out;
  std::vector<std::pair<std::size_t, double>> load;  // (particle, normal force) per contact with one mesh
  for (const auto* mc : meshes) {
    load.clear();
    for (const auto& c : mc->contacts()) {
      if (contact_is_current(P, c)) load.emplace_back(static_cast<std::size_t>(c.particle_index), c.normal_force);
    }
    // A sphere pressed across an edge of the tessellation touches two facets: their forces add up.
    std::sort(load.begin(), load.end());
    for (std::size_t a = 0; a < load.size();) {
      std::size_t b = a;
      double f = 0;
      for (; b < load.size() && load[b].first == load[a].first; ++b) f += load[b].second;
      const std::size_t i = load[a].first;
      if (f > strength.force_of_sphere(P.m[i], P.r[i], rho)) out.push_back(i);
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
      if (!contact_is_current(P, c)) continue;
      const auto i = static_cast<std::size_t>(c.particle_index);
      const Eigen::Vector3d a = -P.r[i] * c.normal;  // arm at the radius, as World::contact_stress
      dem::add_contact_stress(&s[6 * i], a.data(), c.force.data());
    }
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const double* t = &s[6 * i];
    if (t[0] == 0 && t[1] == 0 && t[2] == 0 && t[3] == 0 && t[4] == 0 && t[5] == 0) continue;
    if (equivalent_diametral_load(t, P.r[i]) > strength.force_of_sphere(P.m[i], P.r[i], rho)) out.push_back(i);
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
