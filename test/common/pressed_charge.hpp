#pragma once
// A small pressed charge for the domain-decomposition tests (test/dem/test_ghost_domains.cpp in one process,
// test/parallel over MPI): 500 spheres of 0.9-1 mm in a box about the z axis, the top two layers weakly bonded, thrown
// about and pressed by a descending lid for 3 ms, then saved, so that contacts with histories, bonds and breaks
// cross the sector boundaries of the steps that follow; and the whole charge's own steps from that state.
#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/binary_io.hpp"
#include "dem/ghost_domains.hpp"
#include "dem/mesh_contact.hpp"
#include "dem/world.hpp"

namespace pressed_charge {

constexpr double kHalf = 0.0105;  // box half-width, m
constexpr double kLid = 0.0102;   // lid height at t = 0, m (the charge's top at ~10 mm)
constexpr double kLidSpeed = -0.15;

inline dem::WorldParams params() {
  dem::WorldParams wp;
  wp.dt = 1.5e-6;  // under the bonds' critical step (1.67e-6 s)
  wp.threads = 1;
  return wp;
}

// Walls (the setup a checkpoint's loader repeats): four sides, the floor, and the lid coming down.
inline void walls(dem::World& w) {
  const double lo[3] = {-kHalf, -kHalf, 0}, hi[3] = {kHalf, kHalf, kLid};
  w.add_box(lo, hi, 1, false);
  const double n[3] = {0, 0, -1}, v[3] = {0, 0, kLidSpeed};
  w.set_wall_velocity(w.add_plane(hi, n, 1), v);
}

using Setup = std::function<void(dem::World&)>;

// The same box with a floor of 288 triangles (a 12 x 12 grid of squares at z = 0) instead of the planar floor: the
// liner of the tests with a mesh. Each MeshContact made is appended to *made (when given), so a test can read the
// wrench of every World a decomposition makes.
inline Setup on_plate(std::vector<std::shared_ptr<dem::MeshContact>>* made) {
  return [made](dem::World& w) {
    const double lo[3] = {-kHalf, -kHalf, 0}, hi[3] = {kHalf, kHalf, kLid};
    const double nx[3] = {1, 0, 0}, mx[3] = {-1, 0, 0}, ny[3] = {0, 1, 0}, my[3] = {0, -1, 0};
    w.add_plane(lo, nx, 1);
    w.add_plane(hi, mx, 1);
    w.add_plane(lo, ny, 1);
    w.add_plane(hi, my, 1);
    const double n[3] = {0, 0, -1}, v[3] = {0, 0, kLidSpeed};
    w.set_wall_velocity(w.add_plane(hi, n, 1), v);
    const int m = 12;
    const double h = 2 * kHalf / m;
    std::vector<Eigen::Vector3d> vert;
    std::vector<dem::Triangle> tri;
    for (int j = 0; j <= m; ++j)
      for (int i = 0; i <= m; ++i) vert.emplace_back(-kHalf + i * h, -kHalf + j * h, 0.0);
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        const int a = j * (m + 1) + i, b = a + 1, c = a + m + 2, d = a + m + 1;
        tri.push_back({a, b, c});
        tri.push_back({a, c, d});
      }
    auto mc = std::make_shared<dem::MeshContact>(dem::TriMesh(vert, tri, "plate"), w.materials(), 1);
    mc->set_threads(1);
    w.add_interaction(mc);
    if (made) made->push_back(mc);
  };
}

// The whole charge after 3 ms, saved: returns the checkpoint.
inline std::string whole_charge_state(const Setup& setup = walls) {
  dem::World w(params());
  setup(w);
  std::mt19937_64 rng(25);
  std::uniform_real_distribution<double> U(0, 1);
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 10; ++j)
      for (int i = 0; i < 10; ++i) {
        const double r = 0.9e-3 + 0.1e-3 * U(rng);
        const double x[3] = {-9e-3 + 2e-3 * i + 0.05e-3 * (U(rng) - 0.5), -9e-3 + 2e-3 * j + 0.05e-3 * (U(rng) - 0.5),
                             1e-3 + 2e-3 * k};
        const double v[3] = {0.1 * (U(rng) - 0.5), 0.1 * (U(rng) - 0.5), 0.1 * (U(rng) - 0.5)};
        w.add_particle(x, r, 0, v);
      }
  dem::BondParams bp;
  bp.kn = 100e9;
  bp.kt = 40e9;
  bp.sigma_c = 0.2e6;
  bp.tau_c = 0.15e6;
  // the two top layers (under the lid), bonded where the spheres nearly touch
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  const dem::Particles& p = w.particles();
  for (std::size_t a = 300; a < 500; ++a)
    for (std::size_t b = a + 1; b < 500; ++b) {
      const double d = std::hypot(p.x[a] - p.x[b], p.y[a] - p.y[b], p.z[a] - p.z[b]);
      if (d < p.r[a] + p.r[b] + 0.15e-3) pairs.push_back({a, b});
    }
  w.bond_pairs(pairs, bp);
  w.step(2000);
  std::ostringstream os;
  core::BinaryWriter wr(os);
  w.save_state(wr);
  return os.str();
}

