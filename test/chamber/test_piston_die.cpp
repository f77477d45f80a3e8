// Virtual piston-die test and the flow-material fits (src/chamber/piston_die.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "chamber/flow_model.hpp"
#include "analysis/jackknife.hpp"
#include "chamber/piston_die.hpp"
#include "chamber/piston_die_record.hpp"
#include "mbd/bed_law.hpp"

using namespace chamber;

namespace {
std::vector<double> sieves_m() {
  std::vector<double> s;
  for (double mm : flow_sieves_mm()) s.push_back(mm * 1e-3);
  return s;
}
// The breakage a fit recovered from PSDs made with `truth` (rms misfit of the passing under 0.05 %).
void expect_breakage_recovered(const MaterialFit& m, const BreakageParams& truth) {
  EXPECT_LT(m.psd_rms_pct, 0.05);
  EXPECT_NEAR(m.material.breakage.s_c, truth.s_c, 0.01);
  EXPECT_NEAR(m.material.breakage.m, truth.m, 0.05);
  EXPECT_NEAR(m.material.breakage.q, truth.q, 0.05);
  EXPECT_NEAR(m.material.breakage.phi, truth.phi, 0.03);
  EXPECT_NEAR(m.material.breakage.gamma, truth.gamma, 0.1);
}
// The closed integral of p ds over one loop of mbd::bed_hysteretic itself, s from 0 to D and back in N steps each,
// its memory in the law's coordinate u(s).
double law_loop_loss(double E, double n, double rebound, double D, const CompactionScale& scale, int N) {
  mbd::BedCell c;
  std::vector<double> s, p;
  for (int k = 0; k <= N; ++k) s.push_back(D * k / N), p.push_back(mbd::bed_hysteretic(c, scale.u(s.back()), E, n, rebound).p);
  for (int k = N - 1; k >= 0; --k)
    s.push_back(D * k / N), p.push_back(mbd::bed_hysteretic(c, scale.u(s.back()), E, n, rebound).p);
  return path_integral(s, p);
}
}  // namespace

TEST(PistonDieFit, PowerLawReproducesSyntheticCurveExactly) {
  std::vector<double> s, p;
  for (int k = 1; k <= 40; ++k) s.push_back(0.01 * k), p.push_back(37.5e6 * std::pow(0.01 * k, 2.35));
  s.push_back(0.015), p.push_back(1e9);  // below s = 0.02: must be left out
  const PowerLawFit f = fit_power_law(s, p, 0.02);
  EXPECT_NEAR(f.modulus, 37.5e6, 37.5e6 * 1e-9);
  EXPECT_NEAR(f.exponent, 2.35, 1e-9);
  EXPECT_LT(f.rms_log, 1e-9);
  EXPECT_EQ(f.points, 38);
  EXPECT_THROW(fit_power_law({0.01, 0.5}, {1.0, 2.0}, 0.02), std::invalid_argument);
}

// Loops of mbd::bed_hysteretic itself (0 -> D -> back until p = 0): the closed integral is the documented loss,
// and fit_rebound recovers the rebound the loops were made with.
TEST(PistonDieFit, ReboundFitReproducesSyntheticHystereticLoops) {
  const double E = 60e6, n = 2.2, rebound = 0.23;
  std::vector<double> D{0.1, 0.2, 0.3}, loss;
  for (double d : D) {
    const double l = law_loop_loss(E, n, rebound, d, {}, 4000);
    EXPECT_NEAR(l, hysteretic_loop_loss(E, n, rebound, d), 1e-4 * hysteretic_loop_loss(E, n, rebound, d));
    loss.push_back(l);
  }
  double rms = -1;
  EXPECT_NEAR(fit_rebound(E, n, D, loss, &rms), rebound, 2e-4);
  EXPECT_GE(rms, 0.0);
  // other losses, another rebound: half the loss recovers 1 - (1 - rebound) / 2; more than the loading work: 0
  for (double& l : loss) l *= 0.5;
  EXPECT_NEAR(fit_rebound(E, n, D, loss), 1.0 - 0.5 * (1.0 - rebound), 2e-4);
  for (double& l : loss) l *= 4.0;
  EXPECT_EQ(fit_rebound(E, n, D, loss), 0.01);  // clipped to the smallest recovery the law accepts
}

