#pragma once
// Every pouring of a virtual piston-die test as a text record (a run's piston_die_pourings.txt), so that pourings of
// several runs (seeds 1-4 one day, 5-8 the next) are fitted together later without repeating the DEM, and so that a
// fit's uncertainty over the pourings (the jackknife, leave_one_out_fits) can be recomputed from the files.
// Numbers are written to 17 significant digits: a record read back fits to the same material, bit for bit.
//
// Format (one item per line, "key=value" fields separated by spaces; '#' lines are comments):
//   piston_die_pourings 1
//   pouring seed=.. rocks=.. particles=.. bonds=.. die_diameter_m=.. die_area_m2=.. rock_min_m=.. rock_max_m=..
//           piston_speed_m_s=.. bed_height_m=.. rock_mass_kg=..
//           solid_density_kg_m3=.. loose_solid_fraction=.. dt_s=.. settle_s=.. metaparticle_diameter_m=..
//           min_resolved_m=.. wall_s=..
//   blowup TEXT                  (only where a loop blew up)
//   feed_passing v v ...         (on flow_sieves_mm())
//   loop s_max=.. s_reached=.. loading_work_Pa=.. loop_energy_Pa=.. energy_per_kg=.. loading_energy_per_kg=..
//        bonds_broken=.. mass_error=.. fragments=.. wall_s=..
//   passing v v ...
//   s v v ... / p_Pa v v ... / phase 0 0 ... 1 1
#include <string>
#include <vector>

#include "chamber/piston_die.hpp"

namespace chamber {

void write_pourings(const std::vector<PistonDieResult>& pourings, const std::string& file);
// std::invalid_argument naming the file, the line and what was expected.
std::vector<PistonDieResult> read_pourings(const std::string& file);

// One pouring pressed again in a later run (the same seed, so the same settled bed: rocks, particles, bonds, rock
// mass, bed height and time step equal) adds its loops to the earlier record's, in order of s_max: so a pool's pourings
// can be pressed deeper later. Pourings of different seeds are kept as they are. std::invalid_argument, naming the
// seed and what differs, for a seed recorded twice as different beds or with the same s_max twice.
std::vector<PistonDieResult> merge_repressed_pourings(const std::vector<PistonDieResult>& pourings);

// The jackknife of the pooled fit: the pooled fit of the pourings without pouring i, for each i (at least three
// pourings, so that each fit pools two or more). std::invalid_argument otherwise.
std::vector<MaterialFit> leave_one_out_fits(const std::vector<PistonDieResult>& pourings,
                                            PressureLaw law = PressureLaw::power);

}  // namespace chamber
