// World::contact_stress (contact_stress.cpp): the per-particle sums of sym(a (x) f) over touching pairs.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "dem/world.hpp"

namespace {

// A 16^3 lattice of ~1 mm spheres spaced closer than their diameters: every lattice neighbour overlaps. One tiny
// step from rest builds the neighbour list and the touch flags without moving anything measurably.
dem::World overlapping_lattice(int threads) {
  dem::WorldParams wp;
  wp.dt = 1e-8;
  wp.threads = threads;
  wp.gravity = {0, 0, 0};
  wp.check_time_step = false;
  dem::World w(wp);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> U(-1, 1);
  const int n = 16;
  for (int k = 0; k < n * n * n; ++k) {
    const double x[3] = {1.98e-3 * (k % n) + 5e-6 * U(rng), 1.98e-3 * ((k / n) % n) + 5e-6 * U(rng),
                         1.98e-3 * (k / (n * n)) + 5e-6 * U(rng)};
    w.add_particle(x, 1e-3 + 5e-6 * U(rng), 0);
  }
  w.step(1);
  return w;
}

}  // namespace

// The trace of a pair's sym(a (x) f) is a . f = -(r_i) F_n on i and -(r_j) F_n on j (the shear force is normal to
// the arm), with the Hertz force F_n = 4/3 E* sqrt(r*) delta^1.5 at rest (Eq. 16): the particles' traces add up to
// -sum over touching pairs of (r_i + r_j) F_n, found here by brute force. The pass is parallel over pairs and
// sums in pair order: 1 and 2 threads give the same sums bit for bit.
TEST(ContactStress, TracesAddUpToTheHertzForcesAndThreadsAgreeBitForBit) {
  const dem::World one = overlapping_lattice(1), two = overlapping_lattice(2);
  const auto& P = one.particles();
  const double E = one.materials().pair(0, 0).E_star;
  double expected = 0;
  std::size_t touching = 0;
  for (std::size_t i = 0; i < P.size(); ++i)
    for (std::size_t j = i + 1; j < P.size(); ++j) {
      const double d = std::sqrt(std::pow(P.x[i] - P.x[j], 2) + std::pow(P.y[i] - P.y[j], 2) +
                                 std::pow(P.z[i] - P.z[j], 2));
      const double delta = P.r[i] + P.r[j] - d;
      if (delta <= 0) continue;
      const double r_eff = P.r[i] * P.r[j] / (P.r[i] + P.r[j]);
      expected -= (P.r[i] + P.r[j]) * 4.0 / 3.0 * E * std::sqrt(r_eff) * std::pow(delta, 1.5);
      ++touching;
    }
  ASSERT_GT(touching, 10000u);  // above the parallel threshold (1024 pairs)
  std::vector<double> s1, s2;
  auto time = [](const dem::World& w, std::vector<double>& s) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < 20; ++k) w.contact_stress(s);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / 20;
  };
  const double t1 = time(one, s1), t2 = time(two, s2);
  double trace = 0;
  for (std::size_t i = 0; i < P.size(); ++i) trace += s1[6 * i] + s1[6 * i + 1] + s1[6 * i + 2];
  std::printf("%zu touching pairs: trace sum %.6e N m (Hertz %.6e); pass %.2f ms on 1 thread, %.2f ms on 2\n",
              touching, trace, expected, 1e3 * t1, 1e3 * t2);
  EXPECT_NEAR(trace, expected, 1e-6 * std::abs(expected));
  ASSERT_EQ(s1.size(), s2.size());
  EXPECT_EQ(std::memcmp(s1.data(), s2.data(), s1.size() * sizeof(double)), 0);
}
