#pragma once
// Deterministic random numbers for packing and rock shapes.
// std::mt19937_64 is fully specified by the standard; the distributions of <random> are not
// (libstdc++ and libc++ differ), so uniform and normal deviates are derived here by hand.
// Same seed -> same rock on every platform.
#include <cmath>
#include <cstdint>
#include <random>
#include <sstream>
#include <string>

namespace rocks {

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : gen_(seed) {}
  // Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(gen_() >> 11) * (1.0 / 9007199254740992.0); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Standard normal by Box-Muller (both deviates used).
  double normal() {
    if (have_spare_) {
      have_spare_ = false;
      return spare_;
    }
    double u1 = 0.0;
    do u1 = uniform(); while (u1 <= 0.0);
    const double u2 = uniform();
    const double m = std::sqrt(-2.0 * std::log(u1));
    spare_ = m * std::sin(6.283185307179586 * u2);
    have_spare_ = true;
    return m * std::cos(6.283185307179586 * u2);
  }
  std::uint64_t next() { return gen_(); }
  // Complete generator state as text (the standard's stream format), for checkpoints.
  std::string state() const {
    std::ostringstream os;
    os << gen_ << ' ' << have_spare_ << ' ';
    os.write(reinterpret_cast<const char*>(&spare_), sizeof spare_);
    return os.str();
  }
  // Restores a state() string; returns false if it cannot be parsed.
  bool set_state(const std::string& s) {
    std::istringstream is(s);
    std::mt19937_64 g;
    bool spare_flag = false;
    double spare = 0.0;
    if (!(is >> g >> spare_flag)) return false;
    is.get();
    if (!is.read(reinterpret_cast<char*>(&spare), sizeof spare)) return false;
    gen_ = g;
    have_spare_ = spare_flag;
    spare_ = spare;
    return true;
  }

 private:
  std::mt19937_64 gen_;
  double spare_ = 0.0;
  bool have_spare_ = false;
};

}  // namespace rocks
