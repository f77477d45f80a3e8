#pragma once
// Plant or model recording of the mechanism's measured signals (SI units) and its CSV form.
// Columns (DESIGN.md contract): t_s, x_m, y_m, z_m, power_W, speed_rad_s. Plant exports (plant_export.hpp)
// may also carry test-point accelerations and may lack channels: an empty channel was not recorded.
#include <array>
#include <string>
#include <vector>

namespace analysis {

enum Channel { kX = 0, kY, kZ, kPower, kSpeed, kAx, kAy, kAz, kNumChannels };
extern const std::array<const char*, kNumChannels> kChannelNames;   // "x_m", ..., "ax_m_s2", ...
extern const std::array<const char*, kNumChannels> kChannelUnits;   // "m", "W", "rad/s", "m/s^2"
inline bool is_displacement(int c) { return c == kX || c == kY || c == kZ; }
inline bool is_acceleration(int c) { return c == kAx || c == kAy || c == kAz; }
// The displacement channel whose second time derivative an acceleration channel measures (kAx -> kX).
inline int displacement_of(int c) { return c - kAx + kX; }

struct Recording {
  std::string source;  // file name or "model"; used in messages
  std::vector<double> t_s, x_m, y_m, z_m, power_W, speed_rad_s;
  std::vector<double> ax_m_s2, ay_m_s2, az_m_s2;  // test-point acceleration (plant exports only)
  // Logger resolution of each channel (SI), 0 = not stated (estimated from the data, quantisation.hpp).
  std::array<double, kNumChannels> resolution{};
  // The sensor's zero is arbitrary (a displacement sensor not zeroed at the machine's rest): the channel's mean
  // says nothing of the machine and is not compared (diagnose --zero-unknown).
  std::array<bool, kNumChannels> zero_unknown{};
  std::vector<std::string> notes;  // what reading the file did (rows skipped, gaps), for the report

  std::size_t size() const { return t_s.size(); }
  bool has(int c) const { return !channel(c).empty(); }  // recorded (not every plant logs every channel)
  std::vector<double>& channel(int c);
  const std::vector<double>& channel(int c) const;
  double duration_s() const { return t_s.empty() ? 0.0 : t_s.back() - t_s.front(); }
  double sample_dt_s() const;          // median sample spacing
  double mean_speed_rad_s() const;
  // Samples with t in [t0, t1).
  Recording slice(double t0, double t1) const;
};

// diagnose --zero-unknown: a comma-separated list of displacement channels (x, y, z) whose sensor zero is unknown.
// Throws std::invalid_argument naming a bad item and what is accepted.
std::array<bool, kNumChannels> parse_zero_unknown(const std::string& list);

// One recording logged over several files (a logger's hourly files; diagnose --part): the parts in order, on one
// clock, joined into one; the time between two parts stays a gap (reported in notes). Throws std::invalid_argument
// naming the part when a part has under 2 samples, the parts log different channels, overlap in time, differ in
// sample step by over 1 % or lie over kMaxPartGap_s apart (one harmonic fit spans the parts: its phase must carry
// across the gap; parts further apart are separate recordings).
constexpr double kMaxPartGap_s = 10.0;
Recording join_parts(const std::vector<Recording>& parts);

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
// Throws std::invalid_argument if time is empty, a recorded channel's length differs from time's or a
// value is non-finite. Channels left empty were not recorded.
void check_consistent(const Recording& r);

}  // namespace analysis
