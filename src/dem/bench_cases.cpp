// The DEM benchmark's peer cases (bench_cases.hpp); numbers from the inputs in ../shared/peers/.
#include "dem/bench_cases.hpp"

#include <cmath>

namespace dem::bench {

MaterialTable peer_rock() {
  MaterialTable t;
  Material rock{"rock", 2600.0, 1.3716e9 / (2 * 1.35), 0.35};
  t.add(rock);
  t.set_pair(0, 0, 0.5, 0.15, 0.001);
  return t;
}

WorldParams peer_params(double dt, int threads) {
  WorldParams wp;
  wp.dt = dt;
  wp.threads = threads;
  wp.gravity = {{0, 0, -9.81}};
  wp.materials = peer_rock();
  return wp;
}

FccBlock fcc_block(double a, const double lo[3], const double hi[3]) {
  FccBlock b;
  b.a = a;
  const double h = 0.5 * a;
  for (int d = 0; d < 3; ++d) {
    b.k_lo[d] = static_cast<int>(std::ceil(lo[d] / h));
    b.k_hi[d] = static_cast<int>(std::floor(hi[d] / h));
  }
  return b;
}

std::size_t add_fcc_spheres(World& w, const FccBlock& b, double r) {
  const double h = 0.5 * b.a;
  std::size_t n = 0;
  for (int kz = b.k_lo[2]; kz <= b.k_hi[2]; ++kz)
    for (int ky = b.k_lo[1]; ky <= b.k_hi[1]; ++ky)
      for (int kx = b.k_lo[0]; kx <= b.k_hi[0]; ++kx) {
        if ((kx + ky + kz) % 2) continue;
        const double x[3] = {kx * h, ky * h, kz * h};
        w.add_particle(x, r, 0);
        ++n;
      }
  return n;
}

void build_granular_fcc(World& w) {
  const double lo[3] = {0, 0, 0}, hi[3] = {0.06, 0.06, 0.30};
  w.add_box(lo, hi, 0, false);  // zplane 0, x and y planes at 0 and 0.06
  // LIGGGHTS 'lattice fcc 0.00424264' + 'create_atoms' in the block [2, 58] x [2, 58] x [2, 290] mm:
  // points k * a/2 with k_x + k_y + k_z even
  const double h = 0.5 * 0.00424264;
  w.particles().reserve(50000);
  for (int kz = 0; kz * h < 0.29; ++kz)
    for (int ky = 0; ky * h < 0.058; ++ky)
      for (int kx = 0; kx * h < 0.058; ++kx) {
        if ((kx + ky + kz) % 2) continue;
        const double x[3] = {kx * h, ky * h, kz * h};
        if (x[0] < 0.002 || x[1] < 0.002 || x[2] < 0.002) continue;
        w.add_particle(x, 0.0015, 0);
      }
}

FccBlock granular_pressed_block() {
  const double lo[3] = {0.002, 0.002, 0.002}, hi[3] = {0.058, 0.058, 0.29};  // 'region fill block'
  return fcc_block(kPressedLattice, lo, hi);
}

void granular_pressed_walls(World& w) {
  const double lo[3] = {kPressedWallLo, kPressedWallLo, kPressedWallLo};
  const double hi[3] = {kPressedWallHiXY, kPressedWallHiXY, kPressedWallHiZ};
  w.add_box(lo, hi, 0, true);  // the peer's xw1, xw2, yw1, yw2, zw1, zw2
}

void build_granular_pressed(World& w) {
  granular_pressed_walls(w);
  w.particles().reserve(50000);
  add_fcc_spheres(w, granular_pressed_block(), 0.0015);  // 'diameter 0.003'
}

void bonded_hex_walls(World& w) {
  const double o[3] = {0, 0, 0}, up[3] = {0, 0, 1};
  w.add_plane(o, up, 0);
}

void build_bonded_hex(World& w) {
  const double r = 0.0015, a = 2 * r, hy = a * std::sqrt(3.0) / 2, hz = a * std::sqrt(6.0) / 3;
  const double mn[3] = {0, 0, 0.0015}, mx[3] = {0.05, 0.05, 0.05};
  // Yade pack.regularHexa(inAlignedBox(mn, mx), radius=r, gap=0)
  for (int i = 0; i <= static_cast<int>((mx[0] - mn[0]) / a); ++i)
    for (int j = 0; j <= static_cast<int>((mx[1] - mn[1]) / hy); ++j)
      for (int k = 0; k <= static_cast<int>((mx[2] - mn[2]) / hz); ++k) {
        double x = mn[0] + r + i * a, y = mn[1] + r + j * hy, z = mn[2] + r + k * hz;
        if (j % 2 == 0) x += (k % 2 == 0) ? a / 2 : -a / 2;
        if (k % 2 != 0) {
          x += a / 2;
          y += hy / 2;
        }
        const double p[3] = {x, y, z};
        bool in = true;
        for (int d = 0; d < 3; ++d) in = in && p[d] - r >= mn[d] && p[d] + r <= mx[d];
        if (in) w.add_particle(p, r, 0);
      }
  bonded_hex_walls(w);
  BondParams bp;
  const double A = M_PI * r * r, E = 1.3716e9;
  bp.kn = E * r / A;     // Yade: k_n = 2 E R1 R2 / (R1 + R2) = E R
  bp.kt = 0.35 * bp.kn;  // Yade: k_s = nu k_n
  bp.sigma_c = 25e6;
  bp.tau_c = 9e6;
  bp.radius_multiplier = 1.0;
  w.bond_within(0.2 * 2 * r, bp);  // interactionDetectionFactor 1.2
}

}  // namespace dem::bench
