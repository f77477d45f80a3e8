#pragma once
// Plant or model recording of the mechanism's measured signals (SI units) and its CSV form.
// Columns (DESIGN.md contract): t_s, x_m, y_m, z_m, power_W, speed_rad_s.
#include <array>
#include <string>
#include <vector>

namespace analysis {

enum Channel { kX = 0, kY, kZ, kPower, kSpeed, kNumChannels };
extern const std::array<const char*, kNumChannels> kChannelNames;   // "x_m", ... as in the CSV
extern const std::array<const char*, kNumChannels> kChannelUnits;   // "m", "W", "rad/s"

struct Recording {
  std::string source;  // file name or "model"; used in messages
  std::vector<double> t_s, x_m, y_m, z_m, power_W, speed_rad_s;

  std::size_t size() const { return t_s.size(); }
  std::vector<double>& channel(int c);
  const std::vector<double>& channel(int c) const;
  double duration_s() const { return t_s.empty() ? 0.0 : t_s.back() - t_s.front(); }
  double sample_dt_s() const;          // median sample spacing
  double mean_speed_rad_s() const;
  // Samples with t in [t0, t1).
  Recording slice(double t0, double t1) const;
};

// Any struct with the six vectors (e.g. mbd::Recording) into an analysis::Recording.
template <class R>
Recording from_fields(const R& r, const std::string& source) {
  Recording out;
  out.source = source;
  out.t_s = r.t_s; out.x_m = r.x_m; out.y_m = r.y_m; out.z_m = r.z_m;
  out.power_W = r.power_W; out.speed_rad_s = r.speed_rad_s;
  return out;
}

// Reads a CSV recording. Throws std::invalid_argument naming file, line, column and what is accepted:
// header must name the six columns (any order, extra columns rejected), numbers finite, time strictly
// increasing with near-uniform spacing, speed positive, at least `min_rows` rows.
Recording read_recording_csv(const std::string& path, std::size_t min_rows = 50);
Recording parse_recording_csv(const std::string& text, const std::string& name, std::size_t min_rows = 50);
void write_recording_csv(const Recording& r, const std::string& path);
// Throws std::invalid_argument if vectors differ in length, are empty or hold non-finite values.
void check_consistent(const Recording& r);

}  // namespace analysis