inline const std::string& state() {
  static const std::string s = whole_charge_state();
  return s;
}

inline const std::string& plate_state() {
  static const std::string s = whole_charge_state(on_plate(nullptr));
  return s;
}

// The whole charge loaded from its checkpoint and stepped n times: its state by id (as LocalDomains gives it).
struct Reference {
  std::vector<uint64_t> ids;
  std::vector<double> x;
  std::vector<std::pair<uint64_t, uint64_t>> breaks;
  std::vector<std::pair<uint64_t, uint64_t>> bonds;  // intact, by particle ids, sorted
  dem::MeshWrench plate;  // the last step's wrench on the plate about the origin (with on_plate)
};

// The intact bonds of a World whose first particle is owned (all: owned empty), by particle ids.
inline void add_intact_bonds(const dem::World& w, const std::vector<char>& owned,
                             std::vector<std::pair<uint64_t, uint64_t>>& out) {
  for (const dem::Bond& b : w.bonds())
    if (b.alive && (owned.empty() || owned[b.i])) out.push_back({w.particles().id[b.i], w.particles().id[b.j]});
}

// plate: the charge on the plate (plate_state, on_plate), else in the box (state, walls).
inline Reference reference(long n, bool plate = false) {
  std::vector<std::shared_ptr<dem::MeshContact>> made;
  dem::World w(params());
  if (plate) on_plate(&made)(w); else walls(w);
  std::istringstream is(plate ? plate_state() : state());
  core::BinaryReader r(is, "test");
  w.load_state(r);
  const std::size_t before = w.breaks().size();
  w.step(n);
  Reference ref;
  const dem::Particles& p = w.particles();
  std::vector<uint32_t> all(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) all[i] = static_cast<uint32_t>(i), ref.ids.push_back(p.id[i]);
  dem::pack_ghosts(p, all, ref.x);
  for (std::size_t k = before; k < w.breaks().size(); ++k) ref.breaks.push_back({w.breaks()[k].id_i, w.breaks()[k].id_j});
  std::sort(ref.breaks.begin(), ref.breaks.end());
  add_intact_bonds(w, {}, ref.bonds);
  std::sort(ref.bonds.begin(), ref.bonds.end());
  if (!made.empty()) ref.plate = made.back()->wrench_about(Eigen::Vector3d::Zero());
  return ref;
}

constexpr long kSteps = 300;  // 0.45 ms
constexpr double kReach = 2e-3 + 1.0e-3;  // a margin of 0.5 mm

// The largest difference of the positions (x, y, z of each kGhostDoubles record) of two states (m).
inline double largest_position_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0;
  for (std::size_t k = 0; k < a.size() && k < b.size(); ++k)
    if (k % dem::kGhostDoubles < 3) worst = std::max(worst, std::fabs(a[k] - b[k]));
  return worst;
}

// A feed and discharge between steps: the 10 lowest particles (by z, then id) leave and 10 new ones of the same size
// take their places at rest (new ids), so the box stays full and nothing overlaps.
inline void recycle_lowest(dem::World& w) {
  const dem::Particles& p = w.particles();
  std::vector<std::size_t> order(p.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return p.z[a] != p.z[b] ? p.z[a] < p.z[b] : p.id[a] < p.id[b];
  });
  std::vector<char> remove(p.size(), 0);
  std::vector<std::array<double, 4>> again;
  for (std::size_t k = 0; k < 10 && k < order.size(); ++k) {
    const std::size_t i = order[k];
    remove[i] = 1;
    again.push_back({p.x[i], p.y[i], p.z[i], p.r[i]});
  }
  w.remove_particles(remove);
  for (const auto& a : again) w.add_particle(a.data(), a[3], 0);
}

// The breaks among b logged after the cut (those before it are in every rank's log), as sorted id pairs.
inline std::vector<std::pair<uint64_t, uint64_t>> breaks_after_cut(const std::vector<dem::BondBreak>& b) {
  dem::World w(params());
  walls(w);
  std::istringstream is(state());
  core::BinaryReader r(is, "test");
  w.load_state(r);
  std::vector<std::pair<uint64_t, uint64_t>> old, out;
  for (const auto& x : w.breaks()) old.push_back({x.id_i, x.id_j});
  std::sort(old.begin(), old.end());
  for (const auto& x : b)
    if (!std::binary_search(old.begin(), old.end(), std::make_pair(x.id_i, x.id_j))) out.push_back({x.id_i, x.id_j});
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace pressed_charge
