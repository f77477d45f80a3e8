// Loose pouring of bonded rocks into a container (see rock_pour.hpp).
#include "chamber/rock_pour.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "core/binary_io.hpp"
#include "dem/world.hpp"
#include "rocks/shape.hpp"

namespace chamber {
namespace {

constexpr int kRock = 0;  // dem::default_table4()

// One irregular rock packed with the BPM's metaparticles; like coupling::ChamberDem, a shape too small for the
// packing density steps it down by 0.03 (to 0.30 at least) rather than fail.
// A shape thinner than the largest metaparticle cannot be packed: such a seed is skipped for the next one.
rocks::RockPacking pack_rock(const rocks::BpmModel& bpm, unsigned long long seed, double size) {
  const double dmax = 2.0 * bpm.metaparticles.max_radius();
  std::unique_ptr<rocks::PolyhedronShape> shape;
  for (int t = 0;; ++t, seed += 1000003ULL) {
    shape = rocks::make_irregular_rock(seed, size, 22, "rock" + std::to_string(seed));
    if ((shape->max_corner() - shape->min_corner()).minCoeff() >= dmax) break;
    if (t == 50)
      throw std::invalid_argument("rock pour: rock size " + std::to_string(size * 1e3) +
                                  " mm is too small for the BPM's metaparticles (largest diameter " +
                                  std::to_string(dmax * 1e3) + " mm); accepted rock_min >= about 1.8 x that");
  }
  rocks::PackingOptions po = bpm.packing;
  po.seed = seed;
  for (;;) {
    try {
      return rocks::pack_shape(*shape, bpm.metaparticles, po);
    } catch (const std::runtime_error&) {
      if (po.density <= 0.3 + 1e-9) throw;
      po.density = std::max(0.3, po.density - 0.03);
    }
  }
}

Eigen::Quaterniond random_orientation(rocks::Rng& rng) {
  Eigen::Quaterniond q(rng.normal(), rng.normal(), rng.normal(), rng.normal());
  return q.normalized();
}

}  // namespace

std::vector<PouredRock> pour_rocks(const rocks::BpmModel& bpm, const PourSpec& spec, rocks::Rng& rng) {
  // ---- the feed: irregular rocks of log-uniform nominal size
  std::vector<PouredRock> feed;
  double rock_volume = 0.0;
  for (int k = 0;; ++k) {
    if (spec.rock_count > 0 ? k >= spec.rock_count : rock_volume >= spec.fill_volume) break;
    const double size = std::exp(std::log(spec.rock_min) + rng.uniform() * std::log(spec.rock_max / spec.rock_min));
    PouredRock fr;
    fr.pack = pack_rock(bpm, spec.seed * 7919ULL + 17ULL * k + 1ULL, size);
    // The rock weighs rho V of its envelope (the flow model's solid density), as feed.rock_density does.
    fr.sphere_density = spec.rock_density * fr.pack.container_volume / fr.pack.solid_volume();
    rock_volume += fr.pack.container_volume;
    feed.push_back(std::move(fr));
  }

  // ---- random sequential placement, each rock at the lowest free layer
  double rmax = 0.0;
  for (const auto& f : feed)
    for (double r : f.pack.radii) rmax = std::max(rmax, r);
  const double cell = 2.0 * rmax;
  auto key = [cell](const Eigen::Vector3d& x) {
    const long long i = static_cast<long long>(std::floor(x.x() / cell)) + (1 << 20);
    const long long j = static_cast<long long>(std::floor(x.y() / cell)) + (1 << 20);
    const long long l = static_cast<long long>(std::floor(x.z() / cell)) + (1 << 20);
    return (i << 42) | (j << 21) | l;
  };
  std::unordered_map<long long, std::vector<std::pair<Eigen::Vector3d, double>>> grid;
  auto clear = [&](const Eigen::Vector3d& x, double r) {
    if (x.z() < r + 1e-5 || !spec.inside(x, r)) return false;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = grid.find(key(x + Eigen::Vector3d(dx, dy, dz) * cell));
          if (it == grid.end()) continue;
          for (const auto& [y, ry] : it->second)
            if ((x - y).squaredNorm() < (r + ry) * (r + ry)) return false;
        }
    return true;
  };
  const double dz = 0.1 * spec.rock_min;
  double z_top = 0.0, z_layer0 = 0.0;
  for (std::size_t k = 0; k < feed.size(); ++k) {
    const auto& rk = feed[k].pack;
    bool done = false;
    for (double zc = z_layer0; !done; zc += dz) {
      if (zc > spec.max_height) throw std::runtime_error("rock pour: cannot place rock " + std::to_string(k));
      int misses = 0;
      for (int t = 0; t < 40 && !done; ++t) {
        const Eigen::Vector2d xy = spec.sample_xy(rng);
        const Eigen::Vector3d c(xy.x(), xy.y(), zc);
        const Eigen::Quaterniond q = random_orientation(rng);
        std::vector<Eigen::Vector3d> xs;
        bool ok = true;
        for (std::size_t i = 0; i < rk.size() && ok; ++i) {
          xs.push_back(c + q * rk.positions[i]);
          ok = clear(xs.back(), rk.radii[i]);
        }
        if (!ok) {
          ++misses;
          continue;
        }
        for (std::size_t i = 0; i < rk.size(); ++i) {
          grid[key(xs[i])].emplace_back(xs[i], rk.radii[i]);
          z_top = std::max(z_top, xs[i].z() + rk.radii[i]);
        }
        feed[k].x = std::move(xs);
        done = true;
      }
      // layers far below the current top stay full: start later rocks higher up
      if (!done && misses == 40 && zc + 2.0 * spec.rock_max < z_top) z_layer0 = std::max(z_layer0, zc);
    }
  }
  return feed;
}

