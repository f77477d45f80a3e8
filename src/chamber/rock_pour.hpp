#pragma once
// Loose pouring of irregular bonded rocks (rocks::make_irregular_rock packed with the calibrated BPM's metaparticles,
// paper section 2.4.1) into a steel container on a floor at z = 0, shared by the virtual piston die (piston_die.hpp)
// and the gap slice (gap_slice.hpp): random sequential placement bottom-up without overlap, then settling under gravity.
#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "rocks/bpm_config.hpp"
#include "rocks/packing.hpp"
#include "rocks/rng.hpp"

#include "dem/world.hpp"

namespace chamber {

struct PouredRock {
  rocks::RockPacking pack;
  double sphere_density = 0.0;          // kg/m^3: the rock weighs rock_density x its envelope's volume
  std::vector<Eigen::Vector3d> x;       // placed sphere centres (m)
};

struct PourSpec {
  int rock_count = 0;                   // rocks; 0: as many as fill `fill_volume` of envelope volume
  double fill_volume = 0.0;             // m^3
  double rock_min = 0.0, rock_max = 0.0;  // m, nominal sizes (y extent), log-uniform
  double rock_density = 2600.0;         // kg/m^3
  unsigned long long seed = 1;
  // A trial centre's horizontal position; and whether a sphere (centre, radius) lies inside the container's sides.
  std::function<Eigen::Vector2d(rocks::Rng&)> sample_xy;
  std::function<bool(const Eigen::Vector3d&, double)> inside;
  double max_height = 1.0;              // m: a rock that finds no room below this height is an error
};

// The rocks' sizes, then their packings and places, drawn from `rng` in that order (the die's pourings depend on it).
// std::invalid_argument when a size is too small for the metaparticles; std::runtime_error when a rock finds no room.
std::vector<PouredRock> pour_rocks(const rocks::BpmModel& bpm, const PourSpec& spec, rocks::Rng& rng);
double poured_top(const std::vector<PouredRock>& rocks);  // m: the highest sphere's top
// The world's parameters for a pouring: Table 4's materials, the step set later by fill_with_rocks, the blow-up bound on
// overlap / smaller radius and the blow-up dump's file ("": an unguessable name in the temporary folder).
dem::WorldParams rock_world_params(int threads, double max_overlap_fraction, const std::string& blowup_dump_path);
struct FilledWorld {
  std::size_t particles = 0, bonds = 0;
  double dt = 0.0;    // s: dt_safety x min(0.3 Rayleigh step, bond step) (the platen tests' rule)
  double mass = 0.0;  // kg of rock
};
// Adds the rocks' spheres (rock material 0) and their bonds (the BPM's bond law) to a world that holds the container,
// and sets its step.
FilledWorld fill_with_rocks(dem::World& w, const std::vector<PouredRock>& rocks, const rocks::BpmModel& bpm,
                            double dt_safety);
// Steps the world in chunks of ~2 ms until, from the time t_min on, the rms speed sqrt(2 KE / mass) is below `speed`,
// or until the time t_max; returns that rms speed.
double settle_world(dem::World& w, double mass, double t_min, double t_max, double speed);
// The world's checkpoint (dem::World::save_state) as bytes: a settled or pressed bed that copies are loaded from.
std::string world_state_bytes(dem::World& w);
// Loads such bytes into a world built with the same walls and interactions; `what` names the state in errors.
void load_world_state(dem::World& w, const std::string& bytes, const char* what);
// m: the highest sphere's top (z + r) in the world; -infinity without particles.
double highest_top(const dem::World& w);

}  // namespace chamber
