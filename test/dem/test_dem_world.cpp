// World-level behaviour: determinism, moving walls and wall forces, insertion/removal with stable ids,
// neighbour-list correctness against brute force, input validation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "dem/world.hpp"

namespace {

// A poured polydisperse packing in a box with two bonded clusters.
std::vector<double> run_packing(int threads, long steps, int count = 640) {
  dem::WorldParams wp;
  wp.dt = 1e-6;
  wp.threads = threads;
  dem::World w(wp);
  const double lo[3] = {0, 0, 0}, hi[3] = {0.02, 0.02, 0.1};
  w.add_box(lo, hi, 1, false);
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> U(0, 1);
  // 8 x 8 x 10 grid of 2 mm spacing, radii 0.6-0.95 mm, jittered, falling onto the floor
  for (int k = 0; k < count; ++k) {
    const double r = 0.6e-3 + 0.35e-3 * U(rng);
    const double x[3] = {0.003 + 0.002 * (k % 8) + 0.1e-3 * U(rng), 0.003 + 0.002 * ((k / 8) % 8) + 0.1e-3 * U(rng),
                         0.0011 + 0.002 * (k / 64)};
    const double v[3] = {0.1 * (U(rng) - 0.5), 0.1 * (U(rng) - 0.5), -1.0};
    w.add_particle(x, r, 0, v);
  }
  dem::BondParams bp;
  bp.kn = 100e9; bp.kt = 40e9; bp.sigma_c = 25e6; bp.tau_c = 9e6;
  w.bond_within(0.5e-3, bp, 0, 100);
  w.step(steps);
  const auto& p = w.particles();
  std::vector<double> out;
  for (std::size_t i = 0; i < p.size(); ++i) {
    out.push_back(p.x[i]); out.push_back(p.y[i]); out.push_back(p.z[i]);
    out.push_back(p.wx[i]);
  }
  out.push_back(w.wall(4).force[2]);
  out.push_back(static_cast<double>(w.n_contacts()));
  out.push_back(static_cast<double>(w.breaks().size()));
  return out;
}

TEST(World, SameThreadCountGivesBitwiseIdenticalResults) {
  const auto a = run_packing(2, 6000), b = run_packing(2, 6000);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k + 3 < a.size(); k += 4) {  // a sane state: finite, inside the box
    ASSERT_TRUE(std::isfinite(a[k]) && std::isfinite(a[k + 1]) && std::isfinite(a[k + 2]));
    ASSERT_GT(a[k], 0.0); ASSERT_LT(a[k], 0.02); ASSERT_GT(a[k + 2], 0.0);
  }
  EXPECT_GT(a[a.size() - 2], 20.0);  // a dense, colliding state (contact count)
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0);
  // every particle receives its pair and bond terms in one fixed order (slab blocks), so 1 thread gives the
  // same positions too
  const auto c = run_packing(1, 6000);
  for (std::size_t k = 0; k + 3 < a.size(); ++k) ASSERT_EQ(a[k], c[k]) << k;
}

// Above the serial threshold (1024 particles) every loop runs in parallel: 2 threads twice, 3 and 1 thread.
TEST(World, LargePackingIsBitwiseIdenticalRunToRunAndAcrossThreadCounts) {
  const auto a = run_packing(2, 2500, 2000), b = run_packing(2, 2500, 2000);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_GT(a[a.size() - 2], 40.0);  // colliding (contact count)
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0);
  const auto c = run_packing(3, 2500, 2000), d = run_packing(1, 2500, 2000);
  EXPECT_EQ(std::memcmp(a.data(), c.data(), a.size() * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(a.data(), d.data(), a.size() * sizeof(double)), 0);
}

// Neighbour list + Verlet skin must not miss contacts: compare the contact count with brute force while the
// particles move.
TEST(World, NeighbourListFindsEveryContact) {
  dem::WorldParams wp;
  wp.dt = 1e-6;
  wp.threads = 2;
  wp.max_overlap_fraction = 0;  // random insertion: some start deeply overlapped
  dem::World w(wp);
  const double lo[3] = {0, 0, 0}, hi[3] = {0.02, 0.02, 0.05};
  w.add_box(lo, hi, 1);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> U(0, 1);
  for (int k = 0; k < 800; ++k) {
    const double r = 0.4e-3 + 0.5e-3 * U(rng);
    const double x[3] = {0.001 + 0.018 * U(rng), 0.001 + 0.018 * U(rng), 0.001 + 0.048 * U(rng)};
    const double v[3] = {U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5};
    w.add_particle(x, r, 0, v);
  }
  for (int round = 0; round < 5; ++round) {
    w.step(300);
    const auto& p = w.particles();
    std::size_t brute = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
      for (std::size_t j = i + 1; j < p.size(); ++j) {
        const double dx = p.x[i] - p.x[j], dy = p.y[i] - p.y[j], dz = p.z[i] - p.z[j], rs = p.r[i] + p.r[j];
        if (dx * dx + dy * dy + dz * dz < rs * rs) ++brute;
      }
    EXPECT_EQ(w.n_contacts(), brute) << "round " << round;
  }
  EXPECT_GT(w.n_rebuilds(), 1);
}

