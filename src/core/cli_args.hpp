#pragma once
// Command-line walking for the tools: `--flag value` pairs with checked numbers, so that every tool says
// the same thing about a missing value or a number out of range.
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace core {

class CliArgs {
 public:
  CliArgs(int argc, char** argv) : argc_(argc), argv_(argv) {}
  bool next() { return ++i_ < argc_; }           // advances to the next flag
  std::string flag() const { return argv_[i_]; }
  std::string value() {                          // the flag's value
    if (i_ + 1 >= argc_) throw std::invalid_argument(flag() + " needs a value");
    return argv_[++i_];
  }
  double number(double lo, double hi) {          // the flag's value as a number in [lo, hi]
    const std::string f = flag(), v = value();
    char* end = nullptr;
    const double x = std::strtod(v.c_str(), &end);
    if (v.empty() || !end || *end || !(x >= lo && x <= hi))
      throw std::invalid_argument(f + " " + v + ": accepted a number in [" + std::to_string(lo) + ", " +
                                  std::to_string(hi) + "]");
    return x;
  }
  long integer(long lo, long hi) {               // the flag's value as a whole number in [lo, hi]
    const std::string f = flag(), v = value();
    char* end = nullptr;
    const long n = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || !end || *end || n < lo || n > hi)
      throw std::invalid_argument(f + " " + v + ": accepted a whole number in [" + std::to_string(lo) + ", " +
                                  std::to_string(hi) + "]");
    return n;
  }

 private:
  int argc_;
  char** argv_;
  int i_ = 0;
};

}  // namespace core
