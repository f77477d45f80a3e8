// The bed that refills the opened gap as its rock falls (chamber/bed_refill.hpp), its gap-slice form and the fit of its
// length (chamber/refill_fit.hpp), and the law in the flow model: against the closed forms of its origin, its limits
// (at once: the hysteretic law; never: the sprung-back bed), the slice's loop loss, and a resume bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "../common/coaxial_liners.hpp"
#include "../common/flow_params.hpp"
#include "chamber/bed_refill.hpp"
#include "chamber/flow_config.hpp"
#include "chamber/flow_model.hpp"
#include "chamber/refill_fit.hpp"

namespace {

constexpr double kE = 18e6, kN = 2.87, kRebound = 0.1, kG = 9.81;

// Loads the bed from u_from to u_to in n steps of h (either way); returns the last pressure.
double ramp(mbd::BedCell& c, chamber::BedRefill& r, double d, double u_from, double u_to, int n, double h) {
  double p = 0;
  for (int i = 1; i <= n; ++i) p = chamber::bed_refilling(c, r, u_from + (u_to - u_from) * i / n, h, kE, kN, kRebound, d, kG).p;
  return p;
}

chamber::FlowMaterial material() {
  chamber::FlowMaterial m;
  m.modulus_Pa = kE, m.exponent = kN, m.rebound = kRebound, m.loose_fraction = 0.47, m.solid_density = 2600;
  m.max_compression = 0.53;
  return m;
}

}  // namespace

// Pressed to 0.3, released (the unloading branch reaches 0 at er = 0.3 - rebound 0.3), the gap opened to u 0.05 and
// closed again: the liner meets the bed at u0 = low + exp(-g t^2 / (2 d)) (er - low), t the time since the release,
// and presses it along a virgin curve from there, E (u - u0)^n.
TEST(BedRefill, TheLinerMeetsTheBedWhereItHasRefilled) {
  const double d = 0.015, h = 1e-5;
  mbd::BedCell c;
  chamber::BedRefill r;
  EXPECT_GT(ramp(c, r, d, 0.0, 0.3, 1000, h), 0.0);
  EXPECT_FALSE(r.open);
  const double er = 0.3 - kRebound * 0.3;
  ramp(c, r, d, 0.3, 0.05, 2500, h);  // released on the way down
  ASSERT_TRUE(r.open);
  EXPECT_NEAR(r.released, er, 1e-12);
  EXPECT_NEAR(r.low, 0.05, 1e-12);
  const double t_released = r.t;  // the time spent below er so far
  EXPECT_GT(t_released, 0.0);
  // closing slowly: while below the refilled origin, nothing; past it, the virgin curve from the origin at contact
  double t = t_released, p = 0, u0_contact = -1, u = 0.05;
  for (int i = 1; i <= 40000 && u0_contact < 0; ++i) {
    u = 0.05 + 0.25 * i / 40000.0;
    t += h;
    const double u0 = 0.05 + std::exp(-0.5 * kG * t * t / d) * (er - 0.05);
    p = chamber::bed_refilling(c, r, u, h, kE, kN, kRebound, d, kG).p;
    if (u <= u0) {
      ASSERT_EQ(p, 0.0) << "pressed before the liner met the bed, u " << u << " u0 " << u0;
      ASSERT_TRUE(r.open);
    } else {
      u0_contact = u0;
      EXPECT_FALSE(r.open);
      EXPECT_NEAR(p, kE * std::pow(u - u0, kN), 1e-9 * kE * std::pow(u - u0, kN));
    }
  }
  ASSERT_GT(u0_contact, 0.05 + 1e-6);  // met above the widest gap's compaction: the bed had not refilled it all
  ASSERT_LT(u0_contact, er);
  const double p_further = chamber::bed_refilling(c, r, u + 0.1, h, kE, kN, kRebound, d, kG).p;
  EXPECT_NEAR(p_further, kE * std::pow(u + 0.1 - u0_contact, kN), 1e-9 * p_further);
}

// Its limits: a refill length far shorter than the fall gives the hysteretic law (the next pressing from the widest
// gap's compaction); one far longer, a bed that stays where it sprang back to (the next pressing from er).
TEST(BedRefill, AtOnceItIsTheHystereticLawAndNeverItStaysWhereItSprangBack) {
  const double h = 1e-4;
  auto path = [](int i) { return 0.2 * (1.0 - std::cos(2.0 * M_PI * i / 1500.0)) / 2.0; };  // three loops of 0.15 s
  mbd::BedCell a, b;
  chamber::BedRefill r;
  for (int i = 1; i <= 4500; ++i) {
    const double pa = mbd::bed_hysteretic(a, path(i), kE, kN, kRebound).p;
    const double pb = chamber::bed_refilling(b, r, path(i), h, kE, kN, kRebound, 1e-12, kG).p;
    ASSERT_NEAR(pb, pa, 1e-9 * kE) << "step " << i;
  }
  mbd::BedCell c;
  chamber::BedRefill never;
  double peak2 = 0;
  for (int i = 1; i <= 3000; ++i) {
    const double p = chamber::bed_refilling(c, never, path(i), h, kE, kN, kRebound, 1e9, kG).p;
    if (i > 1500) peak2 = std::max(peak2, p);
  }
  const double er = 0.2 - kRebound * 0.2;  // the reload's virgin curve from er to the peak 0.2
  EXPECT_NEAR(peak2, kE * std::pow(0.2 - er, kN), 1e-4 * kE * std::pow(0.2 - er, kN));
}

