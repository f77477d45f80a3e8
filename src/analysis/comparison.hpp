#pragma once
// Model-versus-recording comparison at the drive frequency: alignment (time offset modulo one drive
// period, displacement-sensor gain), residual by channel, by harmonic order and by time window.
#include <array>
#include <string>
#include <vector>

#include "analysis/harmonics.hpp"
#include "analysis/recording.hpp"

namespace analysis {

constexpr int kFitOrders = 12;     // orders fitted to recordings and model (0..12)
constexpr int kReportOrders = 6;   // orders reported individually (0..6); the rest is "other"

using ChannelHarmonics = std::array<Harmonics, kNumChannels>;

// Steady-state periodic description of a model run: harmonics of each channel at the run's own mean
// speed. The shape is a function of drive phase, so it is re-timed to the recording's fundamental.
// Acceleration channels the run lacks are its displacement's second time derivative (5-point stencil,
// its gain per order divided out), fitted like the others; re-timed to a fundamental w' they scale by
// (w'/w)^2. The accelerometer's mean (bias, gravity) is not compared: order 0 of an acceleration channel
// is left out.
ChannelHarmonics model_harmonics(const Recording& model_run, int K = kFitOrders);

// How a recording's channel enters the comparison, and its noise floor's parts.
struct ChannelUse {
  bool compared = false;           // recorded, and a signal (not a set point)
  // Its mean (order 0) compared: not an accelerometer's (bias, gravity) nor a sensor's of unknown zero.
  bool mean_compared = false;
  std::string why_not;             // "not recorded", "set point" (when not compared)
  double setpoint_value = 0;       // median of a set-point channel (SI)
  double resolution = 0;           // logger resolution (SI): stated, or the smallest step in the data
  bool resolution_estimated = false;
  double quantisation_var = 0;     // q^2 / 12: the noise floor's least value
  double quantisation_systematic = 0;  // its undithered part (does not average out; quantisation.hpp)
};

// A recording (or a time window of one) prepared for comparison.
struct Dataset {
  std::string label;                         // e.g. "rec1 [0, 6) s"
  Recording rec;
  double omega = 0;                          // fundamental, rad/s (refined from speed_rad_s)
  double mean_speed = 0;                     // mean of speed_rad_s
  double setpoint = 0;                       // drive set point the model runs at, rad/s
  ChannelHarmonics H;                        // harmonics of the recording
  std::array<double, kNumChannels> sigma2{};     // noise variance per channel (non-harmonic remainder)
  std::array<double, kNumChannels> rss_rest{};   // sum of squares of the non-harmonic remainder
  std::array<double, kNumChannels> tss{};        // sum of squares about the mean
  std::array<ChannelUse, kNumChannels> use{};
};
Dataset prepare_dataset(const Recording& rec, const std::string& label, int K = kFitOrders);

// Non-physical differences: the recording equals gain * model(t - tau) on the displacement channels
// and model(t - tau) on power and speed. tau is only defined modulo one drive period.
struct Alignment {
  double tau_s = 0;
  double gain = 1;
  double period_s = 0;
};
// Best tau in [0, period) (and gain, if fit_gain) in the harmonic domain, weights 1 / sigma2.
Alignment align(const Dataset& d, const ChannelHarmonics& m, bool fit_gain = true, bool fit_tau = true);
// Noise variance against which a channel's harmonic residual is judged: recording noise plus the model
// run's non-periodic remainder scaled to the recording's length (a short model run of a mechanism with
// broadband fluctuation gives uncertain harmonics), plus the undithered quantisation power spread over
// the fitted orders (it does not average down with the number of samples).
double harmonic_sigma2(const Dataset& d, const Harmonics& m, int c, double gain);
// Weighted cost sum_c RSS_c / sigma2_c (recording noise only) evaluated in the harmonic domain (fast; used inside fits).
double harmonic_cost(const Dataset& d, const ChannelHarmonics& m, const Alignment& a);
// Per-channel harmonic-domain RSS (non-harmonic remainder included).
std::array<double, kNumChannels> harmonic_rss(const Dataset& d, const ChannelHarmonics& m, const Alignment& a);

struct ChannelError {
  double rss = 0, tss = 0, n = 0, sigma2 = 0;
  double nrmse = 0, fit_percent = 0;
  // Mismatch by order k = 0..kReportOrders, plus index kReportOrders+1 = orders above (to kFitOrders):
  std::vector<double> order_residual_power;   // mean power of the residual's order-k part
  std::vector<double> order_recording_power;  // mean power of the recording's order-k part
  std::vector<double> order_nrmse;            // sqrt(residual / recording power) per order
  bool compared = false;       // false: channel not recorded or a set point; all figures 0, n = 0
  double harmonic_sigma2 = 0;  // sigma2 plus the model's own non-periodic part (see harmonic_sigma2)
  double chi2 = 0;   // n * harmonic residual power / harmonic_sigma2 (chi-square, dof_chi2, if only noise)
  int dof_chi2 = 0;
  std::vector<double> window_rms_over_sigma;  // RMS residual / noise std in each time window
};

struct Comparison {
  std::string label;
  Alignment alignment;
  std::array<ChannelError, kNumChannels> ch;
  std::vector<double> window_t0_s;
  double nrmse_overall = 0;      // sqrt(sum rss/sigma2 / sum tss/sigma2): noise-weighted over channels
  double fit_percent_overall = 0;
  std::vector<double> model_on_recording_times[kNumChannels];  // aligned model, for plots
};
// Time-domain comparison (exact residuals), with breakdowns.
Comparison compare(const Dataset& d, const ChannelHarmonics& m, const Alignment& a, const std::string& label,
                   int n_windows = 0);
// Significance of a channel's harmonic residual against noise (chi-square upper tail, normal approx.).
bool residual_significant(const ChannelError& e, double z = 5.0);

}  // namespace analysis