// A platen moving at constant speed v onto a sphere resting on a fixed floor: the sphere moves at v/2, each
// contact closes at v/2 and carries the Hertz force of its overlap plus the Eq. 16 damping force
// 2 sqrt(5/6) xi sqrt(m k_n) v/2 (2.7 % of the total here, so the check sees the damping law too).
TEST(World, MovingWallForceMatchesHertz) {
  dem::WorldParams wp;
  wp.dt = 1e-7;
  wp.gravity = {{0, 0, 0}};
  wp.threads = 1;
  dem::World w(wp);
  const double r = 5e-3;
  const double o[3] = {0, 0, 0}, up[3] = {0, 0, 1}, top[3] = {0, 0, 2 * r}, down[3] = {0, 0, -1};
  w.add_plane(o, up, 1);
  const int platen = w.add_plane(top, down, 1);
  const double x[3] = {0, 0, r};
  w.add_particle(x, r, 0);
  const double vp[3] = {0, 0, -0.01};
  w.set_wall_velocity(platen, vp);
  w.step(20000);  // platen moved 20 um
  const double total = 0.01 * w.time();
  const double dz_each = 0.5 * total;
  const dem::PairProps& pp = w.materials().pair(0, 1);
  const double m = w.particles().m[0];
  const double kn = 2 * pp.E_star * std::sqrt(r * dz_each);
  const double F = 4.0 / 3.0 * pp.E_star * std::sqrt(r) * std::pow(dz_each, 1.5) +
                   2 * std::sqrt(5.0 / 6.0) * pp.beta * std::sqrt(m * kn) * 0.005;
  EXPECT_NEAR(w.wall(platen).force[2], F, 0.005 * F);
  EXPECT_NEAR(w.wall(0).force[2], -F, 0.005 * F);
  EXPECT_NEAR(w.wall(platen).p[2], 2 * r - total, 1e-12);
}

TEST(World, InsertionAndRemovalKeepIdsAndBonds) {
  dem::WorldParams wp;
  wp.dt = 1e-7;
  wp.gravity = {{0, 0, 0}};
  dem::World w(wp);
  const double r = 1e-3;
  for (int k = 0; k < 6; ++k) {
    const double x[3] = {2 * r * k, 0, 0};
    w.add_particle(x, r, 0);
  }
  dem::BondParams bp;
  bp.kn = 400e9; bp.kt = 160e9; bp.sigma_c = 25e6; bp.tau_c = 9e6;
  EXPECT_EQ(w.bond_within(1e-9, bp), 5u);
  w.step(10);
  const uint64_t id3 = w.particles().id[3];
  w.remove_particles_by_id({w.particles().id[1]});
  EXPECT_EQ(w.particles().size(), 5u);
  EXPECT_EQ(w.index_of(id3), 2);
  EXPECT_EQ(w.n_bonds_intact(), 3u);  // bonds 0-1 and 1-2 went with particle 1
  EXPECT_TRUE(w.breaks().empty());    // removal is not breakage
  // a new cluster inserted while running gets fresh ids and its own bonds
  const std::size_t first = w.particles().size();
  for (int k = 0; k < 3; ++k) {
    const double x[3] = {2 * r * k, 0.01, 0};
    w.add_particle(x, r, 0);
  }
  EXPECT_EQ(w.bond_within(1e-9, bp, first), 2u);
  EXPECT_EQ(w.particles().id[first], 6u);
  w.step(10);
  EXPECT_EQ(w.n_bonds_intact(), 5u);
  EXPECT_EQ(w.index_of(1), -1);
  EXPECT_LT(w.kinetic_energy(), 1e-20);
}

TEST(World, BadInputIsRejected) {
  dem::WorldParams wp;
  wp.dt = -1;
  EXPECT_THROW(dem::World{wp}, std::invalid_argument);
  wp.dt = 1e-7;
  dem::World w(wp);
  const double x[3] = {0, 0, 0}, zero[3] = {0, 0, 0};
  EXPECT_THROW(w.add_particle(x, -1e-3, 0), std::invalid_argument);
  EXPECT_THROW(w.add_particle(x, 1e-3, 7), std::invalid_argument);
  EXPECT_THROW(w.add_plane(x, zero, 1), std::invalid_argument);
  EXPECT_THROW(w.remove_particles(std::vector<char>(3, 0)), std::invalid_argument);
}

}  // namespace

// A dense colliding cloud without gravity or walls on 3 threads (parallel slab blocks): every pair force is
// applied to both partners exactly once, so linear momentum stays at its initial value up to rounding.
TEST(World, ParallelPairForcesConserveMomentum) {
  dem::WorldParams wp;
  wp.dt = 1e-6;
  wp.gravity = {{0, 0, 0}};
  wp.threads = 3;
  dem::World w(wp);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(0, 1);
  for (int k = 0; k < 3000; ++k) {  // 15 x 15 x 13.3 lattice of 2 mm spacing, radii up to 1.05 mm: touching
    const double x[3] = {0.002 * (k % 15), 0.002 * ((k / 15) % 15), 0.002 * (k / 225)};
    const double v[3] = {U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5};
    w.add_particle(x, 0.9e-3 + 0.15e-3 * U(rng), 0, v);
  }
  auto momentum = [&w](double out[3]) {
    const auto& p = w.particles();
    double scale = 0;
    out[0] = out[1] = out[2] = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      out[0] += p.m[i] * p.vx[i]; out[1] += p.m[i] * p.vy[i]; out[2] += p.m[i] * p.vz[i];
      scale += p.m[i] * std::sqrt(p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i]);
    }
    return scale;
  };
  double p0[3], p1[3];
  const double scale = momentum(p0);
  w.step(1);
  EXPECT_GT(w.n_contacts(), 1000u);
  w.step(1500);
  momentum(p1);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(p1[a], p0[a], 1e-12 * scale) << a;
}
