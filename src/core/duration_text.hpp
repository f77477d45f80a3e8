#pragma once
// A wall time for people: "3 d 4 h", "5 h 12 min", "12 min 5 s", "45 s" (two units at most), "unknown" when not
// finite or negative.
#include <cmath>
#include <cstdio>
#include <string>

namespace core {

inline std::string duration_text(double s) {
  if (!std::isfinite(s) || s < 0) return "unknown";
  const long long t = std::llround(s);
  const long long d = t / 86400, h = t % 86400 / 3600, m = t % 3600 / 60, sec = t % 60;
  char b[48];
  if (d > 0) std::snprintf(b, sizeof b, "%lld d %lld h", d, h);
  else if (h > 0) std::snprintf(b, sizeof b, "%lld h %lld min", h, m);
  else if (m > 0) std::snprintf(b, sizeof b, "%lld min %lld s", m, sec);
  else std::snprintf(b, sizeof b, "%lld s", sec);
  return b;
}

}  // namespace core
