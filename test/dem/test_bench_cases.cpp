// The benchmark's granular_pressed case against its peer (../shared/peers/liggghts_granular_pressed.in): the
// lattice, walls and overlaps, and the contact count at step 0 (LIGGGHTS: 283,556 pair contacts), derived in
// closed form from the fcc block and counted by the engine.
#include <gtest/gtest.h>

#include <cmath>

#include "dem/bench_cases.hpp"

namespace {

using Range = std::array<std::array<int, 2>, 3>;  // per axis [k_lo, k_hi]

// Sites (k_x, k_y, k_z) of the box with k_x + k_y + k_z even: (N + S_x S_y S_z) / 2, where S_d = sum of (-1)^k over
// the axis' range is (-1)^k_lo for an odd number of values and 0 for an even one.
long even_sites(const Range& b) {
  long n = 1, s = 1;
  for (const auto& r : b) {
    const long len = r[1] - r[0] + 1;
    if (len <= 0) return 0;
    n *= len;
    s *= len % 2 ? (r[0] % 2 ? -1 : 1) : 0;
  }
  return (n + s) / 2;
}

Range range_of(const dem::bench::FccBlock& b) {
  Range r;
  for (int d = 0; d < 3; ++d) r[d] = {b.k_lo[d], b.k_hi[d]};
  return r;
}

// Nearest-neighbour pairs of the fcc block: the 6 bond directions (+-1, +-1, 0) and permutations, up to sign; a
// pair along d is a site i with i + d in the block too (i + d has the same parity as i).
long nearest_pairs(const Range& b) {
  const int dirs[6][3] = {{1, 1, 0}, {1, -1, 0}, {1, 0, 1}, {1, 0, -1}, {0, 1, 1}, {0, 1, -1}};
  long n = 0;
  for (const auto& d : dirs) {
    Range s = b;
    for (int a = 0; a < 3; ++a) {
      if (d[a] > 0) s[a][1] -= 1;
      if (d[a] < 0) s[a][0] += 1;
    }
    n += even_sites(s);
  }
  return n;
}

// Sites on the six faces of the block (a site on an edge touches two walls, a corner three).
long face_sites(const Range& b) {
  long n = 0;
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      Range s = b;
      s[a] = {b[a][side], b[a][side]};
      n += even_sites(s);
    }
  return n;
}

TEST(BenchCases, ClosedFormCountsMatchBruteForceOnASmallBlock) {
  Range b{{{1, 4}, {2, 6}, {3, 5}}};
  long sites = 0, pairs = 0, faces = 0;
  for (int x = 1; x <= 4; ++x)
    for (int y = 2; y <= 6; ++y)
      for (int z = 3; z <= 5; ++z) {
        if ((x + y + z) % 2) continue;
        ++sites;
        faces += (x == 1) + (x == 4) + (y == 2) + (y == 6) + (z == 3) + (z == 5);
        for (int dx = -1; dx <= 1; ++dx)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dz = -1; dz <= 1; ++dz) {
              const int nx = x + dx, ny = y + dy, nz = z + dz;
              if (std::abs(dx) + std::abs(dy) + std::abs(dz) != 2) continue;
              if (nx >= 1 && nx <= 4 && ny >= 2 && ny <= 6 && nz >= 3 && nz <= 5) ++pairs;
            }
      }
  EXPECT_EQ(even_sites(b), sites);
  EXPECT_EQ(nearest_pairs(b), pairs / 2);
  EXPECT_EQ(face_sites(b), faces);
}

// The pressed lattice and walls as liggghts_granular_pressed.in states them: nearest neighbours and the walls
// overlap the 1.5 mm spheres by 9 um; the second-nearest neighbours (a apart) and the second layer from each wall
// do not touch, so the contacts are exactly the nearest-neighbour pairs and the outer sites' wall contacts.
TEST(BenchCases, GranularPressedGeometryIsThePeers) {
  namespace B = dem::bench;
  const double r = 0.0015, a = B::kPressedLattice, h = a / 2;
  EXPECT_NEAR(2 * r - a / std::sqrt(2.0), 9.0e-6, 0.05e-6);
  EXPECT_GT(a, 2 * r);
  const auto blk = B::granular_pressed_block();
  const double wall_lo = B::kPressedWallLo;
  const double wall_hi[3] = {B::kPressedWallHiXY, B::kPressedWallHiXY, B::kPressedWallHiZ};
  for (int d = 0; d < 3; ++d) {
    EXPECT_NEAR(r - (blk.k_lo[d] * h - wall_lo), 9.0e-6, 0.05e-6) << "axis " << d;
    EXPECT_NEAR(r - (wall_hi[d] - blk.k_hi[d] * h), 9.0e-6, 0.05e-6) << "axis " << d;
    EXPECT_GT((blk.k_lo[d] + 1) * h - wall_lo, r);
    EXPECT_GT(wall_hi[d] - (blk.k_hi[d] - 1) * h, r);
  }
  const Range b = range_of(blk);
  EXPECT_EQ(even_sites(b), 49936);       // ../shared/peers/README.md
  EXPECT_EQ(nearest_pairs(b), 283556);   // LIGGGHTS' c_cnsum / 2 at step 0 (issue 25)
  EXPECT_EQ(face_sites(b), 8124);
}

// The engine, built by the benchmark's own code, finds exactly those contacts at step 0 (a new particle has no
// force in its first step, so step 1 evaluates the contacts at the lattice positions).
TEST(BenchCases, GranularPressedContactCountAtStepZeroIsThePeers) {
  namespace B = dem::bench;
  dem::WorldParams wp = B::peer_params(1e-6, 2);
  wp.skin = 0.3e-3;
  dem::World w(wp);
  B::build_granular_pressed(w);
  const Range b = range_of(B::granular_pressed_block());
  ASSERT_EQ(static_cast<long>(w.particles().size()), even_sites(b));
  w.step(1);
  EXPECT_EQ(static_cast<long>(w.n_contacts()), nearest_pairs(b));
  EXPECT_EQ(w.n_contacts(), 283556u);
  EXPECT_EQ(static_cast<long>(w.n_wall_contacts()), face_sites(b));
  EXPECT_EQ(w.n_pairs(), w.n_contacts());  // skin 0.3 mm < a - 2 r: only nearest neighbours are listed
}

}  // namespace
