#include "analysis/comparison.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "analysis/metrics.hpp"
#include "analysis/optimise.hpp"

namespace analysis {
namespace {
double kPi = 3.14159265358979323846;

// Noise variance must not vanish (a noiseless channel would take all the weight): floor it at a tiny
// fraction of the channel's spread.
double floor_sigma2(double s2, double spread2) { return std::max(s2, 1e-12 * spread2 + 1e-30); }

std::complex<double> shifted(const Harmonics& h, int k, double omega, double tau) {
  return h.C[k] * std::polar(1.0, -k * omega * tau);
}
bool is_displacement(int c) { return c == kX || c == kY || c == kZ; }
}  // namespace

double harmonic_sigma2(const Dataset& d, const Harmonics& m, int c, double gain) {
  // Recording noise plus the model's own non-periodic part, as seen by a harmonic coefficient: the
  // model's coefficients come from m.samples samples, the recording's from d.rec.size().
  const double g = is_displacement(c) ? gain : 1.0;
  const double model = m.samples > 0 ? g * g * m.remainder_var * d.rec.size() / m.samples : 0.0;
  return d.sigma2[c] + model;
}

ChannelHarmonics model_harmonics(const Recording& run, int K) {
  check_consistent(run);
  const double w = run.mean_speed_rad_s();
  ChannelHarmonics out;
  for (int c = 0; c < kNumChannels; ++c) {
    out[c] = fit_harmonics(run.t_s, run.channel(c), w, K);
    const auto r = harmonic_remainder(run.t_s, run.channel(c), out[c]);
    double s = 0;
    for (double v : r) s += v * v;
    out[c].samples = run.size();
    out[c].remainder_var = s / std::max(1.0, run.size() - (2.0 * K + 1));
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
  // The recorded speed may carry noise and ripple; its mean locates the fundamental, the displacement
  // and power harmonics pin it down (within +-1 %).
  d.omega = refine_fundamental(rec.t_s, {&rec.x_m, &rec.y_m, &rec.power_W}, d.mean_speed, 0.01, 3);
  const double n = rec.size();
  for (int c = 0; c < kNumChannels; ++c) {
    const auto& y = rec.channel(c);
    d.H[c] = fit_harmonics(rec.t_s, y, d.omega, K);
    auto r = harmonic_remainder(rec.t_s, y, d.H[c]);
    double s = 0;
    for (double v : r) s += v * v;
    d.rss_rest[c] = s;
    d.tss[c] = variance(y) * n;
    d.sigma2[c] = floor_sigma2(s / std::max(1.0, n - (2 * K + 1)), variance(y));
  }
  return d;
}

std::array<double, kNumChannels> harmonic_rss(const Dataset& d, const ChannelHarmonics& m, const Alignment& a) {
  std::array<double, kNumChannels> out{};
  const double n = d.rec.size();
  for (int c = 0; c < kNumChannels; ++c) {
    const double g = is_displacement(c) ? a.gain : 1.0;
    const int K = std::min(d.H[c].orders(), m[c].orders());
    double p = 0;
    for (int k = 0; k <= K; ++k) {
      const auto r = d.H[c].C[k] - g * shifted(m[c], k, d.omega, a.tau_s);
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
    for (int c : {kX, kY, kZ}) {
      const double w = 1.0 / d.sigma2[c];
      const int K = std::min(d.H[c].orders(), m[c].orders());
      for (int k = 0; k <= K; ++k) {
        const auto mk = shifted(m[c], k, d.omega, tau);
        const double f = k == 0 ? 1.0 : 0.5;
        num += w * f * (std::conj(mk) * d.H[c].C[k]).real();
        den += w * f * std::norm(mk);
      }
    }
    return den > 0 ? num / den : 1.0;
  };
  auto cost_at = [&](double tau) {
    Alignment t = a;
    t.tau_s = tau;
    t.gain = fit_gain ? best_gain(tau) : 1.0;
    return harmonic_cost(d, m, t);
  };
  if (fit_tau) {
    // Scan one period finely enough for the highest order, then golden-section refine.
    const int n = 8 * kFitOrders + 1;
    Minimum best = minimise_scan_golden(cost_at, 0.0, a.period_s, n, 1e-9 * a.period_s);
    a.tau_s = std::fmod(best.x + a.period_s, a.period_s);
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
    const double g = is_displacement(c) ? a.gain : 1.0;
    const auto& y = d.rec.channel(c);
    auto& yhat = out.model_on_recording_times[c];
    yhat.resize(n);
    for (std::size_t i = 0; i < n; ++i) yhat[i] = g * m[c].value(t[i] * d.omega / m[c].omega, a.tau_s * d.omega / m[c].omega);
    ChannelError& e = out.ch[c];
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
    Harmonics hr = fit_harmonics(t, res, d.omega, kFitOrders);
    e.order_residual_power.assign(kReportOrders + 2, 0.0);
    e.order_recording_power.assign(kReportOrders + 2, 0.0);
    double hp = 0;
    for (int k = 0; k <= kFitOrders; ++k) {
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
    e.dof_chi2 = 2 * kFitOrders + 1;
    num += e.rss / e.sigma2;
    den += e.tss / e.sigma2;
  }
  out.nrmse_overall = den > 0 ? std::sqrt(num / den) : 0.0;
  out.fit_percent_overall = fit_percent(out.nrmse_overall);
  return out;
}

}  // namespace analysis
