// DEM benchmark: the two peer cases of ../shared/peers/ with the same physics, timed in this engine.
//   granular_fcc: LIGGGHTS case, 49,572 touching 3 mm spheres (fcc, lattice 4.24264 mm) in a 60x60x300 mm box
//                 with 5 planar walls, Hertz-Mindlin + history + CDT rolling friction, E 1.3716 GPa, nu 0.35,
//                 e 0.15, mu 0.5, mu_r 0.001, rho 2600, dt 1e-6 s, gravity; 1000 warm-up + 5000 timed steps.
//   bonded_hex:   Yade case, 1.5 mm spheres in Yade's regularHexa packing of a 50 mm cube, every pair within
//                 1.2 x (r_i + r_j) bonded (Yade's interactionDetectionFactor 1.2), strengths 25 / 9 MPa,
//                 bond stiffness matched to Yade's CohFrictPhys (k_n = E R, k_s = nu k_n over A = pi R^2),
//                 floor plane, gravity, dt 1e-7 s; 200 warm-up + 2000 timed steps.
// Usage: dem_bench [--case granular_fcc|bonded_hex|all] [--steps S] [--threads T] [--warmup W]
// (--warmup overrides the peers' warm-up step counts, for profiling only)
#include <omp.h>

#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <stdexcept>
#include <string>

#include "core/cli_args.hpp"
#include "dem/world.hpp"

namespace {

dem::MaterialTable peer_rock() {
  dem::MaterialTable t;
  dem::Material rock{"rock", 2600.0, 1.3716e9 / (2 * 1.35), 0.35};
  t.add(rock);
  t.set_pair(0, 0, 0.5, 0.15, 0.001);
  return t;
}

void report(const char* name, const dem::World& w, long steps, double wall) {
  const double n = static_cast<double>(w.particles().size());
  std::printf(
      "case %s particles %zu steps %ld threads %d wall_s %.3f particle_steps_per_s %.4g bytes_per_particle %.0f "
      "bytes_per_bond %.0f\n",
      name, w.particles().size(), steps, w.threads(), wall, n * steps / wall, w.bytes_per_particle(),
      w.bytes_per_bond());
  std::fflush(stdout);
  const auto& ph = w.phase_seconds();
  std::fprintf(stderr,
               "%s phases (s, warm-up included): drift %.3f rebuild %.3f (%ld) pairs %.3f bonds %.3f gather %.3f "
               "interactions %.3f kick %.3f; %zu neighbour pairs, %zu contacts\n",
               name, ph[0], ph[1], w.n_rebuilds(), ph[2], ph[3], ph[4], ph[5], ph[6], w.n_pairs(), w.n_contacts());
}

double cpu_seconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

// Wall seconds of the timed steps; the process CPU seconds go to stderr (on a shared, loaded machine
// particle-steps per CPU-second x threads is the steadier figure).
double timed(dem::World& w, long steps) {
  const double c0 = cpu_seconds();
  const auto t0 = std::chrono::steady_clock::now();
  w.step(steps);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double cpu = cpu_seconds() - c0;
  std::fprintf(stderr, "timed steps: wall %.3f s, process CPU %.3f s, particle-steps per CPU-second %.4g\n", wall,
               cpu, static_cast<double>(w.particles().size()) * steps / cpu);
  return wall;
}

// The peers' physics: rock of ../shared/peers, gravity, the given step and thread count.
dem::WorldParams peer_params(double dt, int threads) {
  dem::WorldParams wp;
  wp.dt = dt;
  wp.threads = threads;
  wp.gravity = {{0, 0, -9.81}};
  wp.materials = peer_rock();
  return wp;
}

void granular_fcc(long steps, int threads, long warmup) {
  dem::WorldParams wp = peer_params(1e-6, threads);
  wp.skin = 0.3e-3;
  dem::World w(wp);
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
  w.step(warmup >= 0 ? warmup : 1000);  // warm-up, as the peer's first 'run 1000'
  const double wall = timed(w, steps);
  report("granular_fcc", w, steps, wall);
}

void bonded_hex(long steps, int threads, long warmup) {
  dem::World w(peer_params(1e-7, threads));
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
  const double o[3] = {0, 0, 0}, up[3] = {0, 0, 1};
  w.add_plane(o, up, 0);
  dem::BondParams bp;
  const double A = M_PI * r * r, E = 1.3716e9;
  bp.kn = E * r / A;        // Yade: k_n = 2 E R1 R2 / (R1 + R2) = E R
  bp.kt = 0.35 * bp.kn;     // Yade: k_s = nu k_n
  bp.sigma_c = 25e6;
  bp.tau_c = 9e6;
  bp.radius_multiplier = 1.0;
  w.bond_within(0.2 * 2 * r, bp);  // interactionDetectionFactor 1.2
  w.step(warmup >= 0 ? warmup : 200);
  const double wall = timed(w, steps);
  report("bonded_hex", w, steps, wall);
  std::fprintf(stderr, "bonded_hex: %zu intact bonds (%.2f per particle), %zu broken\n", w.n_bonds_intact(),
               2.0 * w.n_bonds_intact() / w.particles().size(), w.breaks().size());
}

}  // namespace

int main(int argc, char** argv) {
  std::string which = "all";
  long steps = -1;
  int threads = 0;
  long warmup = -1;
  try {
    for (int k = 1; k < argc; ++k) {
      const std::string a = argv[k];
      auto next = [&]() -> std::string {
        if (k + 1 >= argc) throw std::invalid_argument("option " + a + " needs a value");
        return argv[++k];
      };
      if (a == "--case") {
        which = next();
        if (which != "granular_fcc" && which != "bonded_hex" && which != "all")
          throw std::invalid_argument("--case accepts granular_fcc, bonded_hex or all, got '" + which + "'");
      } else if (a == "--steps") {
        steps = core::parse_integer(a, next(), 1, 1000000000);
      } else if (a == "--threads") {
        threads = static_cast<int>(core::parse_integer(a, next(), 1, 1024));
      } else if (a == "--warmup") {
        warmup = core::parse_integer(a, next(), 0, 1000000000);
      } else if (a == "-h" || a == "--help") {
        std::cout << "usage: dem_bench [--case granular_fcc|bonded_hex|all] [--steps S] [--threads T]\n";
        return 0;
      } else {
        throw std::invalid_argument("unknown option '" + a + "' (accepted: --case, --steps, --threads, --warmup)");
      }
    }
    if (threads == 0) threads = omp_get_max_threads();
    if (which == "granular_fcc" || which == "all") granular_fcc(steps > 0 ? steps : 5000, threads, warmup);
    if (which == "bonded_hex" || which == "all") bonded_hex(steps > 0 ? steps : 2000, threads, warmup);
  } catch (const std::exception& e) {
    std::cerr << "dem_bench: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
