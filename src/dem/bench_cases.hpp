#pragma once
// The DEM benchmark's peer cases (../shared/peers/): the same particles, walls and materials as the peers'
// inputs, built into a dem::World. Used by dem_bench and by the tests that check a case matches its peer.
#include <array>

#include "dem/world.hpp"

namespace dem::bench {

// The peers' rock: rho 2600, E 1.3716 GPa, nu 0.35 (G = E / 2(1 + nu)), e 0.15, mu 0.5, mu_r 0.001 (CDT).
MaterialTable peer_rock();
// The peers' physics: that rock, gravity 9.81 down z, the given step and thread count.
WorldParams peer_params(double dt, int threads);

// LIGGGHTS 'lattice fcc a' + 'create_atoms' in the region block [lo, hi] (bounds included): the sites k a/2 with
// k_x + k_y + k_z even, per axis k in [k_lo, k_hi] = [ceil(2 lo / a), floor(2 hi / a)].
struct FccBlock {
  double a = 0;                      // lattice constant (m)
  std::array<int, 3> k_lo{}, k_hi{};  // site index range per axis, in units of a/2
};
FccBlock fcc_block(double a, const double lo[3], const double hi[3]);
// Adds one sphere of radius r (material 0) per site, z outermost, then y, then x; returns the count.
std::size_t add_fcc_spheres(World& w, const FccBlock& b, double r);

// granular_fcc (liggghts_granular_fcc.in): 3 mm spheres on the fcc lattice 4.24264 mm (touching, no overlap) in
// [2, 58] x [2, 58] x [2, 290] mm, box 60 x 60 x 300 mm without a lid; 49,572 spheres.
void build_granular_fcc(World& w);

// granular_pressed (liggghts_granular_pressed.in): the same block on the pressed lattice 4.22991208 mm
// (nearest neighbours 2.990982 mm apart: 9 um overlap), 49,936 spheres, held by six planes at the peer's
// positions, each overlapping the outer spheres by 9 um.
constexpr double kPressedLattice = 0.00422991208;  // m, liggghts_granular_pressed.in 'lattice fcc'
constexpr double kPressedWallLo = 0.000623956;      // m, the x, y and z planes' lower position
constexpr double kPressedWallHiXY = 0.058594813;    // m, upper x and y planes
constexpr double kPressedWallHiZ = 0.291239977;     // m, upper z plane
FccBlock granular_pressed_block();
void build_granular_pressed(World& w);
void granular_pressed_walls(World& w);  // its six planes alone (a checkpoint's loader adds them)

// bonded_hex (yade_bonded_hex.py): 1.5 mm spheres in Yade's regularHexa packing of a 50 mm cube on a floor, every
// pair within 1.2 (r_i + r_j) bonded, strengths 25 / 9 MPa, bond stiffness as Yade's CohFrictPhys.
void build_bonded_hex(World& w);
void bonded_hex_walls(World& w);  // its floor alone

}  // namespace dem::bench
