// MPI benchmark of the DEM engine across processes (issue 25, parallel/mpi_domain.hpp): a peer case of dem_bench
// (granular_pressed: 49,936 pressed spheres, 283,556 contacts; bonded_hex: 1.5 mm spheres all bonded), built and
// warmed up on rank 0 in one World, saved, cut into equal-count azimuthal sectors about the z axis (both blocks lie in
// x, y > 0: the axis runs along their corner, so the wedges split the block along vertical planes through it), and
// timed over --steps steps with the ghost exchange. Run it under mpirun; with one rank it times the same World
// without an exchange, so `-np 1 --threads 2` and `-np 2 --threads 1` compare processes with threads on two cores.
// --case crusher --config FILE: the coupled run's DEM chamber (coupling::ChamberDem) of a run config, pre-filled and
// gyrating as dem_bench's crusher case, on P ranks (ChamberDem::decompose over parallel::MpiEngine, as dem_node
// --ranks runs it; one rank: the whole World); --steps coupling steps (default 2) after --warmup (default 1, the
// pre-fill's); rank 0 prints the wall time per simulated second.
// Usage: mpirun -np P dem_mpi_bench [--case granular_pressed|bonded_hex|crusher] [--config FILE] [--steps S]
//                                   [--warmup W] [--threads T] [--rebalance-tolerance X]
// --rebalance-tolerance: the sectors' imbalance over which a spent margin cuts the charge anew through rank 0 instead
// of migrating (default 0.05; -1: always through rank 0, as before migrations).
// Prints one line per rank on stderr (owned, ghosts, wall, exchange, re-cut and migration seconds) and rank 0's case
// line on stdout: particle-steps per second of the whole charge, the exchange's share of the slowest rank's wall time.
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/binary_io.hpp"
#include "core/cli_args.hpp"
#include "core/heap_policy.hpp"
#include "dem/bench_cases.hpp"
#include "dem/world.hpp"
#include "core/config.hpp"
#include "core/run_config.hpp"
#include "coupling/chamber_dem.hpp"
#include "mbd/mechanism_params.hpp"
#include "parallel/mpi_domain.hpp"
#include "parallel/mpi_engine.hpp"
#include "tools/crusher_gyration.hpp"

