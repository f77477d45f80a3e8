// Cost model of an azimuthally decomposed DEM run (cost_model.hpp; src/dem/README.md "Cost model").
#include "dem/cost_model.hpp"

#include <cmath>
#include <stdexcept>

namespace dem {

CostModelRow cost_model(const CostModelInputs& in, int ranks) {
  if (ranks < 1) throw std::invalid_argument("cost_model: ranks must be >= 1");
  if (!(in.particles > 0) || !(in.dt_s > 0) || !(in.core_s_per_particle_step > 0) || !(in.mean_radius_m > 0) ||
      !(in.bandwidth_B_s > 0) || in.ghost_width_m < 0 || in.latency_s < 0 || in.serial_s_per_step < 0 ||
      !(in.ghost_factor > 0) || !(in.ghost_work >= 0))
    throw std::invalid_argument("cost_model: particles, dt, per-particle cost, mean radius, bandwidth and ghost factor "
                                "must be > 0, ghost width, ghost work, latency and serial time >= 0");
  CostModelRow r;
  r.ranks = ranks;
  const double P = ranks;
  r.compute_s = in.particles * in.core_s_per_particle_step / P;
  r.serial_s = in.serial_s_per_step;
  if (ranks > 1) {
    r.ghosts_per_boundary = in.particles * in.ghost_width_m / (2 * M_PI * in.mean_radius_m) * in.ghost_factor;
    r.compute_s += 2 * r.ghosts_per_boundary * in.ghost_work * in.core_s_per_particle_step;  // pairs across, twice
    r.comm_s = 4 * in.latency_s + 2 * r.ghosts_per_boundary * (in.bytes_forward + in.bytes_reverse) / in.bandwidth_B_s;
    r.comm_s += 2 * std::ceil(std::log2(P)) * in.latency_s / std::max(1.0, in.steps_per_coupling);
    r.sectors_too_thin = 2 * M_PI * in.mean_radius_m / P < 2 * in.ghost_width_m;
  }
  const double t = r.compute_s + r.serial_s + r.comm_s;
  r.wall_h_per_sim_s = t / in.dt_s / 3600.0;
  const double t1 = in.particles * in.core_s_per_particle_step + in.serial_s_per_step;
  r.efficiency = t1 / (P * t);
  return r;
}

}  // namespace dem
