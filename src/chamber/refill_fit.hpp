#pragma once
// The refill law (bed_refill.hpp) on the gap slice's kinematics (gap_slice.hpp), and its length fitted to slices
// measured at several speeds. A pouring's reloads at two speeds, on copies of the same poured bed, share what the law
// leaves out (how a poured bed takes its first pressing, the box's floor), so the law is fitted to their ratio.
// SI inside.
#include <vector>

#include "chamber/flow_model.hpp"

namespace chamber {

// Work per kg of each of `cycles` cycles of a bed filling the gap loosely (s = 0 at the open gap), pressed by the
// plate x(t) = gap - stroke (1 - cos 2 pi f t) / 2: s = 1 - x / gap, the loop's integral of p ds over the loose density.
std::vector<double> refill_slice_work(const FlowMaterial& m, double gap, double stroke, double frequency_hz, int cycles,
                                      double gravity, int steps_per_cycle = 20000);

// The law's mean reload (cycles 2 on) at rpm over its mean reload at reference_rpm.
double refill_reload_ratio(const FlowMaterial& m, double gap, double stroke, int cycles, double gravity, double rpm,
                           double reference_rpm);

// One pouring's reloads at one speed (gap_slice.csv): the mean work of its cycles 2 on, J/kg.
struct SliceReload {
  int pouring = 0;
  double rpm = 0, reload_J_kg = 0;
};

struct RefillFit {
  double length_m = 0;  // d
  double rms_log = 0;   // rms of ln(measured ratio / the law's) over the fitted ratios
  int ratios = 0;       // pourings x speeds fitted
};

// The refill length d that minimises the squared log error of each pouring's reload at a speed in fit_rpm over its
// reload at reference_rpm (the law's ratio from refill_reload_ratio). Speeds not in fit_rpm stay out of the fit. d is
// searched from 0.1 mm up to the first minimum of the law's ratio at the fastest fitted speed: beyond it a longer
// refill makes every reload a sliver of the first pressing at every speed (reload ratios return to 1), not the
// slice's bed. Throws std::invalid_argument when no pouring has both speeds.
RefillFit fit_refill_length(const FlowMaterial& m, double gap, double stroke, int cycles, double gravity,
                            const std::vector<SliceReload>& data, double reference_rpm, const std::vector<double>& fit_rpm);

}  // namespace chamber
