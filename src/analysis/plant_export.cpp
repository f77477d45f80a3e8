#include "analysis/plant_export.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "core/units.hpp"

namespace analysis {
namespace {

namespace u = core::units;
constexpr double kStandardGravity = 9.80665;  // m/s^2 per g (CGPM 1901)

struct Key {
  const char* name;
  int key;
  const char* quantity;
};
const Key kKeys[] = {{"t", kTimeKey, "time"},   {"x", kX, "displacement"},  {"y", kY, "displacement"},
                     {"z", kZ, "displacement"}, {"power", kPower, "power"}, {"speed", kSpeed, "speed"},
                     {"ax", kAx, "acceleration"}, {"ay", kAy, "acceleration"}, {"az", kAz, "acceleration"}};

struct Unit {
  const char* quantity;
  const char* name;
  double to_si;
};
const Unit kUnits[] = {
    {"time", "s", 1.0},           {"time", "ms", 1e-3},           {"time", "us", 1e-6},
    {"displacement", "m", 1.0},   {"displacement", "mm", u::mm},  {"displacement", "um", 1e-6},
    {"power", "W", 1.0},          {"power", "kW", 1e3},           {"power", "MW", 1e6},
    {"speed", "rad/s", 1.0},      {"speed", "rpm", u::rpm},       {"speed", "1/min", u::rpm},
    {"speed", "Hz", 2.0 * u::kPi},
    {"acceleration", "m/s^2", 1.0}, {"acceleration", "m/s2", 1.0}, {"acceleration", "mm/s^2", 1e-3},
    {"acceleration", "mm/s2", 1e-3}, {"acceleration", "g", kStandardGravity},
};

const Key& key_info(int key) {
  for (const auto& k : kKeys)
    if (k.key == key) return k;
  throw std::logic_error("plant_export: no key " + std::to_string(key));
}
std::string units_of(const char* quantity) {
  std::string s;
  for (const auto& un : kUnits)
    if (std::string(un.quantity) == quantity) s += std::string(s.empty() ? "" : ", ") + un.name;
  return s;
}
std::string trim(const std::string& s) {
  const std::size_t a = s.find_first_not_of(" \t\r\"'");
  const std::size_t b = s.find_last_not_of(" \t\r\"'");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}
// Splits at the delimiter outside double quotes ("1,5" is one cell in a ','-separated file).
std::vector<std::string> split(const std::string& line, char d) {
  std::vector<std::string> out;
  std::string cell;
  bool quoted = false;
  for (char c : line) {
    if (c == '"') quoted = !quoted;
    if (c == d && !quoted) {
      out.push_back(trim(cell));
      cell.clear();
    } else {
      cell += c;
    }
  }
  out.push_back(trim(cell));
  return out;
}
int parse_key(const std::string& k, const std::string& item, const char* option) {
  for (const auto& key : kKeys)
    if (k == key.name) return key.key;
  throw std::invalid_argument(std::string(option) + " '" + item + "': unknown key '" + k + "' (accepted: " +
                              accepted_column_keys() + ")");
}
std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}
bool is_missing_marker(const std::string& cell) {
  const std::string c = lower(cell);
  return c.empty() || c == "nan" || c == "-nan" || c == "na" || c == "n/a" || c == "null" || c == "none" ||
         c == "-" || c == "inf" || c == "-inf" || c == "+inf" || c == "infinity" || c == "-infinity";
}
std::string delimiter_name(char d) { return d == '\t' ? "tab" : std::string("'") + d + "'"; }

}  // namespace

