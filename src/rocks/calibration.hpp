#pragma once
// BPM calibration by the Taguchi method (paper section 2.4.3-2.4.4): the calibration config, the
// 16 Brazilian runs of the L16 array with Table 2's factors, the responses (F_cd of Eq. 27 and the
// critical compression ratio), the Taguchi optimum and its refinement to the target force.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "rocks/bpm_config.hpp"
#include "rocks/platen_test.hpp"
#include "rocks/shape.hpp"
#include "rocks/taguchi.hpp"

namespace rocks {

struct CalibrationConfig {
  double diameter = 0.05, length = 0.05;   // Brazilian disk (m), section 2.4.2
  BpmModel base;                           // metaparticles, packing, stiffness ratio, damping, reference radius
  double stiffness_ratio = 2.5;            // k_bn / k_bt (Wang [37])
  PlatenTestOptions test;                  // platen speed, dt, limits
  double target_force = 14.8e3;            // N, F_cav of Eq. 27
  // Table 2 levels (SI), in level order 1..4; columns 1, 2, 4, 5 of the L16 (3 = error)
  std::vector<double> normal_strength{22e6, 17e6, 25e6, 20e6};
  std::vector<double> shear_strength{16e6, 13e6, 9e6, 11e6};
  std::vector<double> shear_stiffness{100e9, 120e9, 160e9, 200e9};
  std::vector<double> disk_radius{3.2e-3, 3.0e-3, 3.3e-3, 3.1e-3};
  double tolerance = 0.05;                 // confirmation must be within this of the target force
  int max_refinements = 4;
  bool single_particle = true;             // compress the four rock shapes with the result
  std::vector<double> rock_sizes{0.050, 0.046, 0.042, 0.038};
  unsigned long long rock_seed = 11;

  static CalibrationConfig load(const std::string& file);  // mapping "calibration"; finish() checked
};

// Bond settings of one L16 run (row 0..15) from the factor levels.
BondSettings doe_settings(const CalibrationConfig& c, int row);

struct DoeRun {
  int row = 0;
  BondSettings bond;
  PlatenTestResult result;
  double force_kN() const { return result.peak_force * 1e-3; }
  double ccr_pct() const { return result.critical_compression_ratio * 100.0; }
};

// Runs jobs [0, n) on `threads` worker threads (each simulation single-threaded); `done(i)` is
// called under a lock as each job finishes.
void run_parallel(int n, int threads, const std::function<void(int)>& job, const std::function<void(int)>& done);

// Single-particle compression (section 2.4.4, Fig. 12) of rock k (0..3): the irregular rock of size rock_sizes[k]
// (seed rock_seed + k), packed with the model's metaparticles (packing seed + 100 + k; the density lowered by 0.03
// at a time, down to 0.44, where coarse metaparticles do not reach it in a small rock), and the test's options:
// the calibration's, loaded along z (the shortest axis, as a rock lies on a platen) up to at least 15 % closure.
struct SingleParticleRock {
  std::unique_ptr<PolyhedronShape> shape;
  RockPacking packing;
};
SingleParticleRock single_particle_rock(const CalibrationConfig& c, const BpmModel& m, int k);
PlatenTestOptions single_particle_options(const CalibrationConfig& c);

// Factor level (1..4) per factor minimising the marginal mean of F_cd (Taguchi "smaller is better").
std::vector<int> taguchi_optimum(const std::vector<std::vector<double>>& means_fcd);

}  // namespace rocks
