#pragma once
// What a plant measurement adds to the true signals: white sensor noise, a time offset between the
// logger's clock and the drive phase, a displacement-sensor gain error and its zero offset. Used to make test
// recordings from the model (make_recording) with known non-physical differences.
#include <array>
#include <cstdint>

#include "analysis/recording.hpp"

namespace analysis {

struct SensorErrors {
  double noise_rel = 0.0;      // noise std as a fraction of each channel's scale (see channel_scale)
  double time_offset_s = 0.0;  // recording(t) = model(t - offset)
  double gain = 1.0;           // multiplies x, y, z and ax, ay, az (the motion sensor); power, speed unaffected
  std::array<double, 3> zero_offset_m{};  // added to x, y, z: a displacement sensor not zeroed at rest
  std::uint64_t seed = 1;
};

// Scale of a channel for noise: its standard deviation, but at least 1 % of its mean magnitude (so a
// constant drive speed still gets noise).
double channel_scale(const std::vector<double>& v);
Recording apply_sensor_errors(const Recording& model, const SensorErrors& e);
// The test point's acceleration (ax, ay, az) from its displacement, as an accelerometer would log it:
// 5-point central differences (error O(dt^4)) of a uniformly sampled recording; the first and last two
// samples are dropped.
Recording with_acceleration(const Recording& r);

}  // namespace analysis
