#pragma once
// Virtual gap slice on the calibrated bonded-particle rock: what the chamber's cycle costs when the bed is pressed
// across gravity and the opening gap lets it slump, at a given drive speed.
//
// The piston die (piston_die.hpp) presses along gravity: unloaded, its bed rests where it was pressed, and a reload
// costs 3-9 % of the first loop (src/chamber/README.md). In the chamber the liners press the bed sideways; as the gap
// opens the rock falls into the room it frees (Evertsson's flow), for as long as the gap stays open, half a cycle.
// The slice is that: a steel box (concave plate x = 0, mantle plate x = gap, side plates y = 0 and y = depth, floor
// z = 0, open top) filled by loose pouring (rock_pour.hpp); the mantle plate moves x(t) = gap - stroke (1 - cos 2 pi f
// t) / 2, cycle after cycle, for each frequency f on a copy of the same settled bed. Each cycle's work of the plate
// on the rock, peak force, bonds broken and how far the bed's centre of mass sank tell whether the bed is pressed
// from loose every cycle (the flow model's shipped law) or keeps its compaction (the die's reload), and whether that
// depends on the time the gap stays open (400 rpm: 75 ms, free fall 28 mm; 600 rpm: 50 ms, 12 mm).
// SI inside.
#include <string>
#include <vector>

#include "rocks/bpm_config.hpp"

namespace chamber {

struct GapSliceOptions {
  double gap = 0.12;                 // m, the open gap (plate to plate, x)
  double depth = 0.12;               // m, the slice's depth (y)
  double stroke = 0.015;             // m, the mantle plate's closing travel per cycle
  std::vector<double> frequencies{400.0 / 60.0, 600.0 / 60.0};  // Hz, each on a copy of the settled bed
  int cycles = 5;                    // per frequency
  int rock_count = 40;
  double rock_min = 0.028, rock_max = 0.040;  // m, nominal sizes (the die's)
  double rock_density = 2600.0;      // kg/m^3 (Table 4)
  double settle_min_time = 0.03, settle_max_time = 0.4, settle_speed = 0.01;  // s, s, m/s (the die's)
  double dt_safety = 0.8;            // dt = dt_safety x min(0.3 Rayleigh step, bond step)
  double max_overlap_fraction = 0.9; // the die's (a loose bed's few chains)
  int record_every = 100;            // steps per recorded trace point
  unsigned long long seed = 1;
  int threads = 1;
  bool verbose = false;
  std::string blowup_dump_path;      // "": an unguessable name in the temporary folder
  void validate() const;             // std::invalid_argument naming the option and what is accepted
};

struct GapCycle {
  double work_per_kg = 0.0;          // J/kg: the mantle plate's work on the rock over the cycle (in - out)
  double loading_work_per_kg = 0.0;  // J/kg: over its closing half
  double peak_force = 0.0;           // N on the mantle plate
  double peak_pressure = 0.0;        // Pa: peak force / (depth x bed height at the cycle's start)
  double top = 0.0;                  // m: the highest sphere's top at the cycle's start
  double com_drop = 0.0;             // m: how far the centre of mass sank over the cycle (slump and compaction)
  std::size_t bonds_broken = 0;
};

struct GapSliceRun {
  double frequency = 0.0;            // Hz
  std::vector<GapCycle> cycles;
  std::vector<double> t, gap, force; // trace: s since the first cycle's start, m, N (averaged over record_every)
  std::string blowup;                // a cycle that blew up ends this run (the cycles completed are kept): where, why
};

struct GapSliceResult {
  int rocks = 0;
  std::size_t particles = 0, bonds = 0;
  double rock_mass = 0.0;            // kg
  double bed_height = 0.0;           // m, the settled bed's highest sphere top
  double loose_solid_fraction = 0.0; // rock_mass / (gap x depth x bed_height x rock density)
  double dt = 0.0, settle_time = 0.0, wall_s = 0.0;
  std::vector<GapSliceRun> runs;     // one per frequency, in order
};

GapSliceResult run_gap_slice(const rocks::BpmModel& bpm, const GapSliceOptions& o);

}  // namespace chamber
