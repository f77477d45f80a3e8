#include "analysis/sensor_model.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "analysis/metrics.hpp"

namespace analysis {

double channel_scale(const std::vector<double>& v) {
  return std::max(std::sqrt(variance(v)), 0.01 * std::abs(mean(v)));
}

Recording apply_sensor_errors(const Recording& model, const SensorErrors& e) {
  check_consistent(model);
  if (!(e.noise_rel >= 0)) throw std::invalid_argument("noise std must be >= 0 (fraction of channel scale)");
  if (!(e.gain > 0)) throw std::invalid_argument("gain must be > 0");
  Recording r = model;
  std::mt19937_64 rng(e.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (double& t : r.t_s) t += e.time_offset_s;
  for (int c = 0; c < kNumChannels; ++c) {
    auto& v = r.channel(c);
    const double s = e.noise_rel * channel_scale(v);
    const double g = is_displacement(c) || is_acceleration(c) ? e.gain : 1.0;
    for (double& x : v) x = g * x + s * normal(rng);
  }
  for (int c : {kX, kY, kZ})
    for (double& x : r.channel(c)) x += e.zero_offset_m[c - kX];
  return r;
}

Recording with_acceleration(const Recording& r) {
  check_consistent(r);
  if (r.size() < 5) throw std::invalid_argument(r.source + ": too short to differentiate (5 samples needed)");
  Recording out;
  out.source = r.source;
  out.resolution = r.resolution;
  out.zero_unknown = r.zero_unknown;
  out.notes = r.notes;
  for (std::size_t i = 2; i + 2 < r.size(); ++i) {
    out.t_s.push_back(r.t_s[i]);
    for (int c = 0; c < kNumChannels; ++c)
      if (r.has(c)) out.channel(c).push_back(r.channel(c)[i]);
    const double h = 0.25 * (r.t_s[i + 2] - r.t_s[i - 2]);
    for (int c : {kX, kY, kZ}) {
      if (!r.has(c) || r.has(c - kX + kAx)) continue;  // an acceleration already there is kept
      const auto& y = r.channel(c);
      out.channel(c - kX + kAx).push_back((-y[i - 2] + 16 * y[i - 1] - 30 * y[i] + 16 * y[i + 1] - y[i + 2]) / (12 * h * h));
    }
  }
  return out;
}

}  // namespace analysis
