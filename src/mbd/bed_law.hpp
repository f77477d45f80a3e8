#pragma once
// Pressure laws of the equivalent material bed for one mantle patch; strain e = 1 - gap / reference gap.
#include <cmath>

namespace mbd {

// Memory of the hysteretic bed of one patch: e0 where the material was filled in, emax the largest strain since.
struct BedCell {
  double e0 = 0, emax = 0;
};

struct BedPressure {
  double p = 0;       // Pa
  double stored = 0;  // recoverable energy per unit area and reference gap (Pa)
};

inline double bed_power(double x, double n) { return n == 1.5 ? x * std::sqrt(x) : std::pow(x, n); }

// Elastic bed p = E e^n.
inline BedPressure bed_elastic(double e, double E, double n) {
  const double p = E * bed_power(e, n);
  return {p, p * e / (n + 1.0)};
}

// Rate-independent crushing bed. Virgin loading p = E (e - e0)^n; unloading from emax recovers the fraction
// `rebound` of the compression D = emax - e0 along p = E D^n ((e - er) / (rebound D))^n, er = emax - rebound D
// (continuous at emax; reloading retraces it without loss); below er the gap has opened past the rebound
// and fresh feed fills it (e0 = emax = e). Loss per full loop: (1 - rebound) E D^(n+1) / (n + 1).
inline BedPressure bed_hysteretic(BedCell& c, double e, double E, double n, double rebound) {
  if (e >= c.emax) c.emax = e;
  const double D = c.emax - c.e0, er = c.emax - rebound * D;
  if (e <= er || D <= 0) {
    c.e0 = c.emax = e;
    return {};
  }
  const double p = E * bed_power(D, n) * bed_power((e - er) / (rebound * D), n);
  return {p, p * (e - er) / (n + 1.0)};
}

}  // namespace mbd
