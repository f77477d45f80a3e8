#pragma once
// Batch runs of the mechanism without ROS: the `bed` (equivalent material load) and `none` (idle) cases.
#include <string>
#include <vector>

#include "mbd/mechanism_params.hpp"

namespace mbd {

struct SimOptions {
  double duration_s = 10.0;  // recorded time after the settle time
  double sample_hz = 1000;   // rounded to whole steps
  std::string load = "bed";  // none | bed
  double settle_s = 4.0;     // simulated and discarded first (drive ramp + absorber transient)
};

// Test point displacement (m, relative to equilibrium, world), drive power and speed; t_s starts at 0. power_W is
// the power a plant logs: the motor input (DriveState::input_power, the shaft power unless effects.drive_efficiency).
struct Recording {
  std::vector<double> t_s, x_m, y_m, z_m, power_W, speed_rad_s;
};

Recording simulate(const MechanismParams& params, const SimOptions& options);

// Test-point amplitude as used for Table 5 throughout the project: HALF the peak-to-peak of the signal
// within each whole drive cycle (period_s), one value per cycle (Table 5 reports their mean and std).
std::vector<double> cycle_amplitudes(const std::vector<double>& t_s, const std::vector<double>& x, double period_s);

}  // namespace mbd
