#pragma once
// DEM material properties (paper Table 4) and pair properties with the mixed moduli of Eq. 17.
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace dem {

struct Material {
  std::string name;
  double density = 0;  // kg/m^3
  double G = 0;        // shear modulus, Pa
  double nu = 0;       // Poisson's ratio
  double E() const { return 2.0 * G * (1.0 + nu); }  // Young's modulus
};

// Table 4 of the paper.
inline Material rock_table4() { return {"rock", 2600.0, 5.08e8, 0.35}; }
inline Material steel_table4() { return {"steel", 7800.0, 7.0e10, 0.3}; }

// Properties of a contact between two materials (Eq. 16-19).
struct PairProps {
  double friction = 0;          // Coulomb mu (Eq. 19)
  double restitution = 1;       // e
  double rolling_friction = 0;  // mu_r (CDT model)
  double E_star = 0;            // Eq. 17: (sum (1-nu^2)/E)^-1
  double G_star = 0;            // Mindlin: (sum (2-nu)/G)^-1
  double beta = 0;              // xi_d = -ln e / sqrt(ln^2 e + pi^2) (Eq. 16), 0 for e = 1
  double sqrt_kt_kn = 0;        // sqrt(k_t / k_n) = sqrt(4 G* / E*), cached by make_pair (0: computed on use)
};

inline double xi_from_restitution(double e) {
  if (!(e > 0) || e > 1)
    throw std::invalid_argument("restitution coefficient must be in (0, 1], got " + std::to_string(e));
  if (e == 1.0) return 0.0;
  const double l = std::log(e);
  return -l / std::sqrt(l * l + M_PI * M_PI);
}

inline PairProps make_pair(const Material& a, const Material& b, double friction, double restitution,
                           double rolling_friction) {
  if (!(friction >= 0)) throw std::invalid_argument("friction coefficient must be >= 0");
  if (!(rolling_friction >= 0)) throw std::invalid_argument("rolling friction coefficient must be >= 0");
  if (!(a.G > 0) || !(b.G > 0) || !(a.nu > -1 && a.nu < 0.5) || !(b.nu > -1 && b.nu < 0.5))
    throw std::invalid_argument("material '" + a.name + "'/'" + b.name +
                                "': need G > 0 and Poisson ratio in (-1, 0.5)");
  PairProps p;
  p.friction = friction;
  p.restitution = restitution;
  p.rolling_friction = rolling_friction;
  p.E_star = 1.0 / ((1 - a.nu * a.nu) / a.E() + (1 - b.nu * b.nu) / b.E());
  p.G_star = 1.0 / ((2 - a.nu) / a.G + (2 - b.nu) / b.G);
  p.beta = xi_from_restitution(restitution);
  p.sqrt_kt_kn = std::sqrt(4.0 * p.G_star / p.E_star);
  return p;
}

// Materials by index plus a symmetric pair table. Index 0/1 are rock/steel in default_table4().
class MaterialTable {
 public:
  int add(const Material& m) {
    if (!(m.density > 0)) throw std::invalid_argument("material '" + m.name + "': density must be > 0");
    mats_.push_back(m);
    pairs_.assign(mats_.size() * mats_.size(), PairProps{});
    set_.assign(mats_.size() * mats_.size(), 0);
    return static_cast<int>(mats_.size()) - 1;
  }
  // Add all materials first, then set pairs (adding a material clears the pair table).
  void set_pair(int i, int j, double friction, double restitution, double rolling_friction) {
    check(i); check(j);
    const PairProps p = make_pair(mats_[i], mats_[j], friction, restitution, rolling_friction);
    pairs_[i * n() + j] = p; pairs_[j * n() + i] = p;
    set_[i * n() + j] = set_[j * n() + i] = 1;
  }
  const PairProps& pair(int i, int j) const { return pairs_[i * n() + j]; }
  bool has_pair(int i, int j) const { return i >= 0 && j >= 0 && i < n() && j < n() && set_[i * n() + j]; }
  const Material& material(int i) const { check(i); return mats_[i]; }
  int n() const { return static_cast<int>(mats_.size()); }
  int find(const std::string& name) const {
    for (int i = 0; i < n(); ++i) if (mats_[i].name == name) return i;
    throw std::invalid_argument("unknown material '" + name + "'");
  }

 private:
  void check(int i) const {
    if (i < 0 || i >= n())
      throw std::invalid_argument("material index " + std::to_string(i) + " out of range [0, " +
                                  std::to_string(n()) + ")");
  }
  std::vector<Material> mats_;
  std::vector<PairProps> pairs_;
  std::vector<char> set_;
};

// Table 4: rock = 0, steel = 1; rock-rock mu 0.5 e 0.15 mu_r 0.001; rock-steel mu 0.7 e 0.2 mu_r 0.001.
// Steel-steel is not in Table 4; it is set to the rock-steel values so every pair is defined.
inline MaterialTable default_table4() {
  MaterialTable t;
  const int rock = t.add(rock_table4());
  const int steel = t.add(steel_table4());
  t.set_pair(rock, rock, 0.5, 0.15, 0.001);
  t.set_pair(rock, steel, 0.7, 0.2, 0.001);
  t.set_pair(steel, steel, 0.7, 0.2, 0.001);
  return t;
}

}  // namespace dem