// The law that diverges at the solid's density (bed_compaction.hpp) is the power law in u = s / (1 - s / s_solid):
// p = E u^n = E s_solid^n (s / (s_solid - s))^n (chamber_models.md section 3's diverging form); the fit in u recovers
// a synthetic curve of it exactly, and the plain power law cannot (the two are told apart by the fit's rms).
TEST(PistonDieFit, TheDivergingLawIsThePowerLawInItsCoordinate) {
  const CompactionScale plain, div{0.45};
  EXPECT_FALSE(plain.diverges());
  EXPECT_TRUE(div.diverges());
  for (double s : {0.0, 0.05, 0.2, 0.4, 0.449}) {
    EXPECT_EQ(plain.u(s), s);
    EXPECT_NEAR(div.s(div.u(s)), s, 1e-14);
    EXPECT_NEAR(2e6 * std::pow(div.u(s), 1.6), 2e6 * std::pow(0.45, 1.6) * std::pow(s / (0.45 - s), 1.6),
                1e-9 * 2e6 * std::pow(div.u(s), 1.6));
  }
  std::vector<double> s, p;
  for (int k = 1; k <= 42; ++k) s.push_back(0.01 * k), p.push_back(0.8e6 * std::pow(div.u(0.01 * k), 1.45));
  const PowerLawFit f = fit_power_law(s, p, 0.02, div);
  EXPECT_NEAR(f.modulus, 0.8e6, 0.8e6 * 1e-9);
  EXPECT_NEAR(f.exponent, 1.45, 1e-9);
  EXPECT_LT(f.rms_log, 1e-9);
  EXPECT_GT(fit_power_law(s, p, 0.02).rms_log, 0.05);  // the power law in s misses its rise near the limit
  // the material's scale: the solid limit 1 - loose fraction when it diverges, none otherwise
  FlowMaterial mat;
  mat.loose_fraction = 0.47;
  EXPECT_FALSE(compaction_scale(mat).diverges());
  mat.solid_divergence = true;
  EXPECT_DOUBLE_EQ(compaction_scale(mat).limit, 0.53);
  EXPECT_LT(diverging_compaction_limit(0.47), 0.53);
}

// Loops of mbd::bed_hysteretic in the diverging coordinate (memory in u, the liner's path in s): the closed integral
// of p ds is hysteretic_loop_loss with the scale (Simpson), the plain closed form in the limit of an infinite solid
// limit, and fit_rebound with the scale recovers the rebound the loops were made with.
TEST(PistonDieFit, DivergingLoopLossAndReboundFromSyntheticLoops) {
  const double E = 0.9e6, n = 1.45, rebound = 0.18;
  const CompactionScale div{0.53};
  std::vector<double> D{0.15, 0.3, 0.42}, loss;
  for (double d : D) {
    const double l = law_loop_loss(E, n, rebound, d, div, 20000), model = hysteretic_loop_loss(E, n, rebound, d, div);
    EXPECT_NEAR(l, model, 1e-4 * model) << "D " << d;
    EXPECT_GT(model, 1.05 * hysteretic_loop_loss(E, n, rebound, d));  // stiffer than the power law in s
    loss.push_back(l);
  }
  EXPECT_NEAR(hysteretic_loop_loss(E, n, rebound, 0.3, CompactionScale{1e9}), hysteretic_loop_loss(E, n, rebound, 0.3),
              1e-6 * hysteretic_loop_loss(E, n, rebound, 0.3));
  double rms = -1;
  EXPECT_NEAR(fit_rebound(E, n, D, loss, &rms, div), rebound, 2e-4);
  EXPECT_LT(rms, 1e-3 * loss.back());
  for (double& l : loss) l *= 10.0;  // more than the loading work: the smallest recovery the law accepts
  EXPECT_EQ(fit_rebound(E, n, D, loss, nullptr, div), 0.01);
}

TEST(PistonDieFit, BreakageEventConservesMassAndFitRecoversParameters) {
  const auto sv = sieves_m();
  // feed spread over 16-50 mm
  std::vector<double> feed(sv.size(), 0.0);
  for (std::size_t k = 0; k < sv.size(); ++k) feed[k] = std::clamp(std::log(sv[k] / 0.016) / std::log(50.0 / 16.0), 0.0, 1.0);
  BreakageParams truth;
  truth.s_c = 0.18, truth.m = 1.6, truth.q = 0.7, truth.phi = 0.3, truth.gamma = 1.1, truth.beta = 3.0;
  PistonDieResult r;
  r.feed_passing = feed;
  r.min_resolved = 0.001, r.metaparticle_diameter = 0.0005;
  r.solid_density = 2600, r.loose_solid_fraction = 0.5;
  for (double s : {0.1, 0.2, 0.3}) {
    PressLoop L;
    L.s_max = L.s_reached = s;
    for (int k = 0; k <= 30; ++k) L.s.push_back(s * k / 30.0), L.p.push_back(4e7 * std::pow(s * k / 30.0, 2.5)), L.phase.push_back(0);
    L.s.push_back(0.9 * s), L.p.push_back(0.0), L.phase.push_back(1);
    L.loop_energy = path_integral(L.s, L.p);
    L.passing = breakage_event(feed, sv, s, truth);
    EXPECT_NEAR(L.passing.back(), 1.0, 1e-12);  // mass conserved
    for (std::size_t k = 0; k < sv.size(); ++k) EXPECT_GE(L.passing[k], feed[k] - 1e-12);
    r.loops.push_back(L);
  }
  const MaterialFit m = fit_flow_material(r);
  EXPECT_NEAR(m.material.modulus_Pa, 4e7, 1e-3 * 4e7);
  EXPECT_NEAR(m.material.exponent, 2.5, 1e-6);
  EXPECT_NEAR(m.material.max_compression, 0.5, 1e-12);  // the solid limit 1 - loose fraction, not the 0.3 reached
  expect_breakage_recovered(m, truth);
  EXPECT_EQ(m.material.breakage.x_resolved, 0.001);  // below it the documented size law (q_below), not a fit:
  EXPECT_NEAR(m.material.breakage.q_below, 0.45 / 2.5, 1e-6);  // the strength's size effect through p = E s^n
}

