#include "mbd/simulate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "mbd/mechanism.hpp"

namespace mbd {

Recording simulate(const MechanismParams& params, const SimOptions& o) {
  if (!(o.duration_s > 0)) throw std::invalid_argument("mbd::simulate: duration_s must be > 0");
  if (!(o.settle_s >= 0)) throw std::invalid_argument("mbd::simulate: settle_s must be >= 0");
  if (!(o.sample_hz > 0)) throw std::invalid_argument("mbd::simulate: sample_hz must be > 0");
  if (o.load != "bed" && o.load != "none")
    throw std::invalid_argument("mbd::simulate: load '" + o.load + "' is not accepted; accepted: none, bed");
  const LoadModel load = load_model_from_string(o.load);

  Mechanism m(params, load);
  const double dt = params.dt_s;
  const long settle_steps = std::lround(o.settle_s / dt);
  for (long i = 0; i < settle_steps; ++i) m.step();
  const long every = std::max(1L, std::lround(1.0 / (o.sample_hz * dt)));
  const long steps = std::lround(o.duration_s / dt);
  Recording r;
  const std::size_t n = static_cast<std::size_t>(steps / every + 1);
  for (auto* v : {&r.t_s, &r.x_m, &r.y_m, &r.z_m, &r.power_W, &r.speed_rad_s}) v->reserve(n);
  const double t0 = m.time();
  auto sample = [&] {
    const auto tp = m.test_point();
    const auto d = m.drive();
    r.t_s.push_back(m.time() - t0);
    r.x_m.push_back(tp.displacement.x());
    r.y_m.push_back(tp.displacement.y());
    r.z_m.push_back(tp.displacement.z());
    r.power_W.push_back(d.input_power);  // the logged motor power (= shaft power unless effects.drive_efficiency)
    r.speed_rad_s.push_back(d.speed);
  };
  sample();
  for (long i = 1; i <= steps; ++i) {
    m.step();
    if (i % every == 0) sample();
  }
  return r;
}

std::vector<double> cycle_amplitudes(const std::vector<double>& t, const std::vector<double>& x, double period) {
  if (t.size() != x.size()) throw std::invalid_argument("mbd::cycle_amplitudes: t and x differ in length");
  if (!(period > 0)) throw std::invalid_argument("mbd::cycle_amplitudes: period must be > 0");
  std::vector<double> out;
  std::size_t i = 0;
  if (t.empty()) return out;
  for (double t0 = t.front(); t0 + period <= t.back() + 1e-12; t0 += period) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (; i < t.size() && t[i] < t0 + period - 1e-12; ++i) lo = std::min(lo, x[i]), hi = std::max(hi, x[i]);
    if (hi >= lo) out.push_back(0.5 * (hi - lo));
  }
  return out;
}

}  // namespace mbd