namespace {

struct Case {
  double dt, skin, reach;
  long warmup;
  void (*build)(dem::World&);
  void (*walls)(dem::World&);
};

Case case_named(const std::string& name) {
  // reach: the largest contact (2 r = 3 mm) or bond (1.2 x 2 r) distance plus room to move before a re-cut
  if (name == "granular_pressed")
    return {1e-6, 0.3e-3, 3.6e-3, 1000, dem::bench::build_granular_pressed, dem::bench::granular_pressed_walls};
  if (name == "bonded_hex")
    return {1e-7, -1, 4.2e-3, 200, dem::bench::build_bonded_hex, dem::bench::bonded_hex_walls};
  throw std::invalid_argument("--case " + name + ": accepted granular_pressed, bonded_hex, crusher");
}

int crusher(const std::string& config, long steps, long warmup, int threads, double tolerance) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (config.empty()) throw std::invalid_argument("--case crusher needs --config FILE (a coupled run's config)");
  auto root = core::ConfigNode::load_file(config);
  const double dtc = core::load_coupling_options(root.child_or_empty("coupling")).dt_s;
  const auto mech = mbd::load_mechanism_params(root.child("mbd"));
  const auto flow = root.child_or_empty("flow");
  auto cp = coupling::load_chamber_params(root.child("dem"), mech.chamber, mech.floating_cone.com_z_m,
                                          mech.fixed_cone.com_z_m, &flow);
  cp.threads = threads;
  tools::Gyration g;
  g.theta = 0.73 * M_PI / 180;  // dem_bench's default
  g.omega = mech.drive_speed_rad_s;
  g.mantle_com_z = mech.floating_cone.com_z_m;
  g.concave_com_z = mech.fixed_cone.com_z_m;
  coupling::ChamberDem dem(cp);
  if (size > 1) dem.decompose(parallel::mpi_engine(MPI_COMM_WORLD, 3.0 * dem.largest_sphere_radius(), tolerance));
  long k = 0;
  for (; k < std::max(1L, warmup); ++k) dem.advance(g.mantle(k * dtc), g.concave(), dtc);  // the first pre-fills
  MPI_Barrier(MPI_COMM_WORLD);
  const auto ph0 = dem.phase_seconds();
  const auto t0 = std::chrono::steady_clock::now();
  for (const long e = k + steps; k < e; ++k) dem.advance(g.mantle(k * dtc), g.concave(), dtc);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto ph = dem.phase_seconds();
  std::vector<uint64_t> ids;
  std::vector<double> state;
  dem.owned_state(ids, state);
  unsigned long long mine = ids.size(), all = 0;
  MPI_Reduce(&mine, &all, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, 0, MPI_COMM_WORLD);
  double slowest = 0;
  MPI_Reduce(&wall, &slowest, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
  const auto* own = dem.engine().owned(0);  // null: one World, no ghosts
  const std::size_t ghosts = own ? std::count(own->begin(), own->end(), 0) : 0;
  const auto* mpi = dynamic_cast<const parallel::MpiEngine*>(&dem.engine());
  std::fprintf(stderr,
               "rank %d of %d: owned %llu ghosts %zu wall_s %.3f steps_s %.2f crushing_s %.2f bookkeeping_s %.2f "
               "recuts %d recut_s %.2f migrations %d migrate_s %.2f\n",
               rank, size, mine, ghosts, wall, ph[0] - ph0[0], ph[3] - ph0[3], ph[4] - ph0[4], dem.engine().recuts(),
               mpi ? mpi->domain().recut_seconds() : 0.0, dem.engine().migrations(),
               mpi ? mpi->domain().migrate_seconds() : 0.0);
  if (rank == 0) {
    std::printf("case crusher ranks %d threads %d particles %llu coupling_steps %ld wall_s %.3f wall_h_per_sim_s %.2f "
                "recuts %d migrations %d\n", size, threads, all, steps, slowest, slowest / (steps * dtc) / 3600.0,
                size > 1 ? dem.engine().recuts() : 0, size > 1 ? dem.engine().migrations() : 0);
    std::fflush(stdout);
  }
  return 0;
}

int run(int argc, char** argv) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  std::string name = "granular_pressed", config;
  long steps = -1, warmup = -1;
  int threads = 1;
  double tolerance = dem::kRebalanceTolerance;
  for (core::CliArgs a(argc, argv); a.next();) {
    const std::string f = a.flag();
    if (f == "--case") name = a.value();
    else if (f == "--steps") steps = a.integer(1, 100000000);
    else if (f == "--warmup") warmup = a.integer(0, 100000000);
    else if (f == "--threads") threads = static_cast<int>(a.integer(1, 1024));
    else if (f == "--config") config = a.value();
    else if (f == "--rebalance-tolerance") tolerance = a.number(-1.0, 1e9);
    else throw std::invalid_argument("unknown option " + f +
                                     " (accepted: --case, --config, --steps, --warmup, --threads, --rebalance-tolerance)");
  }
  if (name == "crusher") return crusher(config, steps > 0 ? steps : 2, warmup >= 0 ? warmup : 1, threads, tolerance);
  if (steps < 0) steps = 2000;
  const Case c = case_named(name);
  if (warmup < 0) warmup = c.warmup;
  dem::WorldParams wp = dem::bench::peer_params(c.dt, threads);
  wp.skin = c.skin;
  std::string ckpt;
  if (rank == 0) {
    dem::World w(wp);
    c.build(w);
    w.step(warmup);
    std::ostringstream os;
    core::BinaryWriter bw(os);
    w.save_state(bw);
    ckpt = os.str();
  }
  ckpt = parallel::broadcast_bytes(MPI_COMM_WORLD, ckpt);
  parallel::MpiDomain d(MPI_COMM_WORLD, ckpt, wp, c.walls, c.reach);
  d.set_rebalance_tolerance(tolerance);
  MPI_Barrier(MPI_COMM_WORLD);
  const auto t0 = std::chrono::steady_clock::now();
  d.step(steps);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::size_t owned = 0;
  for (char o : d.plan().owned) owned += o ? 1 : 0;
  std::fprintf(stderr,
               "rank %d of %d: owned %zu ghosts %zu neighbour_pairs %zu bonds %zu wall_s %.3f exchange_s %.3f recuts %d "
               "recut_s %.3f migrations %d migrate_s %.3f\n",
               rank, size, owned, d.ghosts(), d.world().n_pairs(), d.world().n_bonds_intact(), wall, d.exchange_seconds(),
               d.recuts(), d.recut_seconds(), d.migrations(), d.migrate_seconds());
  double slowest = 0, exch = 0;
  MPI_Reduce(&wall, &slowest, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
  const double mine = d.exchange_seconds();
  MPI_Reduce(&mine, &exch, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
  unsigned long long n_own = owned, n_all = 0, g = d.ghosts(), g_max = 0;
  MPI_Reduce(&n_own, &n_all, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, 0, MPI_COMM_WORLD);
  MPI_Reduce(&g, &g_max, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, 0, MPI_COMM_WORLD);
  if (rank == 0) {
    std::printf("case %s ranks %d threads %d particles %llu steps %ld wall_s %.3f particle_steps_per_s %.4g "
                "exchange_share %.3f ghosts_max %llu\n",
                name.c_str(), size, threads, n_all, steps, slowest, static_cast<double>(n_all) * steps / slowest,
                exch / slowest, g_max);
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  core::keep_freed_heap();  // as dem_node
  MPI_Init(&argc, &argv);
  int rc = 0;
  try {
    rc = run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dem_mpi_bench: %s\n", e.what());
    MPI_Abort(MPI_COMM_WORLD, 2);
  }
  MPI_Finalize();
  return rc;
}