std::vector<std::string> split_items(const std::string& spec) {
  std::vector<std::string> out;
  std::string cur;
  int depth = 0;
  for (char c : spec) {
    if (c == '[') ++depth;
    if (c == ']') depth = std::max(0, depth - 1);
    if (c == ',' && depth == 0) {
      out.push_back(trim(cur));
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(trim(cur));
  return out;
}

std::string accepted_column_keys() {
  std::string s;
  for (const auto& k : kKeys)
    s += std::string(s.empty() ? "" : "; ") + k.name + " (" + k.quantity + ": " + units_of(k.quantity) + ")";
  return s;
}

double unit_to_si(int key, const std::string& unit) {
  const Key& k = key_info(key);
  std::string un = unit;
  // Spellings of the same unit.
  if (un == "\xC2\xB5m" || un == "\xCE\xBCm") un = "um";
  if (un == "\xC2\xB5s" || un == "\xCE\xBCs") un = "us";
  if (un == "m/s\xC2\xB2") un = "m/s^2";
  if (un == "mm/s\xC2\xB2") un = "mm/s^2";
  if (un == "U/min" || un == "r/min" || un == "min^-1") un = "rpm";
  for (const auto& x : kUnits)
    if (un == x.name && std::string(x.quantity) == k.quantity) return x.to_si;
  throw std::invalid_argument("unit '" + unit + "' for " + k.name + " (" + k.quantity + ") is not known; accepted: " +
                              units_of(k.quantity));
}

std::map<int, ColumnSpec> parse_column_map(const std::string& spec) {
  const char* opt = "--columns";
  std::map<int, ColumnSpec> out;
  for (const std::string& item : split_items(spec)) {
    if (item.empty()) continue;
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos)
      throw std::invalid_argument(std::string(opt) + " '" + item + "': expected KEY=COLUMN[UNIT], e.g. x=disp_x[mm]");
    const int key = parse_key(trim(item.substr(0, eq)), item, opt);
    const std::string rest = trim(item.substr(eq + 1));
    const std::size_t lb = rest.rfind('[');
    if (rest.empty() || rest.back() != ']' || lb == std::string::npos || lb + 2 > rest.size())
      throw std::invalid_argument(std::string(opt) + " '" + item + "': the column's unit is missing; write " +
                                  key_info(key).name + "=COLUMN[UNIT] with UNIT one of " +
                                  units_of(key_info(key).quantity));
    ColumnSpec c;
    c.column = trim(rest.substr(0, lb));
    c.unit = trim(rest.substr(lb + 1, rest.size() - lb - 2));
    if (c.column.empty()) throw std::invalid_argument(std::string(opt) + " '" + item + "': the column name is empty");
    try {
      c.to_si = unit_to_si(key, c.unit);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string(opt) + " '" + item + "': " + e.what());
    }
    if (out.count(key)) throw std::invalid_argument(std::string(opt) + ": key '" + key_info(key).name + "' is given twice");
    for (const auto& [k, other] : out)
      if (other.column == c.column)
        throw std::invalid_argument(std::string(opt) + ": column '" + c.column + "' is mapped to both " +
                                    key_info(k).name + " and " + key_info(key).name);
    out[key] = c;
  }
  if (!out.count(kTimeKey))
    throw std::invalid_argument(std::string(opt) + " '" + spec + "': no time column; map t=COLUMN[s|ms|us]");
  bool motion = false;
  for (int c : {kX, kY, kZ, kAx, kAy, kAz}) motion = motion || out.count(c);
  if (!motion)
    throw std::invalid_argument(std::string(opt) + " '" + spec + "': no test-point channel; map at least one of "
                                "x, y, z (displacement) or ax, ay, az (acceleration): the time offset, the "
                                "sensor gain and most effects are seen in the test point's motion");
  return out;
}

char parse_delimiter(const std::string& s) {
  if (s == "tab" || s == "\\t" || s == "\t") return '\t';
  if (s == "," || s == ";" || s == "|") return s[0];
  if (s == "semicolon") return ';';
  if (s == "comma") return ',';
  throw std::invalid_argument("--delimiter '" + s + "': accepted ',', ';', '|' or tab");
}
char parse_decimal(const std::string& s) {
  if (s == "." || s == ",") return s[0];
  if (s == "comma") return ',';
  if (s == "point") return '.';
  throw std::invalid_argument("--decimal '" + s + "': accepted '.' or ','");
}