namespace {
// A synthetic pouring: loading p = E s^n to each s, the product one breakage event of `truth` on `feed`.
PistonDieResult synthetic_pouring(const std::vector<double>& feed, const BreakageParams& truth, double E, double n,
                                  double loose, double rock_mass) {
  PistonDieResult r;
  r.feed_passing = feed;
  r.min_resolved = 0.001, r.metaparticle_diameter = 0.0005;
  r.solid_density = 2600, r.loose_solid_fraction = loose, r.rock_mass = rock_mass;
  for (double s : {0.1, 0.2, 0.3}) {
    PressLoop L;
    L.s_max = L.s_reached = s;
    for (int k = 0; k <= 30; ++k) L.s.push_back(s * k / 30.0), L.p.push_back(E * std::pow(s * k / 30.0, n)), L.phase.push_back(0);
    L.s.push_back(0.9 * s), L.p.push_back(0.0), L.phase.push_back(1);
    L.loop_energy = path_integral(L.s, L.p);
    L.passing = breakage_event(feed, sieves_m(), s, truth);
    r.loops.push_back(L);
  }
  return r;
}
}  // namespace

// The die's first compression presses the top rocks alone (H0 is the highest rock's top): a loading branch that is
// the bed's law E s^n only past kDieBedOnset and above it before (the top rocks carry the piston early) gives the bed's
// law exactly, while a fit from s 0.02 is dragged off it: too soft at depth, as the DEM die's pourings were
// (src/chamber/README.md).
TEST(PistonDieFit, TheBedLawIsFittedWhereThePistonBearsOnTheWholeBed) {
  const auto sv = sieves_m();
  std::vector<double> feed(sv.size());
  for (std::size_t k = 0; k < sv.size(); ++k) feed[k] = std::clamp(std::log(sv[k] / 0.020) / std::log(50.0 / 20.0), 0.0, 1.0);
  BreakageParams truth;
  truth.s_c = 0.18, truth.m = 1.6, truth.q = 0.7, truth.phi = 0.3, truth.gamma = 1.1, truth.beta = 3.0;
  const double E = 2e7, n = 3.0;
  PistonDieResult r = synthetic_pouring(feed, truth, E, n, 0.47, 3.0);
  PressLoop& deep = r.loops.back();
  ASSERT_DOUBLE_EQ(deep.s_reached, 0.3);
  int settling = 0;
  for (std::size_t k = 0; k < deep.s.size(); ++k)
    if (deep.phase[k] == 0 && deep.s[k] > 0 && deep.s[k] <= kDieBedOnset) {  // the top rocks: continuous at the onset
      deep.p[k] = E * std::pow(deep.s[k], n) * std::pow(kDieBedOnset / deep.s[k], 1.5);
      ++settling;
    }
  EXPECT_GT(settling, 15);
  const MaterialFit m = fit_flow_material(r);
  EXPECT_NEAR(m.material.modulus_Pa, E, 1e-9 * E);
  EXPECT_NEAR(m.material.exponent, n, 1e-9);
  EXPECT_EQ(m.pressure_fit.s_min, kDieBedOnset);
  EXPECT_EQ(m.pressure_fit.points, 10);  // s 0.21 ... 0.30
  std::vector<double> s, p;
  for (std::size_t k = 0; k < deep.s.size(); ++k)
    if (deep.phase[k] == 0) s.push_back(deep.s[k]), p.push_back(deep.p[k]);
  const PowerLawFit all = fit_power_law(s, p, 0.02);
  EXPECT_LT(all.exponent, n - 0.5);  // the top rocks' early load flattens it
  EXPECT_LT(all.modulus * std::pow(0.5, all.exponent), 0.5 * E * std::pow(0.5, n));  // ... yet too soft beyond it
  const std::string f = ::testing::TempDir() + "/onset_material.yaml";
  write_flow_material_yaml(m, f, {"test"});
  std::ifstream in(f);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("loading points (s > 0.2)"), std::string::npos) << text;
}

