#pragma once
// The bed refills the opened gap as its rock falls (the gap slice, gap_slice.hpp; src/chamber/README.md).
//
// The hysteretic law alone (mbd::bed_hysteretic) lets a released bed fill the opening gap at once, so its next pressing
// starts from the widest gap's compaction. Pressed across gravity, the bed fills the room by slumping into it, which
// takes time: released at compaction u_r, after t seconds it has filled the share
//   phi(t) = 1 - exp(-g t^2 / (2 d))
// of the room the gap has opened since (its free fall g t^2 / 2 over the refill length d), so the liner next meets it
// at u0 = low + (1 - phi) (u_r - low), low the least compaction the gap has given it since the release, and the next
// virgin curve starts there. d -> 0: at once (the hysteretic law); d -> infinity: it stays where it sprang back to.
// u is the pressure law's compaction coordinate (bed_compaction.hpp). SI.
#include <algorithm>
#include <cmath>

#include "mbd/bed_law.hpp"

namespace chamber {

struct BedRefill {
  bool open = false;    // released and not yet met again by the liner
  double released = 0;  // u where the last pressing released the bed
  double low = 0;       // the least u the gap has given it since
  double t = 0;         // s since the release
};

// The share of the room opened since the release that a bed has filled after t seconds (d = 0: all of it).
inline double refill_share(double t, double length_m, double gravity) {
  return length_m > 0 ? 1.0 - std::exp(-0.5 * gravity * t * t / length_m) : 1.0;
}

// Where the liner meets the released bed now.
inline double refill_origin(const BedRefill& r, double length_m, double gravity) {
  return r.low + (1.0 - refill_share(r.t, length_m, gravity)) * (r.released - r.low);
}

// The hysteretic bed that refills as its rock falls: the pressure at compaction u after a step of h seconds. While
// released, the liner touches nothing until u reaches the refilled bed's origin; a release starts the clock.
// length_m 0: the hysteretic law itself (r untouched).
inline mbd::BedPressure bed_refilling(mbd::BedCell& c, BedRefill& r, double u, double h, double E, double n,
                                      double rebound, double length_m, double gravity) {
  if (length_m <= 0) return mbd::bed_hysteretic(c, u, E, n, rebound);
  if (r.open) {
    r.t += h;
    if (u <= r.low) {  // at the least compaction since the release: below any origin (low <= u0), no exp needed
      r.low = u;
      return {};
    }
    const double u0 = refill_origin(r, length_m, gravity);
    if (u <= u0) return {};
    r.open = false;
    c.e0 = c.emax = u0;
  }
  const mbd::BedCell before = c;
  const mbd::BedPressure p = mbd::bed_hysteretic(c, u, E, n, rebound);
  if (mbd::bed_loop_ended(before, c))  // released in this step, where the unloading branch reached 0
    r = {true, before.emax - rebound * (before.emax - before.e0), u, 0.0};
  return p;
}

}  // namespace chamber