double poured_top(const std::vector<PouredRock>& rocks) {
  double top = 0.0;
  for (const auto& r : rocks)
    for (std::size_t i = 0; i < r.x.size(); ++i) top = std::max(top, r.x[i].z() + r.pack.radii[i]);
  return top;
}

dem::WorldParams rock_world_params(int threads, double max_overlap_fraction, const std::string& blowup_dump_path) {
  dem::WorldParams wp;
  wp.threads = threads;
  wp.materials = dem::default_table4();
  wp.dt = 1e-7;  // set by fill_with_rocks from the particles and bonds
  wp.check_time_step = true;
  wp.max_overlap_fraction = max_overlap_fraction;
  wp.blowup_dump_path = blowup_dump_path;
  return wp;
}

FilledWorld fill_with_rocks(dem::World& w, const std::vector<PouredRock>& rocks, const rocks::BpmModel& bpm,
                            double dt_safety) {
  FilledWorld f;
  const dem::BondParams bp = bpm.bond.params();
  for (const auto& rk : rocks) {
    const std::size_t first = w.particles().size();
    for (std::size_t i = 0; i < rk.pack.size(); ++i) {
      const double x[3] = {rk.x[i].x(), rk.x[i].y(), rk.x[i].z()};
      w.add_particle(x, rk.pack.radii[i], kRock, rk.sphere_density, nullptr, nullptr);
    }
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    for (auto [i, j] : rk.pack.bonds) pairs.emplace_back(first + i, first + j);
    f.bonds += w.bond_pairs(pairs, bp);
  }
  f.particles = w.particles().size();
  const dem::TimeStepCheck c = w.time_step_check();
  f.dt = dt_safety * std::min(0.3 * c.rayleigh, c.bond);
  w.set_dt(f.dt);
  w.require_stable_time_step();
  for (std::size_t i = 0; i < w.particles().size(); ++i) f.mass += w.particles().m[i];
  return f;
}

double settle_world(dem::World& w, double mass, double t_min, double t_max, double speed) {
  const long chunk = std::max(1L, static_cast<long>(std::lround(2e-3 / w.dt())));
  for (;;) {
    w.step(chunk);
    const double v = std::sqrt(2.0 * w.kinetic_energy() / mass);
    if ((w.time() >= t_min && v < speed) || w.time() >= t_max) return v;
  }
}

std::string world_state_bytes(dem::World& w) {
  std::stringstream state;
  core::BinaryWriter bw(state);
  w.save_state(bw);
  return state.str();
}

void load_world_state(dem::World& w, const std::string& bytes, const char* what) {
  std::istringstream is(bytes);
  core::BinaryReader br(is, what);
  w.load_state(br);
}

double highest_top(const dem::World& w) {
  double top = -std::numeric_limits<double>::infinity();
  const auto& P = w.particles();
  for (std::size_t i = 0; i < P.size(); ++i) top = std::max(top, P.z[i] + P.r[i]);
  return top;
}

}  // namespace chamber