// Pourings of one rock with other feeds and packings: the pooled fit recovers the rock from all of them, and weighs
// each (a fit of the first alone, as before, gives the first's pressure and packing).
TEST(PistonDieFit, PooledFitOfReplicatePouringsRecoversTheRockAndWeighsEveryPouring) {
  const auto sv = sieves_m();
  std::vector<double> coarse(sv.size()), fine(sv.size());
  for (std::size_t k = 0; k < sv.size(); ++k) {
    coarse[k] = std::clamp(std::log(sv[k] / 0.020) / std::log(50.0 / 20.0), 0.0, 1.0);
    fine[k] = std::clamp(std::log(sv[k] / 0.012) / std::log(40.0 / 12.0), 0.0, 1.0);
  }
  BreakageParams truth;
  truth.s_c = 0.18, truth.m = 1.6, truth.q = 0.7, truth.phi = 0.3, truth.gamma = 1.1, truth.beta = 3.0;
  const std::vector<PistonDieResult> same{synthetic_pouring(coarse, truth, 4e7, 2.5, 0.50, 2.0),
                                          synthetic_pouring(fine, truth, 4e7, 2.5, 0.40, 1.0)};
  const MaterialFit m = fit_flow_material(same);
  EXPECT_NEAR(m.material.modulus_Pa, 4e7, 1e-3 * 4e7);
  EXPECT_NEAR(m.material.exponent, 2.5, 1e-6);
  EXPECT_NEAR(m.material.loose_fraction, 3.0 / (2.0 / 0.5 + 1.0 / 0.4), 1e-12);  // total mass / total loose volume
  EXPECT_NEAR(m.material.max_compression, 1.0 - m.material.loose_fraction, 1e-12);
  expect_breakage_recovered(m, truth);
  EXPECT_NE(m.breakage_note.find("2 pourings"), std::string::npos) << m.breakage_note;

  // two beds of one law but other stiffness (as a stiff and a soft pouring): equal points each, so the log fit of
  // them together is the geometric mean of the moduli; the rebound fits both loops' losses
  const std::vector<PistonDieResult> two{synthetic_pouring(coarse, truth, 2e7, 2.0, 0.5, 1.0),
                                         synthetic_pouring(coarse, truth, 8e7, 2.0, 0.5, 1.0)};
  const MaterialFit g = fit_flow_material(two);
  EXPECT_NEAR(g.material.modulus_Pa, 4e7, 1e-9 * 4e7);
  EXPECT_NEAR(g.material.exponent, 2.0, 1e-9);
  EXPECT_GT(g.pressure_fit.rms_log, 0.6);  // ln 2 apart from each: the pourings' spread shows in the fit's rms
  std::vector<double> D, loss;
  for (const auto& r : two)
    for (const auto& L : r.loops) D.push_back(L.s_reached), loss.push_back(L.loop_energy);
  EXPECT_NEAR(g.material.rebound, fit_rebound(4e7, 2.0, D, loss), 1e-12);
  EXPECT_THROW(fit_flow_material(std::vector<PistonDieResult>{}), std::invalid_argument);
}

TEST(PistonDieFit, LabCsvIsFittedAndBadInputNamed) {
  const std::string f = testing::TempDir() + "/lab_piston_die.csv";
  {
    std::ofstream out(f);
    out << "s,p_MPa,phase\n";
    for (int k = 0; k <= 25; ++k) out << 0.012 * k << "," << 80.0 * std::pow(0.012 * k, 2.5) << ",load\n";
    for (int k = 24; k >= 22; --k) out << 0.012 * k << "," << 80.0 * std::pow(0.3, 2.5) * (k - 22) / 3.0 << ",unload\n";
  }
  const MaterialFit m = fit_flow_material_lab(read_lab_csv(f));
  EXPECT_NEAR(m.material.modulus_Pa, 80e6, 80e6 * 1e-6);
  EXPECT_NEAR(m.material.exponent, 2.5, 1e-6);
  EXPECT_NEAR(m.material.max_compression, 1 - m.material.loose_fraction, 1e-12);  // solid, not the 0.3 reached
  // unloading from 0.3 to 0.264, p linear to 0: recovers 0.018 p_max of the 0.3 p_max / 3.5 loading work
  EXPECT_NEAR(m.material.rebound, 0.018 * 3.5 / 0.3, 0.005);
  {
    std::ofstream out(f);
    out << "s,p_MPa\n0,0\n0.1,x\n";
  }
  try {
    read_lab_csv(f);
    FAIL() << "bad p accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("line 3"), std::string::npos) << e.what();
  }
  std::remove(f.c_str());
}

namespace {
// The record tests' pouring: a 20-50 mm feed and one rock's breakage.
std::vector<double> record_feed() {
  const auto sv = sieves_m();
  std::vector<double> feed(sv.size());
  for (std::size_t k = 0; k < sv.size(); ++k) feed[k] = std::clamp(std::log(sv[k] / 0.020) / std::log(2.5), 0.0, 1.0);
  return feed;
}
BreakageParams record_rock() {
  BreakageParams b;
  b.s_c = 0.18, b.m = 1.6, b.q = 0.7, b.phi = 0.3, b.gamma = 1.1, b.beta = 3.0;
  return b;
}
}  // namespace