// The law on the slice's kinematics: refilled at once, every cycle is the hysteretic loop's loss from loose,
// (1 - rebound) E s^(n+1) / (n + 1) per loose volume; with a refill length the reloads cost less the faster the plate
// (less time to refill), the first pressing the same; the reload ratio returns to 1 for a length far beyond the fall.
TEST(BedRefill, OnTheSliceTheReloadsCostLessTheFasterThePlate) {
  chamber::FlowMaterial m = material();
  const double gap = 0.12, stroke = 0.015, s = stroke / gap, rho0 = m.loose_fraction * m.solid_density;
  const double loss = (1 - kRebound) * kE * std::pow(s, kN + 1) / (kN + 1) / rho0;
  for (double w : chamber::refill_slice_work(m, gap, stroke, 400.0 / 60.0, 3, kG)) EXPECT_NEAR(w, loss, 1e-4 * loss);
  m.refill_length_m = 0.015;
  const auto w300 = chamber::refill_slice_work(m, gap, stroke, 5.0, 4, kG);
  const auto w400 = chamber::refill_slice_work(m, gap, stroke, 400.0 / 60.0, 4, kG);
  const auto w600 = chamber::refill_slice_work(m, gap, stroke, 10.0, 4, kG);
  EXPECT_NEAR(w400[0], loss, 1e-4 * loss);  // the first pressing starts loose at every speed
  EXPECT_NEAR(w600[0], loss, 1e-4 * loss);
  EXPECT_LE(w300[2], loss * (1 + 1e-4));
  EXPECT_GT(w300[2], w400[2]);
  EXPECT_GT(w400[2], w600[2]);
  EXPECT_LT(w600[2], 0.95 * loss);
  const double r600 = chamber::refill_reload_ratio(m, gap, stroke, 4, kG, 600, 400);
  EXPECT_NEAR(r600, (w600[1] + w600[2] + w600[3]) / (w400[1] + w400[2] + w400[3]), 1e-12);
  m.refill_length_m = 1e6;
  EXPECT_NEAR(chamber::refill_reload_ratio(m, gap, stroke, 4, kG, 600, 400), 1.0, 1e-3);
}

// The fit recovers the length that made the data, from the speeds it is given only; refuses data without a pair.
TEST(BedRefill, TheFitRecoversTheLengthThatMadeTheSlicesReloads) {
  chamber::FlowMaterial m = material();
  const double gap = 0.12, stroke = 0.015;
  chamber::FlowMaterial truth = m;
  truth.refill_length_m = 0.012;
  std::vector<chamber::SliceReload> data;
  for (int pouring : {1, 2}) {
    const double scale = pouring == 1 ? 2.0 : 3.0;  // each pouring its own level: only the ratios count
    data.push_back({pouring, 400, scale});
    for (double rpm : {300.0, 500.0})
      data.push_back({pouring, rpm, scale * chamber::refill_reload_ratio(truth, gap, stroke, 5, kG, rpm, 400)});
  }
  data.push_back({1, 600, 1e-3});  // a speed left out of the fit does not move it
  const auto fit = chamber::fit_refill_length(m, gap, stroke, 5, kG, data, 400, {300, 500});
  EXPECT_NEAR(fit.length_m, 0.012, 1e-4);
  EXPECT_EQ(fit.ratios, 4);
  EXPECT_LT(fit.rms_log, 1e-3);
  try {
    chamber::fit_refill_length(m, gap, stroke, 5, kG, {{1, 400, 2.0}, {2, 500, 1.0}}, 400, {500});
    ADD_FAILURE() << "a fit without a pouring at both speeds was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("400"), std::string::npos) << e.what();
  }
}

// In the flow model: a run with the refill law resumes bit for bit through a checkpoint (its state saved), books less
// crushing work than refilling at once on the same path, and a bad length is refused by name (the config key itself:
// test_config_schema.cpp's checks of every key).
TEST(BedRefill, TheFlowModelsRefillingBedResumesBitForBitAndPressesLess) {
  const core::Profile mantle = test_liners::gyp_mantle(), concave = test_liners::gyp_concave();
  chamber::FlowParams p = test_liners::cone_chamber_params();
  p.material.refill_length_m = 0.03;
  chamber::FlowModel m(p, mantle, concave);
  chamber::FlowParams at_once = p;
  at_once.material.refill_length_m = 0;
  chamber::FlowModel ref(at_once, mantle, concave);
  test_liners::nutate({&m, &ref}, 0, 1500);
  const auto resumed = test_liners::resumed(m, p, mantle, concave);
  test_liners::nutate({&m, resumed.get(), &ref}, 1500, 3000);
  EXPECT_GT(m.events(), 100);
  EXPECT_EQ(m.crushing_energy_J(), resumed->crushing_energy_J());
  EXPECT_EQ(m.discharged_by_class(), resumed->discharged_by_class());
  EXPECT_EQ(m.mass_kg(), resumed->mass_kg());
  EXPECT_NEAR(m.fed_kg(), m.mass_kg() + m.discharged_kg(), 1e-9 * m.fed_kg());
  EXPECT_LT(m.crushing_energy_J(), ref.crushing_energy_J());
  EXPECT_EQ(chamber::law_fingerprint(p.material), (std::vector<double>{-6.0, 0.03}));
  // not with the compaction memory, and not negative: refused by name
  auto bad = p;
  bad.compaction_memory = true;
  try {
    chamber::FlowModel refused(bad, mantle, concave);
    ADD_FAILURE() << "refill with compaction_memory was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("refill.length_mm"), std::string::npos) << e.what();
  }
  bad = p;
  bad.material.refill_length_m = -1e-3;
  EXPECT_THROW({ chamber::FlowModel refused(bad, mantle, concave); }, std::invalid_argument);
}
