#include "analysis/recording.hpp"
#include "analysis/plant_export.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace analysis {

const std::array<const char*, kNumChannels> kChannelNames = {
    "x_m", "y_m", "z_m", "power_W", "speed_rad_s", "ax_m_s2", "ay_m_s2", "az_m_s2"};
const std::array<const char*, kNumChannels> kChannelUnits = {"m", "m", "m", "W", "rad/s", "m/s^2", "m/s^2", "m/s^2"};

std::vector<double>& Recording::channel(int c) {
  switch (c) {
    case kX: return x_m;
    case kY: return y_m;
    case kZ: return z_m;
    case kPower: return power_W;
    case kSpeed: return speed_rad_s;
    case kAx: return ax_m_s2;
    case kAy: return ay_m_s2;
    case kAz: return az_m_s2;
  }
  throw std::invalid_argument("Recording::channel: index " + std::to_string(c) + " not in 0.." +
                              std::to_string(kNumChannels - 1));
}
const std::vector<double>& Recording::channel(int c) const {
  return const_cast<Recording*>(this)->channel(c);
}

double Recording::sample_dt_s() const {
  if (t_s.size() < 2) return 0.0;
  std::vector<double> d(t_s.size() - 1);
  for (std::size_t i = 1; i < t_s.size(); ++i) d[i - 1] = t_s[i] - t_s[i - 1];
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  return d[d.size() / 2];
}

double Recording::mean_speed_rad_s() const {
  double s = 0;
  for (double v : speed_rad_s) s += v;
  return speed_rad_s.empty() ? 0.0 : s / speed_rad_s.size();
}

std::array<bool, kNumChannels> parse_zero_unknown(const std::string& list) {
  std::array<bool, kNumChannels> out{};
  for (const std::string& item : split_items(list)) {
    if (item == "x") out[kX] = true;
    else if (item == "y") out[kY] = true;
    else if (item == "z") out[kZ] = true;
    else
      throw std::invalid_argument("--zero-unknown: '" + item + "' is not a displacement channel; accepted: x, y, z " +
                                  "(comma separated, e.g. x,y,z)");
  }
  return out;
}

Recording join_parts(const std::vector<Recording>& parts) {
  if (parts.empty()) throw std::invalid_argument("join_parts: no parts");
  for (const auto& p : parts) {
    check_consistent(p);
    if (p.size() < 2) throw std::invalid_argument(p.source + ": a part of a recording needs at least 2 samples");
  }
  Recording out = parts.front();
  const double dt = out.sample_dt_s();
  for (std::size_t i = 1; i < parts.size(); ++i) {
    const Recording& p = parts[i];
    const std::string pair = p.source + " (part " + std::to_string(i + 1) + " of " + out.source + ")";
    for (int c = 0; c < kNumChannels; ++c)
      if (p.has(c) != out.has(c))
        throw std::invalid_argument(pair + ": " + (p.has(c) ? "logs " : "lacks ") + kChannelNames[c] +
                                    ", the first part does not: parts of one recording log the same channels");
    if (!(p.t_s.front() > out.t_s.back())) {
      std::ostringstream m;
      m << pair << ": starts at t = " << p.t_s.front() << " s, before the parts before it end (" << out.t_s.back()
        << " s): give the parts in time order, on one clock";
      throw std::invalid_argument(m.str());
    }
    if (std::abs(p.sample_dt_s() - dt) > 0.01 * dt) {
      std::ostringstream m;
      m << pair << ": sample step " << p.sample_dt_s() << " s, the first part's " << dt
        << " s: parts of one recording share the logger's rate";
      throw std::invalid_argument(m.str());
    }
    const double gap = p.t_s.front() - out.t_s.back();
    if (gap > kMaxPartGap_s) {
      std::ostringstream m;
      m << pair << ": starts " << gap << " s after the part before it ends; parts more than " << kMaxPartGap_s
        << " s apart are separate recordings (give each its own --recording)";
      throw std::invalid_argument(m.str());
    }
    std::ostringstream note;
    note << "joined part " << p.source << " after " << gap << " s" << (gap > 1.5 * dt ? " (a gap, kept)" : "");
    out.notes.push_back(note.str());
    for (const auto& n : p.notes) out.notes.push_back(p.source + ": " + n);
    out.t_s.insert(out.t_s.end(), p.t_s.begin(), p.t_s.end());
    for (int c = 0; c < kNumChannels; ++c)
      if (p.has(c)) out.channel(c).insert(out.channel(c).end(), p.channel(c).begin(), p.channel(c).end());
  }
  for (std::size_t i = 1; i < parts.size(); ++i) out.source += " + " + parts[i].source;
  return out;
}