// The pourings' record: every field read back as written (17 digits), so a pool of recorded pourings fits to the very
// material the run that made them fitted; a bad record names its line.
TEST(PistonDieRecord, PouringsReadBackExactlyAndFitTheSame) {
  const auto feed = record_feed();
  const BreakageParams truth = record_rock();
  std::vector<PistonDieResult> rs{synthetic_pouring(feed, truth, 2e7 / 3.0, 2.1, 0.47, 1.3),
                                  synthetic_pouring(feed, truth, 4e7, 2.5, 0.52, 0.9)};
  rs[0].seed = 11, rs[1].seed = 12, rs[1].blowup = "loop s_max 0.30: overlap 0.91 r (jam)";
  rs[0].rocks = 45, rs[0].particles = 3811, rs[0].bonds = 7000, rs[0].die_diameter = 0.16, rs[0].die_area = 0.0201;
  rs[0].rock_min = 0.028, rs[0].rock_max = 0.04, rs[0].piston_speed = 0.4, rs[0].bed_height = 0.1234567890123;
  rs[0].dt = 4.75e-7, rs[0].settle_time = 0.28, rs[0].wall_s = 412.5;
  rs[0].loops[1].bonds_broken = 377, rs[0].loops[1].fragments = 212, rs[0].loops[1].mass_error = 5.7e-16;
  const std::string f = testing::TempDir() + "/piston_die_pourings.txt";
  write_pourings(rs, f);
  const auto back = read_pourings(f);
  ASSERT_EQ(back.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const auto &a = rs[i], &b = back[i];
    EXPECT_EQ(a.seed, b.seed);
    EXPECT_EQ(a.blowup, b.blowup);
    EXPECT_EQ(a.rocks, b.rocks);
    EXPECT_EQ(a.particles, b.particles);
    EXPECT_EQ(a.bed_height, b.bed_height);
    EXPECT_EQ(a.rock_mass, b.rock_mass);
    EXPECT_EQ(a.loose_solid_fraction, b.loose_solid_fraction);
    EXPECT_EQ(a.rock_max, b.rock_max);
    EXPECT_EQ(a.feed_passing, b.feed_passing);
    ASSERT_EQ(a.loops.size(), b.loops.size());
    for (std::size_t k = 0; k < a.loops.size(); ++k) {
      EXPECT_EQ(a.loops[k].s, b.loops[k].s);
      EXPECT_EQ(a.loops[k].p, b.loops[k].p);
      EXPECT_EQ(a.loops[k].phase, b.loops[k].phase);
      EXPECT_EQ(a.loops[k].passing, b.loops[k].passing);
      EXPECT_EQ(a.loops[k].loop_energy, b.loops[k].loop_energy);
      EXPECT_EQ(a.loops[k].bonds_broken, b.loops[k].bonds_broken);
      EXPECT_EQ(a.loops[k].mass_error, b.loops[k].mass_error);
    }
  }
  const MaterialFit m0 = fit_flow_material(rs), m1 = fit_flow_material(back);
  EXPECT_EQ(m0.material.modulus_Pa, m1.material.modulus_Pa);
  EXPECT_EQ(m0.material.exponent, m1.material.exponent);
  EXPECT_EQ(m0.material.loose_fraction, m1.material.loose_fraction);
  EXPECT_EQ(m0.material.rebound, m1.material.rebound);
  EXPECT_EQ(m0.material.breakage.s_c, m1.material.breakage.s_c);
  EXPECT_EQ(m0.material.breakage.gamma, m1.material.breakage.gamma);

  // a damaged record: the line and what was expected
  std::string text;
  {
    std::ifstream in(f);
    text.assign(std::istreambuf_iterator<char>(in), {});
  }
  auto expect_refused = [&](const std::string& bad, const std::string& says) {
    const std::string g = testing::TempDir() + "/piston_die_pourings_bad.txt";
    std::ofstream(g) << bad;
    try {
      read_pourings(g);
      ADD_FAILURE() << "accepted a record that " << says;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
    std::remove(g.c_str());
  };
  std::string no_mass = text;
  no_mass.replace(no_mass.find(" rock_mass_kg="), 14, " rock_masskg=");
  expect_refused(no_mass, "line 3: 'pouring' lacks rock_mass_kg");
  std::string nan_p = text;
  nan_p.replace(nan_p.find("\np_Pa ") + 6, 1, "x");
  expect_refused(nan_p, "is not a number");
  expect_refused(text.substr(0, text.find("\nphase")), "differ in length");
  expect_refused("piston_die_pourings 2\n", "expected the header 'piston_die_pourings 1'");
  std::remove(f.c_str());
}

// The jackknife of the pooled fit: each leave-one-out fit is the pooled fit of the others. Pourings of one law that
// differ only in stiffness pool to the geometric mean of their moduli (equal points each), so ln E pooled is the mean
// of the pourings' ln E and its jackknife standard error is their sample std / sqrt(K), a closed form.
// A pouring pressed again later, deeper (the same seed: the same bed), adds its loop to the record; the fit then takes
// its deepest loading branch. The same seed as another bed, or the same pressing twice, is refused by name.
TEST(PistonDieRecord, APouringPressedDeeperLaterAddsItsLoop) {
  const auto feed = record_feed();
  const BreakageParams truth = record_rock();
  PistonDieResult first = synthetic_pouring(feed, truth, 2e7, 2.0, 0.47, 1.3);  // loops to 0.1, 0.2, 0.3
  first.seed = 5, first.particles = 3800, first.bed_height = 0.08, first.dt = 5e-7;
  PistonDieResult deeper = first, other = synthetic_pouring(feed, truth, 2e7, 2.0, 0.47, 1.3);
  other.seed = 6;
  deeper.loops = {first.loops.back()};
  PressLoop& L = deeper.loops.front();
  L.s.clear(), L.p.clear(), L.phase.clear();
  L.s_max = L.s_reached = 0.5;
  for (int k = 0; k <= 50; ++k) L.s.push_back(0.01 * k), L.p.push_back(2e7 * std::pow(0.01 * k, 2.0)), L.phase.push_back(0);
  const auto merged = merge_repressed_pourings({first, other, deeper});
  ASSERT_EQ(merged.size(), 2u);
  ASSERT_EQ(merged[0].loops.size(), 4u);
  EXPECT_EQ(merged[0].loops.back().s_max, 0.5);
  EXPECT_EQ(merged[1].loops.size(), 3u);
  EXPECT_EQ(fit_flow_material(merged[0]).pressure_fit.points, 30);  // s > kDieBedOnset of the 0.5 branch: 0.21 ... 0.5
  try {
    merge_repressed_pourings({first, first});
    FAIL() << "accepted the same pressing twice";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("seed 5 is recorded twice with the loop to s_max"), std::string::npos) << e.what();
  }
  deeper.rock_mass *= 1.01;
  try {
    merge_repressed_pourings({first, deeper});
    FAIL() << "accepted another bed under the same seed";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("as different beds"), std::string::npos) << e.what();
  }
}