void parse_resolutions(const std::string& spec, PlantFormat& format) {
  const char* opt = "--resolution";
  for (const std::string& item : split_items(spec)) {
    if (item.empty()) continue;
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos)
      throw std::invalid_argument(std::string(opt) + " '" + item + "': expected KEY=VALUE[UNIT], e.g. x=0.01mm");
    const int key = parse_key(trim(item.substr(0, eq)), item, opt);
    if (key == kTimeKey) throw std::invalid_argument(std::string(opt) + " '" + item + "': time has no resolution here");
    const std::string v = trim(item.substr(eq + 1));
    char* end = nullptr;
    const double x = std::strtod(v.c_str(), &end);
    if (v.empty() || end == v.c_str() || !(x > 0) || !std::isfinite(x))
      throw std::invalid_argument(std::string(opt) + " '" + item + "': the value must be a positive number");
    std::string unit = trim(end);
    if (!unit.empty() && unit.front() == '[' && unit.back() == ']') unit = unit.substr(1, unit.size() - 2);
    double f = 1.0;
    if (!unit.empty()) {
      try {
        f = unit_to_si(key, unit);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string(opt) + " '" + item + "': " + e.what());
      }
    } else if (format.columns.count(key)) {
      f = format.columns.at(key).to_si;  // the column's own unit
    }
    format.resolution[key] = x * f;
  }
}

