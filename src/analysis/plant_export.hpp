#pragma once
// Plant (DAQ) exports as recordings: a column map with units, any delimiter and decimal separator,
// extra columns, any sample rate, non-uniform steps and gaps, rows with missing values, channels the
// plant does not log, test-point accelerations instead of displacements, logger resolutions.
//
//   --columns t=time[s],x=disp_x[mm],y=disp_y[mm],power=P[kW],speed=n[rpm]
//   --delimiter ';'   --decimal ,   --resolution x=0.01mm,power=0.1kW
//
// Values are converted to SI once, here (DESIGN.md: SI inside).
#include <array>
#include <map>
#include <string>
#include <vector>

#include "analysis/recording.hpp"

namespace analysis {

// The items of a comma list, each trimmed; a comma inside [...] does not split (a unit such as [1/min]).
std::vector<std::string> split_items(const std::string& spec);

constexpr int kTimeKey = -1;  // map key of the time column; channels use their Channel index

struct ColumnSpec {
  std::string column;  // header name
  std::string unit;    // as written, e.g. "mm"
  double to_si = 1.0;  // multiplies the file's value
};

struct PlantFormat {
  std::map<int, ColumnSpec> columns;            // kTimeKey and Channel -> column
  char delimiter = ',';
  char decimal = '.';
  std::array<double, kNumChannels> resolution{};  // SI; 0 = estimated from the data
  double setpoint_rad_s = 0;   // drive set point filling the speed channel when the file has none
  std::size_t min_rows = 50;
  double max_missing_fraction = 0.5;  // rows with a missing value: more than this share is unusable
};

// Key names and units accepted (for messages and --help).
std::string accepted_column_keys();
// "KEY=NAME[UNIT],..." -> columns; throws std::invalid_argument naming the item and what is accepted.
std::map<int, ColumnSpec> parse_column_map(const std::string& spec);
// Factor to SI of `unit` for the quantity of `key`; throws naming the key, the unit and the accepted units.
double unit_to_si(int key, const std::string& unit);
// "," ";" "tab" "|" (or the character itself) -> the character.
char parse_delimiter(const std::string& s);
char parse_decimal(const std::string& s);
// "KEY=VALUE[UNIT],..." (no unit: the column's unit from the map, else SI) -> format.resolution.
void parse_resolutions(const std::string& spec, PlantFormat& format);

// Reads an export. Rows with a missing mapped value (empty, NaN, NA, -, inf) are skipped and reported
// in Recording::notes (count and first line), as are gaps in time; a unit row right after the header is
// skipped. Refused, naming file, line and column: a mapped column missing from the header, a value that is
// not a number (with a hint when delimiter or decimal separator look wrong), time not increasing, a
// non-positive speed, fewer than min_rows usable rows, more than max_missing_fraction rows skipped.
Recording parse_plant_export(const std::string& text, const std::string& name, const PlantFormat& format);
Recording read_plant_export(const std::string& path, const PlantFormat& format);

// Writes a recording as a plant export: the mapped columns in their units, each value rounded to its
// channel's resolution (format.resolution), rows listed in missing_rows written as NaN.
void write_plant_export(const Recording& r, const std::string& path, const PlantFormat& format,
                        const std::vector<std::size_t>& missing_rows = {});

}  // namespace analysis