TEST(PistonDieRecord, LeaveOneOutFitsAreTheJackknifeOfThePooledFit) {
  const auto feed = record_feed();
  const BreakageParams truth = record_rock();
  const std::vector<double> E{1e7, 3e7, 5e7, 2e7};
  std::vector<PistonDieResult> rs;
  for (double e : E) rs.push_back(synthetic_pouring(feed, truth, e, 2.2, 0.5, 1.0));
  const auto loo = leave_one_out_fits(rs);
  ASSERT_EQ(loo.size(), E.size());
  std::vector<double> lnE, loo_lnE;
  for (std::size_t i = 0; i < E.size(); ++i) {
    double mean_ln = 0;
    for (std::size_t j = 0; j < E.size(); ++j)
      if (j != i) mean_ln += std::log(E[j]) / (E.size() - 1);
    EXPECT_NEAR(std::log(loo[i].material.modulus_Pa), mean_ln, 1e-9) << "without pouring " << i;
    EXPECT_NEAR(loo[i].material.exponent, 2.2, 1e-9);
    lnE.push_back(std::log(E[i])), loo_lnE.push_back(std::log(loo[i].material.modulus_Pa));
  }
  double mean = 0, var = 0;
  for (double x : lnE) mean += x / lnE.size();
  for (double x : lnE) var += (x - mean) * (x - mean) / (lnE.size() - 1);
  EXPECT_NEAR(analysis::jackknife_std(loo_lnE), std::sqrt(var / lnE.size()), 1e-9);
  // the pourings differ in stiffness only: the breakage every leave-one-out fit recovers is the same rock's
  for (const auto& m : loo) expect_breakage_recovered(m, truth);
  rs.pop_back(), rs.pop_back();
  EXPECT_THROW(leave_one_out_fits(rs), std::invalid_argument);  // two pourings: a leave-one-out fit pools one
}

// The reduced die of the DEM tests (seconds, not representative numbers), each bed reloaded once.
static PistonDieOptions reduced_die(const std::vector<double>& ratios) {
  PistonDieOptions o;
  o.die_diameter = 0.10;
  o.rock_min = 0.028, o.rock_max = 0.032;  // the smallest the BPM's 16 mm metaparticles pack
  o.rock_count = 18;  // two to three layers: fewer make a bed of lone towers whose pressure comes and goes
  o.compression_ratios = ratios;
  o.piston_speed = 0.5;
  o.settle_max_time = 0.15;
  o.threads = 1;
  o.seed = 3;
  o.reloads = 1;
  return o;
}

TEST(PistonDie, OptionsNameWhatIsWrong) {
  PistonDieOptions o;
  o.die_diameter = 0.05;  // < 3 x 40 mm
  try {
    o.validate();
    FAIL() << "die smaller than 3 rocks accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("die_diameter"), std::string::npos) << e.what();
  }
  o = PistonDieOptions();
  o.compression_ratios = {0.2, 0.1};
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = PistonDieOptions();
  o.reloads = -1;
  try {
    o.validate();
    FAIL() << "negative reloads accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("reloads"), std::string::npos) << e.what();
  }
  o = PistonDieOptions();
  o.reload_shift = 0.02;  // a shift without a reload to follow it
  try {
    o.validate();
    FAIL() << "reload_shift without reloads accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("reload_shift"), std::string::npos) << e.what();
  }
  o.reloads = 1;
  EXPECT_NO_THROW(o.validate());
  o.reload_shift = 0.25;
  EXPECT_THROW(o.validate(), std::invalid_argument);
}

