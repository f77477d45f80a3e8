#pragma once
// A cost model for a DEM run split over P ranks in azimuthal sectors of an annular charge (the crusher chamber), as
// the MPI engine does it (parallel/mpi_domain.hpp): the per-particle cost is measured (dem_bench --case crusher), the
// communication cost is modelled from a stated network. Formula and inputs: src/dem/README.md, "Cost model".
//
// Per DEM step on P ranks (one core each):
//   t_step(P) = (N / P + 2 N_g g_w) c + t_serial + t_comm(P)   (P > 1: a rank computes the pairs and bonds that cross
//               its two boundaries too, g_w of a particle's work per ghost, measured: dem_mpi_bench)
//   t_comm(P) = 4 L + 2 N_g (b_fwd + b_rev) / B   (P > 1; x, v, w to and from the two neighbour sectors)
//   N_g       = N w / (2 pi r_m) x ghost_factor  ghost particles per sector boundary (charge uniform in azimuth;
//                                                 ghost_factor: measured on the real charge over that)
//   + one allreduce of the liner wrenches per coupling step: 2 ceil(log2 P) L / steps_per_coupling
// and the wall time per simulated second is t_step / dt. A sector narrower than 2 w (P > pi r_m / w) leaves no
// interior: the model marks those rows (a 2D decomposition, azimuth x height, would be needed there).
#include <string>
#include <vector>

namespace dem {

struct CostModelInputs {
  double particles = 0;             // N
  double dt_s = 0;                  // DEM step
  double core_s_per_particle_step = 0;  // c: measured, (wall s x threads) / (N x steps) of the parallel phases
  double serial_s_per_step = 0;     // t_serial: measured, the chamber-level work one rank does (fines, crushing, ...)
  double ghost_width_m = 0;         // w: interaction range across a boundary (largest diameter + skin)
  double mean_radius_m = 0;         // r_m: the charge's mean radius about the axis
  double bytes_forward = 72;        // per ghost and step: x, v, w (9 doubles)
  double bytes_reverse = 0;         // per ghost and step sent back: none, a pair across a boundary is computed on
                                    // both ranks (a scheme with forces sent back, f and t: 48, and no ghost stepping)
  double bandwidth_B_s = 1.25e9;    // B
  double latency_s = 20e-6;         // L, per message
  double steps_per_coupling = 1;    // DEM steps per coupling step (the wrench allreduce)
  // Measured ghosts over the uniform formula's N_g (dem_bench: the most loaded rank of the charge's own balanced
  // wedges, sector_decomposition.hpp); 1: the formula as it is.
  double ghost_factor = 1;
  // g_w: a ghost's work over an owned particle's (the World leaves out pairs and bonds of two ghosts, so a ghost
  // costs its pairs and bonds across the boundary, computed on both ranks). Measured with dem_mpi_bench on 2 ranks:
  // granular_pressed 0.23 (295,157 pairs against 283,556 in one World, 4,412 ghosts a rank), bonded_hex 0.19 (bonds).
  double ghost_work = 0.25;
};

struct CostModelRow {
  int ranks = 1;
  double compute_s = 0, serial_s = 0, comm_s = 0;  // per DEM step
  double ghosts_per_boundary = 0;
  double wall_h_per_sim_s = 0;
  double efficiency = 1;  // t_step(1) / (P t_step(P))
  bool sectors_too_thin = false;
};

CostModelRow cost_model(const CostModelInputs& in, int ranks);

}  // namespace dem
