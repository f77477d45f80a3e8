#include "analysis/comparison.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "analysis/metrics.hpp"
#include "analysis/optimise.hpp"
#include "analysis/quantisation.hpp"

namespace analysis {
namespace {
double kPi = 3.14159265358979323846;

// Noise variance must not vanish (a noiseless channel would take all the weight): floor it at a tiny
// fraction of the channel's spread.
double floor_sigma2(double s2, double spread2) { return std::max(s2, 1e-12 * spread2 + 1e-30); }

// Model coefficient k as the recording's sensor sees it, delayed by tau: an acceleration re-timed from
// the model's fundamental to the recording's scales by (w_rec / w_model)^2.
std::complex<double> shifted(const Dataset& d, const Harmonics& h, int c, int k, double tau) {
  const double r = is_acceleration(c) ? (d.omega / h.omega) * (d.omega / h.omega) : 1.0;
  return r * h.C[k] * std::polar(1.0, -k * d.omega * tau);
}
// The sensor gain (non-physical) multiplies the test-point motion channels.
bool is_motion(int c) { return is_displacement(c) || is_acceleration(c); }
// First compared order: an accelerometer's mean (bias, gravity) is not the mechanism's.
int first_order(const Dataset& d, int c) { return d.use[c].mean_compared ? 0 : 1; }
bool comparable(const Dataset& d, const Harmonics& m, int c) { return d.use[c].compared && !m.C.empty(); }

// Second time derivative of a uniformly sampled signal by the 5-point stencil (error O(dt^4)); the
// first and last two samples are dropped.
void second_derivative(const std::vector<double>& t, const std::vector<double>& y, std::vector<double>& ta,
                       std::vector<double>& a) {
  for (std::size_t i = 2; i + 2 < y.size(); ++i) {
    const double h = 0.25 * (t[i + 2] - t[i - 2]);
    ta.push_back(t[i]);
    a.push_back((-y[i - 2] + 16 * y[i - 1] - 30 * y[i] + 16 * y[i + 1] - y[i + 2]) / (12 * h * h));
  }
}
// The stencil's gain at angle theta = w dt per sample, relative to the exact -w^2: it is exact for
// theta -> 0 and 0.996 at theta = 0.75 (order 12 at 600 rpm sampled at 1 kHz); divided out.
double stencil_gain(double theta) {
  if (theta < 1e-6) return 1.0;
  return (30.0 - 32.0 * std::cos(theta) + 2.0 * std::cos(2.0 * theta)) / (12.0 * theta * theta);
}
}  // namespace

double harmonic_sigma2(const Dataset& d, const Harmonics& m, int c, double gain) {
  // Recording noise plus the model's own non-periodic part, as seen by a harmonic coefficient: the
  // model's coefficients come from m.samples samples, the recording's from d.rec.size().
  if (!comparable(d, m, c)) return 1.0;
  const double g = is_motion(c) ? gain : 1.0;
  const double r = is_acceleration(c) ? std::pow(d.omega / m.omega, 4) : 1.0;
  const double n = d.rec.size();
  const double model = m.samples > 0 ? g * g * r * m.remainder_var * n / m.samples : 0.0;
  const int dof = 2 * std::min(d.H[c].orders(), m.orders()) + 1 - first_order(d, c);
  return d.sigma2[c] + model + n * d.use[c].quantisation_systematic / dof;
}

ChannelHarmonics model_harmonics(const Recording& run, int K) {
  check_consistent(run);
  const double w = run.mean_speed_rad_s();
  ChannelHarmonics out;
  for (int c = 0; c < kNumChannels; ++c) {
    if (!run.has(c)) continue;
    out[c] = fit_harmonics(run.t_s, run.channel(c), w, K);
    const auto r = harmonic_remainder(run.t_s, run.channel(c), out[c]);
    double s = 0;
    for (double v : r) s += v * v;
    out[c].samples = run.size();
    out[c].remainder_var = s / std::max(1.0, run.size() - (2.0 * K + 1));
    if (is_displacement(c) && !run.has(c - kX + kAx)) {
      // The test point's acceleration, differentiated in time before the harmonic fit (as an accelerometer
      // sees it: a slow drift of the displacement, which leaks into every fitted order, has almost no
      // acceleration; -(k w)^2 times the displacement's coefficients would amplify that leak).
      std::vector<double> ta, ya;
      second_derivative(run.t_s, run.channel(c), ta, ya);
      Harmonics& a = out[c - kX + kAx];
      a = fit_harmonics(ta, ya, w, K);
      const auto ra = harmonic_remainder(ta, ya, a);
      double sa = 0;
      for (double v : ra) sa += v * v;
      a.samples = ta.size();
      a.remainder_var = sa / std::max(1.0, ta.size() - (2.0 * K + 1));
      const double dt = (ta.back() - ta.front()) / std::max<std::size_t>(1, ta.size() - 1);
      for (int k = 1; k <= K; ++k) a.C[k] /= stencil_gain(k * w * dt);
      a.C[0] = 0.0;  // the mean acceleration is not compared (an accelerometer's bias)
    }
  }
  return out;
}

Dataset prepare_dataset(const Recording& rec, const std::string& label, int K) {
  check_consistent(rec);
  Dataset d;
  d.label = label;
  d.rec = rec;
  d.mean_speed = rec.mean_speed_rad_s();
  d.setpoint = d.mean_speed;
  const double periods = d.mean_speed * rec.duration_s() / (2 * kPi);
  if (periods < 3.0)
    throw std::invalid_argument(rec.source + ": " + label + " spans " + std::to_string(periods) +
                                " drive periods; at least 3 are needed to separate harmonics");
  // Which channels are signals: recorded, and not constant within their resolution (a logged set point).
  for (int c = 0; c < kNumChannels; ++c) {
    ChannelUse& u = d.use[c];
    d.sigma2[c] = 1.0;
    if (!rec.has(c)) {
      u.why_not = "not recorded";
      continue;
    }
    const auto& y = rec.channel(c);
    u.resolution = rec.resolution[c] > 0 ? rec.resolution[c] : estimate_resolution(y);
    u.resolution_estimated = !(rec.resolution[c] > 0);
    u.quantisation_var = quantisation_variance(u.resolution);
    if (constant_within_resolution(y, u.resolution)) {
      u.why_not = "set point";
      u.setpoint_value = median(y);
      continue;
    }
    u.compared = true;
    u.mean_compared = !is_acceleration(c) && !rec.zero_unknown[c];
  }
  if (!rec.has(kSpeed))
    throw std::invalid_argument(rec.source + ": " + label + " has no drive speed (a speed channel or a set "
                                "point) to locate the drive frequency");
  // The recorded speed may carry noise and ripple; its mean locates the fundamental, the motion and power
  // harmonics pin it down (within +-1 %; +-3 % when the speed is a logged set point, as the real speed
  // may droop or slip below it).
  // Orders below the recording's Nyquist limit only: a plant logger may sample at a few times the drive
  // frequency (K orders need more than 2K + 1 samples per period; above that the harmonics alias).
  const double per_period = 2 * kPi / d.mean_speed / rec.sample_dt_s();
  K = std::min(K, static_cast<int>(std::ceil(0.5 * per_period - 0.01)) - 1);  // strictly below N / 2
  if (K < 2) {
    std::ostringstream m;
    m << rec.source << ": " << label << " has " << per_period << " samples per drive period (sample step "
      << rec.sample_dt_s() << " s); at least 6 are needed for two harmonic orders";
    throw std::invalid_argument(m.str());
  }
  std::vector<const std::vector<double>*> pins;
  for (int c : {kX, kY, kAx, kAy, kPower, kZ, kAz})
    if (d.use[c].compared && pins.size() < 3) pins.push_back(&rec.channel(c));
  if (pins.empty())
    throw std::invalid_argument(rec.source + ": " + label + " has no test-point motion or power signal to "
                                "compare (channels not recorded or constant within their resolution)");
  d.omega = refine_fundamental(rec.t_s, pins, d.mean_speed, d.use[kSpeed].compared ? 0.01 : 0.03, std::min(3, K));
  const double n = rec.size();
  for (int c = 0; c < kNumChannels; ++c) {
    if (!d.use[c].compared) continue;
    const auto& y = rec.channel(c);
    d.H[c] = fit_harmonics(rec.t_s, y, d.omega, K);
    auto r = harmonic_remainder(rec.t_s, y, d.H[c]);
    double s = 0;
    for (double v : r) s += v * v;
    d.rss_rest[c] = s;
    d.tss[c] = variance(y) * n;
    // Noise floor: the remainder's variance, at least the quantisation's q^2/12; the quantisation that
    // this noise does not dither is carried separately (harmonic_sigma2).
    ChannelUse& u = d.use[c];
    const double s2 = s / std::max(1.0, n - (2 * K + 1));
    d.sigma2[c] = floor_sigma2(std::max(s2, u.quantisation_var), variance(y));
    u.quantisation_systematic = undithered_quantisation_variance(u.resolution, s2 - u.quantisation_var);
  }
  return d;
}

std::array<double, kNumChannels> harmonic_rss(const Dataset& d, const ChannelHarmonics& m, const Alignment& a) {
  std::array<double, kNumChannels> out{};
  const double n = d.rec.size();
  for (int c = 0; c < kNumChannels; ++c) {
    if (!comparable(d, m[c], c)) continue;
    const double g = is_motion(c) ? a.gain : 1.0;
    const int K = std::min(d.H[c].orders(), m[c].orders());
    double p = 0;
    for (int k = first_order(d, c); k <= K; ++k) {
      const auto r = d.H[c].C[k] - g * shifted(d, m[c], c, k, a.tau_s);
      p += k == 0 ? std::norm(r) : 0.5 * std::norm(r);
    }
    out[c] = d.rss_rest[c] + n * p;
  }
  return out;
}

double harmonic_cost(const Dataset& d, const ChannelHarmonics& m, const Alignment& a) {
  auto rss = harmonic_rss(d, m, a);
  double s = 0;
  // Plain weighted least squares with the recording's noise: the model's own fluctuation must not
  // excuse a misfit inside a fit (a model that blows up would look "uncertain", hence good).
  for (int c = 0; c < kNumChannels; ++c) s += rss[c] / d.sigma2[c];
  return s;
}

Alignment align(const Dataset& d, const ChannelHarmonics& m, bool fit_gain, bool fit_tau) {
  Alignment a;
  a.period_s = 2 * kPi / d.omega;
  // For a given tau the gain is linear least squares over the displacement channels.
  auto best_gain = [&](double tau) {
    double num = 0, den = 0;
    for (int c : {kX, kY, kZ, kAx, kAy, kAz}) {
      if (!comparable(d, m[c], c)) continue;
      const double w = 1.0 / d.sigma2[c];
      const int K = std::min(d.H[c].orders(), m[c].orders());
      for (int k = first_order(d, c); k <= K; ++k) {
        const auto mk = shifted(d, m[c], c, k, tau);
        const double f = k == 0 ? 1.0 : 0.5;
        num += w * f * (std::conj(mk) * d.H[c].C[k]).real();
        den += w * f * std::norm(mk);
      }
    }
    // A sensor gain is positive: with an odd-order-dominated motion, tau + T/2 and -g would fit almost as well.
    return den > 0 ? std::max(0.0, num / den) : 1.0;
  };
  auto cost_at = [&](double tau) {
    Alignment t = a;
    t.tau_s = tau;
    t.gain = fit_gain ? best_gain(tau) : 1.0;
    return harmonic_cost(d, m, t);
  };
  if (fit_tau) {
    // Scan one period finely enough for the highest order, then golden-section refine (around 0 too).
    const int n = 8 * kFitOrders + 1;
    a.tau_s = minimise_periodic_scan_golden(cost_at, a.period_s, n, 1e-9 * a.period_s).x;
  }
  a.gain = fit_gain ? best_gain(a.tau_s) : 1.0;
  return a;
}

bool residual_significant(const ChannelError& e, double z) {
  return e.chi2 > e.dof_chi2 + z * std::sqrt(2.0 * e.dof_chi2);
}

Comparison compare(const Dataset& d, const ChannelHarmonics& m, const Alignment& a, const std::string& label,
                   int n_windows) {
  Comparison out;
  out.label = label;
  out.alignment = a;
  const auto& t = d.rec.t_s;
  const std::size_t n = t.size();
  if (n_windows <= 0) {
    const double periods = d.rec.duration_s() / a.period_s;
    n_windows = std::max(2, std::min(10, static_cast<int>(periods / 5)));
  }
  const double t0 = t.front(), span = d.rec.duration_s() * (1 + 1e-12);
  for (int w = 0; w < n_windows; ++w) out.window_t0_s.push_back(t0 + span * w / n_windows);
  double num = 0, den = 0;
  for (int c = 0; c < kNumChannels; ++c) {
    ChannelError& e = out.ch[c];
    if (!comparable(d, m[c], c)) {
      e.sigma2 = e.harmonic_sigma2 = 1.0;
      e.order_residual_power.assign(kReportOrders + 2, 0.0);
      e.order_recording_power.assign(kReportOrders + 2, 0.0);
      e.order_nrmse.assign(kReportOrders + 2, 0.0);
      e.window_rms_over_sigma.assign(n_windows, 0.0);
      continue;
    }
    e.compared = true;
    const double g = is_motion(c) ? a.gain : 1.0;
    const double r = is_acceleration(c) ? (d.omega / m[c].omega) * (d.omega / m[c].omega) : 1.0;
    // An accelerometer's mean (bias) is taken from the recording: not compared; nor the mean of a sensor whose zero
    // is unknown (the model's mean moved onto the recording's).
    const double bias = is_acceleration(c)          ? d.H[c].C[0].real()
                        : !d.use[c].mean_compared ? d.H[c].C[0].real() - g * r * m[c].C[0].real()
                                                  : 0.0;
    const auto& y = d.rec.channel(c);
    auto& yhat = out.model_on_recording_times[c];
    yhat.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      yhat[i] = bias + g * r * m[c].value(t[i] * d.omega / m[c].omega, a.tau_s * d.omega / m[c].omega);
    e.n = n;
    e.sigma2 = d.sigma2[c];
    e.tss = d.tss[c];
    std::vector<double> res(n);
    std::vector<double> wss(n_windows, 0.0), wn(n_windows, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      res[i] = y[i] - yhat[i];
      e.rss += res[i] * res[i];
      const int w = std::min(n_windows - 1, static_cast<int>((t[i] - t0) / span * n_windows));
      wss[w] += res[i] * res[i];
      wn[w] += 1;
    }
    for (int w = 0; w < n_windows; ++w)
      e.window_rms_over_sigma.push_back(wn[w] > 0 ? std::sqrt(wss[w] / wn[w] / e.sigma2) : 0.0);
    e.nrmse = nrmse(y, yhat);
    e.fit_percent = fit_percent(e.nrmse);
    // Order breakdown of the residual (fitted at the recording's fundamental).
    const int K = d.H[c].orders();  // at most kFitOrders, fewer below the recording's Nyquist limit
    Harmonics hr = fit_harmonics(t, res, d.omega, K);
    e.order_residual_power.assign(kReportOrders + 2, 0.0);
    e.order_recording_power.assign(kReportOrders + 2, 0.0);
    double hp = 0;
    for (int k = 0; k <= K; ++k) {
      const int slot = std::min(k, kReportOrders + 1);
      e.order_residual_power[slot] += hr.power(k);
      e.order_recording_power[slot] += k == 0 ? std::norm(d.H[c].C[0]) : d.H[c].power(k);
      hp += hr.power(k);
    }
    for (int s = 0; s <= kReportOrders + 1; ++s)
      e.order_nrmse.push_back(e.order_recording_power[s] > 0
                                  ? std::sqrt(e.order_residual_power[s] / e.order_recording_power[s])
                                  : 0.0);
    e.harmonic_sigma2 = harmonic_sigma2(d, m[c], c, a.gain);
    e.chi2 = n * hp / e.harmonic_sigma2;
    e.dof_chi2 = 2 * K + 1 - first_order(d, c);
    num += e.rss / e.sigma2;
    den += e.tss / e.sigma2;
  }
  out.nrmse_overall = den > 0 ? std::sqrt(num / den) : 0.0;
  out.fit_percent_overall = fit_percent(out.nrmse_overall);
  return out;
}

}  // namespace analysis