// A bed pushed down the die before its reload (reload_shift): the pour and the first pressing are those of the run
// without the shift, bit for bit (the longer die is built after them); the push moves the bed with the floor, so the
// reload's s, counted from the moved floor, starts where the unshifted reload does to within the bed's settling
// (a reload that counted from the old floor would start 20 mm / H0 ~ 0.35 higher); mass is conserved. And a pressing
// with a sideways sweep books the piston's sideways work within Coulomb's bound.
TEST(PistonDie, ABedPushedDownTheDieIsReloadedWhereItLies) {
  const rocks::BpmModel bpm = rocks::load_bpm_model(std::string(CRUSHER_SOURCE_DIR) + "/launch_free_configs/bpm_calibrated.yaml");
  PistonDieOptions o = reduced_die({0.3});
  const PistonDieResult still = run_piston_die(bpm, o);
  o.reload_shift = 0.02;
  const PistonDieResult pushed = run_piston_die(bpm, o);
  ASSERT_EQ(still.loops.size(), 1u);
  ASSERT_EQ(pushed.loops.size(), 1u);
  const PressLoop &a = still.loops[0], &b = pushed.loops[0];
  EXPECT_EQ(a.s, b.s);
  EXPECT_EQ(a.p, b.p);
  EXPECT_EQ(a.bonds_broken, b.bonds_broken);
  EXPECT_EQ(b.shift, 0.0);
  ASSERT_EQ(b.reloads.size(), 1u);
  const PressLoop &ra = a.reloads[0], &rb = b.reloads[0];
  EXPECT_EQ(ra.shift, 0.0);
  EXPECT_DOUBLE_EQ(rb.shift, 0.02);
  EXPECT_GT(rb.shift_peak_pressure, 0.0);  // the piston pushed: the floor drops away faster than the bed falls at first
  EXPECT_NEAR(rb.s.front(), ra.s.front(), 1e-12);  // the piston starts where it let go, the floor moved with it
  EXPECT_NEAR(rb.s_top, ra.s_top, 0.05);
  EXPECT_GT(rb.s_top, 0.0);
  EXPECT_LT(rb.s_top, o.compression_ratios[0]);
  EXPECT_GE(rb.s_reached, 0.29);
  EXPECT_LT(rb.mass_error, 1e-12);
  EXPECT_GE(rb.fragments, b.fragments);
  EXPECT_EQ(a.sweep_energy_per_kg, 0.0);
  // A pressing with the piston sliding sideways (sweep 1): the sideways work is positive and, by Coulomb's law on each
  // sphere's contact with the piston (rock on steel mu 0.7, Table 4), at most mu x sweep x the normal work done along
  // the piston's path, the loading and unloading works together (2 x loading - loop).
  o.reload_shift = 0.0, o.reloads = 0, o.sweep = 1.0;
  const PistonDieResult swept = run_piston_die(bpm, o);
  ASSERT_EQ(swept.loops.size(), 1u);
  const PressLoop& c = swept.loops[0];
  EXPECT_GT(c.sweep_energy_per_kg, 0.05 * c.energy_per_kg);
  EXPECT_LE(c.sweep_energy_per_kg, 0.7 * 1.0 * (2.0 * c.loading_energy_per_kg - c.energy_per_kg));
  std::printf("pushed 20 mm: reload from s %.4f (bed top %.4f), loop %.2f J/kg (unpushed %.2f); swept: loop %.2f J/kg, "
              "sideways %.2f J/kg of at most %.2f\n", rb.s.front(), rb.s_top, rb.energy_per_kg, ra.energy_per_kg,
              c.energy_per_kg, c.sweep_energy_per_kg, 0.7 * (2.0 * c.loading_energy_per_kg - c.energy_per_kg));
}

