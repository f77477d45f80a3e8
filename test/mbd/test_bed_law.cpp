// Bed pressure laws of one patch (bed_law.hpp) against their closed forms.
#include <gtest/gtest.h>

#include <cmath>

#include "mbd/bed_law.hpp"

namespace {

constexpr double kE = 8e6, kN = 1.5;

// Work per unit area and reference gap, integral of p de, along a strain path (trapezoids); p_at(e) steps a law.
template <class Law>
double work_of(Law p_at, double e_from, double e_to, int steps = 20000) {
  double w = 0, e_prev = e_from, p_prev = p_at(e_from);
  for (int i = 1; i <= steps; ++i) {
    const double e = e_from + (e_to - e_from) * i / steps;
    const double p = p_at(e);
    w += 0.5 * (p + p_prev) * (e - e_prev);
    e_prev = e, p_prev = p;
  }
  return w;
}

double work_along(mbd::BedCell& c, double e_from, double e_to, double rebound) {
  return work_of([&](double e) { return mbd::bed_hysteretic(c, e, kE, kN, rebound).p; }, e_from, e_to);
}

TEST(BedLaw, ElasticStoresItsWork) {
  const auto b = mbd::bed_elastic(0.3, kE, kN);
  EXPECT_NEAR(b.p, kE * std::pow(0.3, 1.5), 1e-6);
  EXPECT_NEAR(b.stored, kE * std::pow(0.3, 2.5) / 2.5, 1e-6);
}

TEST(BedLaw, HystereticLoopLosesOneMinusReboundOfTheLoadingWork) {
  for (double rebound : {0.14, 0.5, 0.9}) {
    mbd::BedCell c;
    const double emax = 0.4;
    const double w_load = work_along(c, 0.0, emax, rebound);
    EXPECT_NEAR(w_load, kE * std::pow(emax, 2.5) / 2.5, 1e-4 * w_load) << "virgin curve E e^n";
    const double stored = mbd::bed_hysteretic(c, emax, kE, kN, rebound).stored;
    EXPECT_NEAR(stored, rebound * w_load, 1e-4 * w_load) << "recoverable part";
    mbd::BedCell loaded = c;
    const double w_unload = -work_along(c, emax, 0.0, rebound);
    EXPECT_NEAR(w_unload, rebound * w_load, 1e-4 * w_load) << "rebound " << rebound;
    // Unloading ends at er = (1 - rebound) emax: loaded just above, slack (and refilled) just below.
    const double er = (1 - rebound) * emax;
    EXPECT_GT(mbd::bed_hysteretic(loaded, er + 1e-6, kE, kN, rebound).p, 0.0);
    EXPECT_EQ(mbd::bed_hysteretic(loaded, er - 1e-6, kE, kN, rebound).p, 0.0);
    EXPECT_NEAR(loaded.e0, er - 1e-6, 1e-12);
    // Refilled at the most open strain (0 here), so reloading follows the virgin curve from 0 again.
    EXPECT_NEAR(c.e0, 0.0, 1e-12);
    EXPECT_NEAR(mbd::bed_hysteretic(c, 0.2, kE, kN, rebound).p, kE * std::pow(0.2, 1.5), 1e-6 * kE);
  }
}

TEST(BedLaw, PartialUnloadingReloadsWithoutLoss) {
  const double rebound = 0.3;
  mbd::BedCell c;
  work_along(c, 0.0, 0.4, rebound);
  const double p_top = mbd::bed_hysteretic(c, 0.4, kE, kN, rebound).p;
  // Down to halfway along the rebound and back: the same branch both ways.
  const double e_mid = 0.4 - 0.5 * rebound * 0.4;
  const double w_down = work_along(c, 0.4, e_mid, rebound), w_up = work_along(c, e_mid, 0.4, rebound);
  EXPECT_NEAR(w_down + w_up, 0.0, 1e-6 * std::fabs(w_up));
  EXPECT_NEAR(mbd::bed_hysteretic(c, 0.4, kE, kN, rebound).p, p_top, 1e-6 * p_top);
  // Beyond emax the virgin curve continues from the original e0.
  EXPECT_NEAR(mbd::bed_hysteretic(c, 0.5, kE, kN, rebound).p, kE * std::pow(0.5, 1.5), 1e-6 * kE);
}

TEST(BedLaw, RefillStartsAVirginCurveAtTheOpenGap) {
  const double rebound = 0.2;
  mbd::BedCell c;
  work_along(c, 0.0, 0.5, rebound);
  work_along(c, 0.5, 0.1, rebound);  // past er = 0.4: slack, refilled at 0.1
  EXPECT_NEAR(c.e0, 0.1, 1e-9);
  EXPECT_NEAR(mbd::bed_hysteretic(c, 0.3, kE, kN, rebound).p, kE * std::pow(0.2, 1.5), 1e-6 * kE);
}

// The same per unit loose volume for the compacted bed.
double compacted_work(mbd::CompactedBed& b, double e_from, double e_to, double rebound) {
  return work_of([&](double e) { return mbd::bed_compacted(b, e, kE, kN, rebound).p; }, e_from, e_to);
}

// A bed pressed to 0.3, released until the liner leaves it, pressed again: it keeps its compaction, so the second
// pressing meets E 0.3^n at 0.3 (the hysteretic law, which forgets it, meets nothing there), reloads without loss,
// and the loop to 0.4 loses (1 - rebound) E (0.4^(n+1) - 0.3^(n+1)) / (n + 1).
TEST(BedLaw, CompactedBedKeepsItsCompactionUntilRePoured) {
  const double rebound = 0.05;
  mbd::CompactedBed b;
  const double w1 = compacted_work(b, 0.0, 0.3, rebound);
  EXPECT_NEAR(w1, kE * std::pow(0.3, kN + 1) / (kN + 1), 1e-4 * w1) << "virgin curve from the loose pour";
  EXPECT_TRUE(b.pressed);
  EXPECT_NEAR(b.c_start, 0.0, 1e-15);
  compacted_work(b, 0.3, 0.1, rebound);  // released past er = 0.285: the liner has left the rock
  EXPECT_FALSE(b.pressed);
  EXPECT_NEAR(b.c, 0.3, 1e-12);
  EXPECT_EQ(mbd::bed_compacted(b, 0.28, kE, kN, rebound).p, 0.0);
  // Pressed again: stiff reloading branch, the full virgin pressure at 0.3.
  const double w_reload = compacted_work(b, 0.1, 0.3, rebound);
  EXPECT_NEAR(mbd::bed_compacted(b, 0.3, kE, kN, rebound).p, kE * std::pow(0.3, kN), 1e-9 * kE);
  EXPECT_NEAR(b.c_start, 0.3, 1e-12) << "this pressing started at the compaction already reached";
  EXPECT_NEAR(w_reload, rebound * w1, 2e-3 * w1) << "the recoverable part only";
  mbd::BedCell forgetting;  // the hysteretic law, which refills loose at every release
  work_along(forgetting, 0.0, 0.3, rebound);
  work_along(forgetting, 0.3, 0.1, rebound);
  EXPECT_NEAR(mbd::bed_hysteretic(forgetting, 0.3, kE, kN, rebound).p, kE * std::pow(0.2, kN), 1e-6 * kE);  // from 0.1
  // On to 0.4 and back to slack: the loop's loss.
  const double w_loop = w_reload + compacted_work(b, 0.3, 0.4, rebound) + compacted_work(b, 0.4, 0.0, rebound);
  const double loss = (1 - rebound) * kE * (std::pow(0.4, kN + 1) - std::pow(0.3, kN + 1)) / (kN + 1);
  EXPECT_NEAR(w_loop, loss, 1e-3 * loss);
  EXPECT_NEAR(b.c, 0.4, 1e-12);
  // Re-pouring: as much loose rock again (volumes add) halves the compaction; rock of the same compaction keeps it.
  mbd::mix_compaction(b, 2.0, 2.0, 0.0);
  EXPECT_NEAR(b.c, 0.2, 1e-12);
  const double volume = 2.0 * (1 - 0.4) + 2.0 * 1.0, mixture = 4.0 * (1 - b.c);  // loose-referenced volumes
  EXPECT_NEAR(volume, mixture, 1e-12);
  mbd::mix_compaction(b, 4.0, 1.0, 0.2);
  EXPECT_NEAR(b.c, 0.2, 1e-12);
}

}  // namespace

