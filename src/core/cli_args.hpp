#pragma once
// Command-line walking for the tools: `--flag value` pairs with checked numbers, so that every tool says
// the same thing about a missing value or a number out of range. parse_number/parse_integer are the one check of
// a number given as text (flags, ROS parameters): the whole text a finite number in [lo, hi], else an
// std::invalid_argument naming the flag, the value and what is accepted.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace core {

inline std::string number_text(double x) {  // 1e+09 -> "1e+09", 0.1 -> "0.1"
  char b[32];
  std::snprintf(b, sizeof b, "%g", x);
  return b;
}

inline double parse_number(const std::string& flag, const std::string& v, double lo, double hi,
                           const std::string& unit = "") {
  char* end = nullptr;
  const double x = std::strtod(v.c_str(), &end);
  if (v.empty() || !end || *end || !std::isfinite(x) || !(x >= lo && x <= hi))
    throw std::invalid_argument(flag + " " + (v.empty() ? "''" : v) + ": accepted a number in [" + number_text(lo) +
                                ", " + number_text(hi) + "]" + (unit.empty() ? "" : " " + unit));
  return x;
}

inline long parse_integer(const std::string& flag, const std::string& v, long lo, long hi) {
  char* end = nullptr;
  errno = 0;
  const long n = std::strtol(v.c_str(), &end, 10);
  if (v.empty() || !end || *end || errno == ERANGE || n < lo || n > hi)
    throw std::invalid_argument(flag + " " + (v.empty() ? "''" : v) + ": accepted a whole number in [" +
                                std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return n;
}

class CliArgs {
 public:
  CliArgs(int argc, char** argv) : argc_(argc), argv_(argv) {}
  bool next() { return ++i_ < argc_; }           // advances to the next flag
  std::string flag() const { return argv_[i_]; }
  std::string value() {                          // the flag's value
    if (i_ + 1 >= argc_) throw std::invalid_argument(flag() + " needs a value");
    return argv_[++i_];
  }
  double number(double lo, double hi, const std::string& unit = "") {  // the flag's value as a number in [lo, hi]
    const std::string f = flag();
    return parse_number(f, value(), lo, hi, unit);
  }
  long integer(long lo, long hi) {               // the flag's value as a whole number in [lo, hi]
    const std::string f = flag();
    return parse_integer(f, value(), lo, hi);
  }
  std::vector<std::string> list() {              // the flag's value split at commas
    std::vector<std::string> items;
    std::stringstream text(value());
    for (std::string item; std::getline(text, item, ',');) items.push_back(item);
    return items;
  }
  std::vector<double> numbers(double lo, double hi, const std::string& unit = "") {  // a comma list, each in [lo, hi]
    const std::string f = flag();
    std::vector<double> xs;
    for (const std::string& item : list()) xs.push_back(parse_number(f, item, lo, hi, unit));
    return xs;
  }

 private:
  int argc_;
  char** argv_;
  int i_ = 0;
};

}  // namespace core