// A reduced die on the calibrated BPM: physically meaningful results of the DEM test.
TEST(PistonDie, ReducedDieOnCalibratedRock) {
  const auto t0 = std::chrono::steady_clock::now();
  const rocks::BpmModel bpm = rocks::load_bpm_model(std::string(CRUSHER_SOURCE_DIR) + "/launch_free_configs/bpm_calibrated.yaml");
  const PistonDieOptions o = reduced_die({0.15, 0.3});
  const PistonDieResult r = run_piston_die(bpm, o);
  ASSERT_EQ(r.loops.size(), 2u);
  EXPECT_EQ(r.rocks, 18);
  EXPECT_GT(r.loose_solid_fraction, 0.2);
  EXPECT_LT(r.loose_solid_fraction, 0.75);
  for (const auto& L : r.loops) {
    EXPECT_GE(L.s_reached, L.s_max - 0.01);
    // the loop absorbs energy, less than the loading work (some is recovered on unloading)
    EXPECT_GT(L.loop_energy, 0.0);
    EXPECT_LT(L.loop_energy, L.loading_work);
    EXPECT_LT(L.mass_error, 1e-12);  // fragments hold every particle
    EXPECT_GE(L.fragments, r.rocks);
    // The same bed pressed again to s_max: it kept part of its compaction (the piston meets it below H0), the second
    // pressing dissipates and breaks less than the first (less of it is new compaction), and broken bonds stay broken.
    ASSERT_EQ(L.reloads.size(), 1u);
    const PressLoop& R = L.reloads.front();
    EXPECT_GT(R.s.front(), 0.0);
    EXPECT_LT(R.s.front(), L.s_max);
    EXPECT_GE(R.s_reached, L.s_max - 0.01);
    EXPECT_GT(R.loop_energy, 0.0);
    EXPECT_LT(R.loop_energy, L.loop_energy);
    EXPECT_LE(R.bonds_broken, L.bonds_broken);
    EXPECT_LT(R.mass_error, 1e-12);
    EXPECT_GE(R.fragments, L.fragments);
    for (std::size_t k = 0; k < R.passing.size(); ++k) EXPECT_GE(R.passing[k], L.passing[k]) << "sieve " << k;
    EXPECT_TRUE(R.reloads.empty());
  }
  // pressure rises with s on loading: mean p over successive s bins (0.1 wide: a loose bed of brittle rocks has
  // local drops where a rock fails) increases
  const auto& deep = r.loops.back();
  EXPECT_LT(deep.reloads.front().bonds_broken, deep.bonds_broken);  // (at 0.15 one bond breaks in each)
  std::vector<double> sum(3, 0.0), cnt(3, 0.0);
  for (std::size_t k = 0; k < deep.s.size(); ++k)
    if (deep.phase[k] == 0 && deep.s[k] > 0.0) {
      const int b = std::min(2, static_cast<int>(deep.s[k] / 0.1));
      sum[b] += deep.p[k], cnt[b] += 1;
    }
  for (int b = 1; b < 3; ++b) {
    ASSERT_GT(cnt[b], 0);
    EXPECT_GT(sum[b] / cnt[b], sum[b - 1] / cnt[b - 1]) << "bin " << b;
  }
  // more compression: more energy, more broken bonds, a finer product
  const auto& a = r.loops[0];
  EXPECT_GT(deep.energy_per_kg, a.energy_per_kg);
  EXPECT_GT(deep.bonds_broken, a.bonds_broken);
  double finer = 0.0;
  for (std::size_t k = 0; k < deep.passing.size(); ++k) {
    EXPECT_GE(deep.passing[k] + 0.02, a.passing[k]) << "sieve " << flow_sieves_mm()[k];
    finer += deep.passing[k] - a.passing[k];
  }
  EXPECT_GT(finer, 0.02);
  const MaterialFit m = fit_flow_material(r);
  EXPECT_GT(m.material.exponent, 1.0);  // a stiffening bed
  // the DEM bed recovers a small part of the loading work; the law's rebound (fitted to the loop energies against
  // the power law's loading work, which a lumpy loose-bed curve may undershoot) is then small, possibly clipped to 0.01
  EXPECT_GT(1.0 - deep.loop_energy / deep.loading_work, 0.01);
  EXPECT_GE(m.material.rebound, 0.0);
  EXPECT_LT(m.material.rebound, 0.6);
  EXPECT_NEAR(m.material.max_compression, 1 - r.loose_solid_fraction, 1e-12);
  EXPECT_GT(m.material.max_compression, deep.s_reached);
  // The same compression in the continuum: one flow-model cell of the die's feed, loose at rest, pressed to the DEM
  // loop's s and released. Its pressure is the DEM's within the fit's scatter, its energy per kg the DEM loop's
  // within 50 %, its product the DEM's to 3 % passing on the sieves the metaparticles resolve.
  FlowParams fp;
  fp.bands = 2, fp.sectors = 1, fp.prefill = false, fp.choke_feed = false;
  fp.material = m.material;
  core::Profile mantle, concave;
  mantle.z = concave.z = {-0.8, -0.2};
  mantle.r = {0.30, 0.30}, concave.r = {0.35, 0.35};  // gap 50 mm; the one sector's point at azimuth 180 deg
  FlowModel cell(fp, mantle, concave);
  const double rho0 = cell.loose_density(), V0 = cell.cell_area(0) * 0.05;
  std::vector<double> f(cell.classes());
  for (std::size_t c = 0; c < f.size(); ++c)
    f[c] = V0 * rho0 * ((c < r.feed_passing.size() ? r.feed_passing[c] : 1.0) - (c ? r.feed_passing[c - 1] : 0.0));
  cell.deposit(0, f);
  const Eigen::Isometry3d rest = Eigen::Isometry3d::Identity();
  auto pressed = [&](double s) {  // gap 50 mm (1 - s)
    Eigen::Isometry3d T = rest;
    T.translation() = Eigen::Vector3d(-0.05 * s, 0, 0);
    return T;
  };
  const Eigen::Vector3d com(0, 0, -0.5);
  cell.step(rest, rest, com, com, 1e-3, 0.0);
  const int n = 1000;  // pressed and released in small steps, as the piston does
  for (int i = 1; i <= n; ++i) cell.step(pressed(deep.s_reached * i / n), rest, com, com, 1e-3, 0.0);
  const double p_cont = cell.cell_pressure(0), p_dem = deep.p[std::max_element(deep.s.begin(), deep.s.end()) - deep.s.begin()];
  for (int i = n - 1; i >= 0; --i) cell.step(pressed(deep.s_reached * i / n), rest, com, com, 1e-3, 0.0);
  ASSERT_EQ(cell.events(), 1);
  const double scatter = std::exp(2 * m.pressure_fit.rms_log);
  EXPECT_GT(p_cont, p_dem / scatter) << p_cont << " Pa against the DEM's " << p_dem;
  EXPECT_LT(p_cont, p_dem * scatter) << p_cont << " Pa against the DEM's " << p_dem;
  EXPECT_NEAR(cell.crushing_energy_J() / (V0 * rho0), deep.energy_per_kg, 0.5 * deep.energy_per_kg);
  const std::vector<double> product(cell.cell_classes(0), cell.cell_classes(0) + cell.classes());
  const auto pass = cell.passing(product);
  for (std::size_t k = 0; k < pass.size(); ++k)
    if (flow_sieves_mm()[k] * 1e-3 >= r.min_resolved * (1 - 1e-9))
      EXPECT_NEAR(pass[k], deep.passing[k], 0.03) << "sieve " << flow_sieves_mm()[k] << " mm";
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("continuum cell at s %.3f: p %.3g MPa against the DEM's %.3g MPa, %.3g J/kg against %.3g\n", deep.s_reached,
              p_cont * 1e-6, p_dem * 1e-6, cell.crushing_energy_J() / (V0 * rho0), deep.energy_per_kg);
  std::printf("reduced die: %zu particles, loose %.3f, E %.3g MPa n %.3f rebound %.3f, %.1f s\n", r.particles,
              r.loose_solid_fraction, m.material.modulus_Pa * 1e-6, m.material.exponent, m.material.rebound, wall);
}
