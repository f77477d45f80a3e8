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
    const double g = (c == kX || c == kY || c == kZ) ? e.gain : 1.0;
    for (double& x : v) x = g * x + s * normal(rng);
  }
  return r;
}

}  // namespace analysis