Recording Recording::slice(double t0, double t1) const {
  Recording out;
  out.source = source;
  out.resolution = resolution;
  out.zero_unknown = zero_unknown;
  out.notes = notes;
  for (std::size_t i = 0; i < t_s.size(); ++i) {
    if (t_s[i] < t0 || t_s[i] >= t1) continue;
    out.t_s.push_back(t_s[i]);
    for (int c = 0; c < kNumChannels; ++c)
      if (has(c)) out.channel(c).push_back(channel(c)[i]);
  }
  return out;
}

void check_consistent(const Recording& r) {
  if (r.t_s.empty()) throw std::invalid_argument(r.source + ": recording is empty");
  for (int c = 0; c < kNumChannels; ++c) {
    if (!r.has(c)) continue;
    if (r.channel(c).size() != r.t_s.size())
      throw std::invalid_argument(r.source + ": channel " + kChannelNames[c] + " has " +
                                  std::to_string(r.channel(c).size()) + " samples but t_s has " +
                                  std::to_string(r.t_s.size()) + "; all channels must be equally long");
    for (double v : r.channel(c))
      if (!std::isfinite(v))
        throw std::invalid_argument(r.source + ": channel " + kChannelNames[c] + " holds a non-finite value");
  }
}

namespace {
std::string trim(const std::string& s) {
  std::size_t a = s.find_first_not_of(" \t\r\"");
  std::size_t b = s.find_last_not_of(" \t\r\"");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}
std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream ss(line);
  while (std::getline(ss, cell, ',')) out.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}
const char* kAccepted =
    "accepted: a header line naming the columns t_s, x_m, y_m, z_m, power_W, speed_rad_s (any order, "
    "comma-separated), then one row of 6 finite numbers per sample, SI units, time strictly increasing";
}  // namespace