Recording parse_plant_export(const std::string& text, const std::string& name, const PlantFormat& fmt) {
  if (fmt.delimiter == fmt.decimal)
    throw std::invalid_argument(name + ": delimiter and decimal separator are both " + delimiter_name(fmt.delimiter) +
                                "; a file with decimal commas is usually ';'-separated (--delimiter ';')");
  if (!fmt.columns.count(kTimeKey)) throw std::invalid_argument(name + ": the column map has no time column (t=...)");
  auto where = [&](std::size_t line, const std::string& col) {
    std::string s = name + ":" + std::to_string(line);
    if (!col.empty()) s += ": column '" + col + "'";
    return s;
  };
  // A byte-order mark (spreadsheet exports) is not part of the first column's name.
  std::istringstream in(text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? text.substr(3) : text);
  std::string line;
  std::size_t lineno = 0, header_line = 0;
  std::vector<std::string> header;
  while (std::getline(in, line)) {
    ++lineno;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    header = split(line, fmt.delimiter);
    header_line = lineno;
    break;
  }
  if (header.empty()) throw std::invalid_argument(name + ": file is empty: no header line");
  // Column of each mapped key: NAME, or NAME[UNIT] / NAME [UNIT] when the header carries the unit.
  std::map<int, std::size_t> col;
  for (const auto& [key, spec] : fmt.columns) {
    std::vector<std::size_t> hits;
    for (std::size_t j = 0; j < header.size(); ++j)
      if (header[j] == spec.column || header[j] == spec.column + "[" + spec.unit + "]" ||
          header[j] == spec.column + " [" + spec.unit + "]")
        hits.push_back(j);
    if (hits.size() > 1)
      throw std::invalid_argument(where(header_line, spec.column) + ": the header names it " +
                                  std::to_string(hits.size()) + " times; rename one column");
    if (hits.empty()) {
      std::ostringstream m;
      m << where(header_line, "") << ": column '" << spec.column << "' (" << key_info(key).name
        << ") is not in the header; split at " << delimiter_name(fmt.delimiter) << " the header has "
        << header.size() << " column(s): ";
      for (std::size_t j = 0; j < header.size() && j < 12; ++j) m << (j ? ", " : "") << "'" << header[j] << "'";
      if (header.size() > 12) m << ", ...";
      for (char d : {';', ',', '\t', '|'})
        if (d != fmt.delimiter && split(line, d).size() > header.size() + 1) {
          m << "; the file looks " << delimiter_name(d) << "-separated: give --delimiter "
            << (d == '\t' ? "tab" : std::string("'") + d + "'");
          break;
        }
      throw std::invalid_argument(m.str());
    }
    col[key] = hits[0];
  }
  Recording r;
  r.source = name;
  for (const auto& [key, c] : col)
    if (key != kTimeKey) r.channel(key).clear();
  std::size_t rows = 0, missing = 0, first_missing = 0, unit_row = 0;
  bool first_row = true;
  std::vector<double> values(kNumChannels + 1);
  while (std::getline(in, line)) {
    ++lineno;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    const auto cells = split(line, fmt.delimiter);
    ++rows;
    // A unit row right after the header ("s;mm;mm;kW;rpm"): every mapped cell is text.
    if (first_row) {
      first_row = false;
      bool all_text = true;
      for (const auto& [key, j] : col) {
        std::string c = j < cells.size() ? cells[j] : "";
        std::replace(c.begin(), c.end(), ',', '.');
        char* end = nullptr;
        std::strtod(c.c_str(), &end);
        if (c.empty() || is_missing_marker(c) || (end && *end == '\0')) all_text = false;
      }
      if (all_text) {
        unit_row = lineno;
        --rows;
        continue;
      }
    }
    bool skip = false;
    for (const auto& [key, j] : col) {
      const std::string& colname = fmt.columns.at(key).column;
      if (j >= cells.size() || is_missing_marker(cells[j])) {
        skip = true;
        continue;
      }
      std::string c = cells[j];
      const char other = fmt.decimal == '.' ? ',' : '.';
      if (c.find(other) != std::string::npos) {
        std::string hint = fmt.decimal == '.' ? "it looks like a decimal comma: give --decimal ," :
                                                 "it has a decimal point: give --decimal . (or fix a thousands separator)";
        throw std::invalid_argument(where(lineno, colname) + ": '" + c + "' is not a number with decimal separator '" +
                                    fmt.decimal + "'; " + hint);
      }
      if (fmt.decimal == ',') std::replace(c.begin(), c.end(), ',', '.');
      char* end = nullptr;
      const double v = std::strtod(c.c_str(), &end);
      if (!end || *end != '\0' || end == c.c_str())
        throw std::invalid_argument(where(lineno, colname) + ": '" + cells[j] + "' is not a number (decimal separator " +
                                    fmt.decimal + ", delimiter " + delimiter_name(fmt.delimiter) + ")");
      if (!std::isfinite(v)) {
        skip = true;
        continue;
      }
      values[key + 1] = v * fmt.columns.at(key).to_si;
    }
    if (skip) {
      if (!missing) first_missing = lineno;
      ++missing;
      continue;
    }
    const double time = values[0];
    if (!r.t_s.empty() && time <= r.t_s.back()) {
      std::ostringstream m;
      m << where(lineno, fmt.columns.at(kTimeKey).column) << ": time " << time << " s does not increase (previous row "
        << r.t_s.back() << " s); rows must be in time order without repeats";
      throw std::invalid_argument(m.str());
    }
    if (col.count(kSpeed) && !(values[kSpeed + 1] > 0))
      throw std::invalid_argument(where(lineno, fmt.columns.at(kSpeed).column) + ": speed must be positive (drive "
                                  "running); cut the file to the running drive");
    r.t_s.push_back(time);
    for (const auto& [key, j] : col)
      if (key != kTimeKey) r.channel(key).push_back(values[key + 1]);
  }
  const std::size_t n = r.size();
  if (rows > 0 && missing > fmt.max_missing_fraction * rows) {
    std::ostringstream m;
    m << name << ": " << missing << " of " << rows << " rows lack a mapped value (first at line " << first_missing
      << "); more than " << 100 * fmt.max_missing_fraction << " % missing is not a usable recording";
    throw std::invalid_argument(m.str());
  }
  if (n < fmt.min_rows) {
    std::ostringstream m;
    m << name << ":" << lineno << ": only " << n << " usable data rows";
    if (missing) m << " (" << missing << " skipped for missing values, first at line " << first_missing << ")";
    m << ", at least " << fmt.min_rows << " needed";
    throw std::invalid_argument(m.str());
  }
  if (!col.count(kSpeed)) {
    if (!(fmt.setpoint_rad_s > 0))
      throw std::invalid_argument(name + ": no speed column in the map and no drive set point; map speed=COLUMN[rpm|"
                                  "rad/s|Hz] or give the set point (diagnose --setpoint-rpm)");
    r.speed_rad_s.assign(n, fmt.setpoint_rad_s);
    std::ostringstream m;
    m << "no speed column: the drive set point " << fmt.setpoint_rad_s / u::rpm << " rpm stands for it";
    r.notes.push_back(m.str());
  }
  r.resolution = fmt.resolution;
  std::ostringstream m;
  m << "read " << n << " rows";
  if (unit_row) m << "; unit row at line " << unit_row << " skipped";
  if (missing) m << "; " << missing << " row(s) with a missing value skipped, first at line " << first_missing;
  r.notes.insert(r.notes.begin(), m.str());
  // Sampling: any step is fine for the least-squares harmonics; gaps are reported.
  const double dt = r.sample_dt_s();
  std::size_t gaps = 0;
  double missing_s = 0, largest = 0, at = 0;
  for (std::size_t i = 1; i < n; ++i) {
    const double step = r.t_s[i] - r.t_s[i - 1];
    if (step > 1.5 * dt) {
      ++gaps;
      missing_s += step - dt;
      if (step > largest) largest = step, at = r.t_s[i - 1];
    }
  }
  std::ostringstream s;
  s << "median step " << dt << " s (" << 1.0 / dt << " Hz)";
  if (gaps)
    s << "; " << gaps << " gap(s) longer than 1.5 steps, " << missing_s << " s missing in all, the largest "
      << largest << " s after t = " << at << " s (fitted as they are: least-squares harmonics need no uniform step)";
  r.notes.push_back(s.str());
  check_consistent(r);
  return r;
}

