#pragma once
// Plant-engineer metrics of one run (Table 5 of the paper), from sampled signals.
// Amplitude of a displacement channel: half the peak-to-peak value within each drive cycle;
// Table 5 reports its mean and standard deviation over cycles, and so do we.
#include <optional>
#include <string>
#include <vector>

namespace analysis {

struct MeanStd {
  double mean = 0, std = 0;
  int samples = 0;  // cycles (amplitude, power) the statistics were taken over
};

struct RunSignals {
  std::vector<double> t_s, x_m, y_m, z_m, power_W, speed_rad_s;
};

// Per-cycle amplitude statistics of one channel, cycles of period 2 pi / drive_speed, skipping t < t_from.
MeanStd cycle_amplitude(const std::vector<double>& t, const std::vector<double>& v, double drive_speed_rad_s,
                        double t_from = 0.0);
// Per-cycle means of a signal (e.g. power), then mean and std over cycles.
MeanStd cycle_mean(const std::vector<double>& t, const std::vector<double>& v, double drive_speed_rad_s,
                   double t_from = 0.0);

struct ProductSummary {  // from the DEM, when particles are attached
  double throughput_tph = 0;
  double mass_discharged_kg = 0;
  std::vector<double> sieve_mm, passing_pct;
  double mass_lost_kg = 0;  // spilled or thrown out of the machine (not product)
  double mass_crushed_kg = 0;  // metaparticles crushed to fines (dem.crushing): discharged or held in the chamber (dem.fines: flow)
};

struct RunSummary {
  MeanStd amplitude_x_mm, amplitude_y_mm, amplitude_z_mm, power_kW, speed_rad_s;
  std::optional<ProductSummary> product;
  double simulated_s = 0, wall_s = 0;
  std::string config, load;
  std::string stopped;  // why the run ended before its end ("" when it ran to its end): null in summary.json
};

// Summary over t >= t_from (settling excluded). Amplitudes in mm, power in kW.
RunSummary summarize(const RunSignals& s, double drive_speed_rad_s, double t_from);

// Size (mm) at which the cumulative passing (ascending sieves, percent) crosses `pct`, interpolated linearly in
// log size between sieves; -1 when it is not crossed inside the sieves.
double passing_size_mm(const std::vector<double>& sieve_mm, const std::vector<double>& passing_pct, double pct);
// Passing (%) at size x_mm, interpolated the same way (clamped to the end sieves' values outside them).
double passing_at_mm(const std::vector<double>& sieve_mm, const std::vector<double>& passing_pct, double x_mm);


// summary.json as DESIGN.md specifies; fields that need particles are null without a product. JSON has no inf or
// nan: a non-finite value is written as null and its field added to *non_finite (for the caller's warning).
std::string to_json(const RunSummary& s, std::vector<std::string>* non_finite = nullptr);

}  // namespace analysis