Recording parse_recording_csv(const std::string& text, const std::string& name, std::size_t min_rows) {
  auto fail = [&](std::size_t line, std::size_t col, const std::string& what) -> void {
    std::ostringstream m;
    m << name;
    if (line) m << ":" << line;
    if (col) m << ": column " << col;
    m << ": " << what << " (" << kAccepted << ")";
    throw std::invalid_argument(m.str());
  };
  Recording r;
  r.source = name;
  std::istringstream in(text);
  std::string line;
  std::size_t lineno = 0;
  std::vector<int> map;  // csv column -> channel (-1 = time)
  while (std::getline(in, line)) {
    ++lineno;
    if (trim(line).empty() || trim(line)[0] == '#') continue;
    auto cells = split(line);
    if (map.empty()) {
      bool seen[6] = {false, false, false, false, false, false};
      for (std::size_t j = 0; j < cells.size(); ++j) {
        int k = -2;
        if (cells[j] == "t_s") k = -1;
        for (int c = 0; c < kAx; ++c)
          if (cells[j] == kChannelNames[c]) k = c;
        if (k == -2) {
          char* end = nullptr;
          std::strtod(cells[j].c_str(), &end);
          if (end && *end == '\0' && !cells[j].empty())
            fail(lineno, j + 1, "expected a header line first, found a number '" + cells[j] + "'");
          fail(lineno, j + 1, "unknown column '" + cells[j] + "'");
        }
        if (seen[k + 1]) fail(lineno, j + 1, "column '" + cells[j] + "' appears twice");
        seen[k + 1] = true;
        map.push_back(k);
      }
      for (int k = 0; k < 6; ++k)
        if (!seen[k]) fail(lineno, 0, std::string("header lacks column '") +
                                          (k == 0 ? "t_s" : kChannelNames[k - 1]) + "'");
      continue;
    }
    if (cells.size() != map.size())
      fail(lineno, std::min(cells.size(), map.size()) + 1,
           "row has " + std::to_string(cells.size()) + " values, header has " +
               std::to_string(map.size()) + " (truncated or malformed row)");
    for (std::size_t j = 0; j < cells.size(); ++j) {
      char* end = nullptr;
      double v = std::strtod(cells[j].c_str(), &end);
      if (cells[j].empty() || !end || *end != '\0') fail(lineno, j + 1, "'" + cells[j] + "' is not a number");
      if (!std::isfinite(v)) fail(lineno, j + 1, "value '" + cells[j] + "' is not finite");
      if (map[j] == -1) {
        if (!r.t_s.empty() && v <= r.t_s.back())
          fail(lineno, j + 1, "time " + cells[j] + " s does not increase (previous " +
                                  std::to_string(r.t_s.back()) + " s)");
        r.t_s.push_back(v);
      } else {
        if (map[j] == kSpeed && v <= 0)
          fail(lineno, j + 1, "speed_rad_s must be positive (drive running), got " + cells[j]);
        r.channel(map[j]).push_back(v);
      }
    }
  }
  if (map.empty()) fail(lineno, 0, "file is empty: no header line");
  if (r.size() < min_rows)
    fail(lineno, 0, "only " + std::to_string(r.size()) + " data rows, at least " +
                        std::to_string(min_rows) + " needed");
  // Near-uniform sampling: the harmonic analysis tolerates jitter but not gaps.
  double dt = r.sample_dt_s();
  for (std::size_t i = 1; i < r.size(); ++i)
    if (r.t_s[i] - r.t_s[i - 1] > 5.0 * dt) {
      std::ostringstream m;
      m << "gap of " << r.t_s[i] - r.t_s[i - 1] << " s before t = " << r.t_s[i]
        << " s (sampling interval " << dt << " s): recording is not continuous";
      fail(0, 0, m.str());
    }
  // Unit slips (issue 22: a recording in mm was read as "sensor gain 1115"): a crusher frame vibrates millimetres
  // (Table 5: 5.5 mm), so a half peak-to-peak above 0.1 m is refused, and a motor that draws under 100 W on average;
  // when 1/1000 (1000x) of the value would fit, the message names the likely unit.
  for (int c : {kX, kY, kZ}) {
    const auto [lo, hi] = std::minmax_element(r.channel(c).begin(), r.channel(c).end());
    const double amp = 0.5 * (*hi - *lo);
    if (amp > 0.1) {
      std::ostringstream m;
      m << kChannelNames[c] << ": half peak-to-peak " << amp << " m is implausible for a crusher frame (at most 0.1 m)"
        << (amp * 1e-3 <= 0.1 ? "; millimetres given for metres? (divide by 1000)" : "");
      fail(0, 0, m.str());
    }
  }
  double mean_W = 0;
  for (double p : r.power_W) mean_W += p / r.size();
  if (mean_W < 100) {
    std::ostringstream m;
    m << "power_W: mean " << mean_W << " W is implausible for a crusher's motor (at least 100 W)"
      << (mean_W * 1e3 >= 100 ? "; kilowatts given for watts? (multiply by 1000)" : "");
    fail(0, 0, m.str());
  }
  check_consistent(r);
  return r;
}

Recording read_recording_csv(const std::string& path, std::size_t min_rows) {
  std::ifstream f(path);
  if (!f) throw std::invalid_argument(path + ": cannot open recording (expected a CSV file)");
  std::stringstream ss;
  ss << f.rdbuf();
  return parse_recording_csv(ss.str(), path, min_rows);
}

void write_recording_csv(const Recording& r, const std::string& path) {
  check_consistent(r);
  for (int c = 0; c < kNumChannels; ++c)
    if (r.has(c) != (c < kAx))
      throw std::invalid_argument(path + ": the CSV recording holds exactly t_s, x_m, y_m, z_m, power_W, "
                                  "speed_rad_s; channel " + std::string(kChannelNames[c]) +
                                  (r.has(c) ? " cannot be written (write a plant export)" : " is missing"));
  std::ofstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot write");
  f << "t_s,x_m,y_m,z_m,power_W,speed_rad_s\n" << std::setprecision(10);
  for (std::size_t i = 0; i < r.size(); ++i) {
    f << r.t_s[i];
    for (int c = 0; c < kAx; ++c) f << ',' << r.channel(c)[i];
    f << '\n';
  }
  if (!f) throw std::runtime_error(path + ": write failed");
}

}  // namespace analysis
