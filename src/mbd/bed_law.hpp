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
  if (e >= c.emax && e > c.e0 && rebound > 0) {  // virgin loading: the branch below at e = emax, one power instead of two
    c.emax = e;
    const double D = e - c.e0, p = E * bed_power(D, n);
    return {p, p * rebound * D / (n + 1.0)};
  }
  if (e >= c.emax) c.emax = e;
  const double D = c.emax - c.e0, er = c.emax - rebound * D;
  if (e <= er || D <= 0) {
    c.e0 = c.emax = e;
    return {};
  }
  const double p = E * bed_power(D, n) * bed_power((e - er) / (rebound * D), n);
  return {p, p * (e - er) / (n + 1.0)};
}

// Whether the step from `before` to `after` ended a loop of bed_hysteretic: a compression had started and the
// unloading branch reached 0 (the gap opened past the rebound), so the memory was reset.
inline bool bed_loop_ended(const BedCell& before, const BedCell& after) {
  return before.emax > before.e0 && after.e0 == after.emax;
}

// Memory of the rock in one flow-model cell (chamber/flow_model.hpp): the compaction c, measured from the loose
// pour, that it has been pressed to since it was poured; c at the start of the present pressing; whether pressed.
struct CompactedBed {
  double c = 0, c_start = 0;
  bool pressed = false;
};

// Pre-compacted bed: rock pressed, released and pressed again without being re-poured keeps its compaction
// (Evertsson 2000: the bed only loosens when it falls). e is the compaction from the loose pour. Beyond c the virgin
// curve p = E e^n of the piston-die test; below c the unloading-reloading branch, which recovers `rebound` of c:
// p = E c^n ((e - er) / (rebound c))^n, er = (1 - rebound) c; below er the liner has left the rock, p = 0, and the
// rock keeps c. So a pressed-and-released bed reloads stiffly, without loss, up to c; a loop that takes it from c0
// to c1 loses (1 - rebound) E (c1^(n+1) - c0^(n+1)) / (n + 1). Only re-pouring loosens it (mix_compaction).
// Where a bed compacted to b.c is released (p = 0 at and below it): the compaction it springs back to.
inline double released_compaction(const CompactedBed& b, double rebound) { return (1.0 - rebound) * b.c; }

inline BedPressure bed_compacted(CompactedBed& b, double e, double E, double n, double rebound) {
  const double er = released_compaction(b, rebound);
  if (e <= er || e <= 0) {
    b.pressed = false;
    return {};
  }
  if (!b.pressed) b.pressed = true, b.c_start = b.c;
  if (e >= b.c) {
    b.c = e;
    const double p = E * bed_power(e, n);
    return {p, p * rebound * e / (n + 1.0)};
  }
  const double p = E * bed_power(b.c, n) * bed_power((e - er) / (rebound * b.c), n);
  return {p, p * (e - er) / (n + 1.0)};
}

// dm kg of rock at compaction c_in joins m kg at b.c: volumes add, m (1 - c) + dm (1 - c_in) loose-referenced, so
// the mixture's compaction is the mass-weighted mean (loose feed or fallen, re-poured rock: c_in = 0).
inline void mix_compaction(CompactedBed& b, double m, double dm, double c_in) {
  if (m + dm <= 0) return;
  b.c = (m * b.c + dm * c_in) / (m + dm);
  b.c_start = (m * b.c_start + dm * c_in) / (m + dm);
}

}  // namespace mbd