Recording read_plant_export(const std::string& path, const PlantFormat& format) {
  std::ifstream f(path);
  if (!f) throw std::invalid_argument(path + ": cannot open recording");
  std::stringstream ss;
  ss << f.rdbuf();
  return parse_plant_export(ss.str(), path, format);
}

void write_plant_export(const Recording& r, const std::string& path, const PlantFormat& fmt,
                        const std::vector<std::size_t>& missing_rows) {
  check_consistent(r);
  if (fmt.delimiter == fmt.decimal) throw std::invalid_argument(path + ": delimiter and decimal separator must differ");
  for (const auto& [key, spec] : fmt.columns)
    if (key != kTimeKey && !r.has(key))
      throw std::invalid_argument(path + ": the recording has no " + kChannelNames[key] + " for column '" +
                                  spec.column + "'");
  std::ofstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot write");
  bool first = true;
  for (const auto& [key, spec] : fmt.columns) {
    f << (first ? "" : std::string(1, fmt.delimiter)) << spec.column << "[" << spec.unit << "]";
    first = false;
  }
  f << "\n";
  std::vector<bool> missing(r.size(), false);
  for (std::size_t i : missing_rows)
    if (i < r.size()) missing[i] = true;
  auto cell = [&](double v) {
    std::ostringstream o;
    o << std::setprecision(12) << v;
    std::string s = o.str();
    if (fmt.decimal == ',') std::replace(s.begin(), s.end(), '.', ',');
    return s;
  };
  for (std::size_t i = 0; i < r.size(); ++i) {
    first = true;
    for (const auto& [key, spec] : fmt.columns) {
      if (!first) f << fmt.delimiter;
      first = false;
      const double si = key == kTimeKey ? r.t_s[i] : r.channel(key)[i];
      if (missing[i] && key != kTimeKey) {
        f << "NaN";
        continue;
      }
      double v = si / spec.to_si;
      const double q = key == kTimeKey ? 0.0 : fmt.resolution[key] / spec.to_si;
      if (q > 0) v = std::round(v / q) * q;
      f << cell(v);
    }
    f << "\n";
  }
  if (!f) throw std::runtime_error(path + ": write failed");
}

}  // namespace analysis
