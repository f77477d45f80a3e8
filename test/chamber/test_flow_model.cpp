// The chamber flow model (chamber/flow_model.hpp, breakage.hpp) against closed forms: the breakage matrices, one
// compression event, action and reaction on the liners, the loop's work against the crushing energy booked, free
// fall through an open chamber, lumps held by a gap narrower than themselves, the mass balance of a long run and a
// bit-for-bit resume.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <sstream>

#include "../common/coaxial_liners.hpp"
#include "../common/flow_params.hpp"
#include "chamber/flow_model.hpp"
#include "chamber/piston_die.hpp"
#include "core/binary_io.hpp"

namespace {

// Coaxial cylinders: the mantle r = 0.30 m, the concave r = 0.30 m + gap, z from -0.8 to -0.2 m (shared height).
using test_liners::cylinder;
using test_liners::shifted;

chamber::FlowParams params(int bands, int sectors) { return test_liners::flow_params(bands, sectors); }

const Eigen::Isometry3d kRest = Eigen::Isometry3d::Identity();
const Eigen::Vector3d kComM(0, 0, -0.5), kComC(0, 0, -0.6);

double sum(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0); }

// The mantle shifted towards +x by d i / n for i from `from` to `to` (either way), one still step each.
void shift_steps(chamber::FlowModel& m, double d, int n, int from, int to) {
  for (int i = from; from < to ? i <= to : i >= to; i += from < to ? 1 : -1)
    m.step(shifted({d * i / n, 0, 0}), kRest, kComM, kComC, 1e-3, 0.0);
}

}  // namespace

TEST(Breakage, MatricesConserveMassAndFollowTheirFunctions) {
  chamber::BreakageParams bp;
  const std::vector<double> sieves{1e-3, 2e-3, 4e-3, 8e-3, 16e-3, 31.5e-3, 63e-3};
  chamber::Breakage br(sieves, bp);
  ASSERT_EQ(br.classes(), sieves.size() + 1);
  for (std::size_t j = 0; j < br.classes(); ++j) {
    double col = 0;
    for (std::size_t i = 0; i <= j; ++i) {
      EXPECT_GE(br.b(i, j), 0.0);
      col += br.b(i, j);
    }
    EXPECT_NEAR(col, 1.0, 1e-14) << "column " << j;
  }
  // Austin's cumulative form: class 3 (4-8 mm) from class 5 (16-31.5 mm), y = 31.5 mm.
  auto B = [&](double u) { return bp.phi * std::pow(u, bp.gamma) + (1 - bp.phi) * std::pow(u, bp.beta); };
  EXPECT_NEAR(br.b(3, 5), B(8 / 31.5) - B(4 / 31.5), 1e-14);
  EXPECT_NEAR(br.b(0, 5), B(1 / 31.5), 1e-14);
  // Selection: 1 - exp(-(s / s_c (x / x_ref)^-q)^m) at the class's geometric-mean size.
  const double x5 = std::sqrt(16e-3 * 31.5e-3), sc = bp.s_c * std::pow(x5 / bp.x_ref, -bp.q);
  EXPECT_NEAR(br.selection(5, 0.2), 1 - std::exp(-std::pow(0.2 / sc, bp.m)), 1e-14);
  EXPECT_GT(br.selection(6, 0.2), br.selection(2, 0.2));  // coarser lumps are selected sooner
  EXPECT_EQ(br.selection(4, 0.0), 0.0);
  // One event: p = [B S + I - S] f, written out.
  std::vector<double> f{0, 0, 1, 0, 2, 3, 4, 0}, p = f;
  br.apply(0.25, p.data());
  for (std::size_t i = 0; i < f.size(); ++i) {
    double e = (1 - br.selection(i, 0.25)) * f[i];
    for (std::size_t j = i; j < f.size(); ++j) e += br.b(i, j) * br.selection(j, 0.25) * f[j];
    EXPECT_NEAR(p[i], e, 1e-13) << "class " << i;
  }
  EXPECT_NEAR(sum(p), sum(f), 1e-13);
  // Pressings 0 -> 0.15 -> 0.25 select as one to 0.25 (the survivors' shares multiply), and a pressing within the
  // compaction reached selects nothing.
  for (std::size_t j = 0; j < br.classes(); ++j)
    EXPECT_NEAR((1 - br.selection_between(j, 0, 0.15)) * (1 - br.selection_between(j, 0.15, 0.25)),
                1 - br.selection(j, 0.25), 1e-14) << "class " << j;
  EXPECT_GT(br.selection_between(5, 0.15, 0.25), 0.0);
  std::vector<double> again = p;
  br.apply_between(0.25, 0.2, again.data());
  EXPECT_EQ(again, p);
  EXPECT_THROW(chamber::Breakage({2e-3, 1e-3}, bp), std::invalid_argument);
}

TEST(Breakage, BelowTheResolvedSizeSelectionFollowsItsOwnSizeExponent) {
  // Above x_res the measured law s_c (x / x_ref)^-q; below it s_c(x_res) (x / x_res)^-q_below (here 0.45),
  // continuous at x_res. x_resolved = 0 keeps one law for every size.
  chamber::BreakageParams bp;
  bp.s_c = 1.3;
  bp.m = 6.6;
  bp.q = 1.07;
  bp.x_ref = 10e-3;
  bp.x_resolved = 22.4e-3;
  bp.q_below = 0.45;
  const double sc_res = 1.3 * std::pow(2.24, -1.07);
  EXPECT_NEAR(chamber::critical_compression(bp, 22.4e-3), sc_res, 1e-14);
  EXPECT_NEAR(chamber::critical_compression(bp, 22.4e-3 * (1 - 1e-12)), sc_res, 1e-10);  // continuous
  EXPECT_NEAR(chamber::critical_compression(bp, 40e-3), 1.3 * std::pow(4.0, -1.07), 1e-14);
  EXPECT_NEAR(chamber::critical_compression(bp, 5e-3), sc_res * std::pow(5 / 22.4, -0.45), 1e-14);
  chamber::BreakageParams one = bp;
  one.x_resolved = 0;
  EXPECT_NEAR(chamber::critical_compression(one, 5e-3), 1.3 * std::pow(0.5, -1.07), 1e-14);
  // In the matrices: class 2-4 mm (x = sqrt 8 mm) below, 31.5-63 mm above.
  const std::vector<double> sieves{1e-3, 2e-3, 4e-3, 8e-3, 16e-3, 31.5e-3, 63e-3};
  chamber::Breakage br(sieves, bp), br_one(sieves, one);
  const double x2 = std::sqrt(8e-6), sc2 = sc_res * std::pow(x2 / 22.4e-3, -0.45);
  EXPECT_NEAR(br.selection(2, 0.5), 1 - std::exp(-std::pow(0.5 / sc2, 6.6)), 1e-14);
  EXPECT_GT(br.selection(2, 0.5), 100 * br_one.selection(2, 0.5));  // the fines break far sooner
  EXPECT_EQ(br.selection(6, 0.3), br_one.selection(6, 0.3));
  bp.q_below = -0.1;
  EXPECT_THROW(chamber::Breakage(sieves, bp), std::invalid_argument);
}

// Below the resolved size a lump in a bed breaks at a bed pressure proportional to its strength: with
// q_below = bed_size_exponent(0.45, n), the bed pressure E s_c(x)^n at which a class is 63 % selected follows the
// ISRM point-load size effect x^-0.45, for any pressure exponent n.
TEST(Breakage, BelowTheResolvedSizeALumpBreaksAtABedPressureFollowingItsStrength) {
  for (double n : {1.5, 1.9167, 3.0}) {
    chamber::BreakageParams bp;
    bp.s_c = 1.3, bp.m = 6.6, bp.q = 1.07, bp.x_ref = 10e-3, bp.x_resolved = 22.4e-3;
    bp.q_below = chamber::bed_size_exponent(chamber::kPointLoadSizeExponent, n);
    const double E = 5e6;
    auto p_c = [&](double x) { return E * std::pow(chamber::critical_compression(bp, x), n); };
    for (double x : {2e-3, 5e-3, 12e-3, 20e-3})
      EXPECT_NEAR(p_c(x) / p_c(22.4e-3), std::pow(x / 22.4e-3, -0.45), 1e-12) << "n " << n << ", x " << x;
  }
}

TEST(FlowModel, RejectsBadParametersByName) {
  auto p = params(4, 8);
  p.material.rebound = 0;
  try {
    chamber::FlowModel m(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2));
    FAIL() << "accepted rebound 0";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("rebound"), std::string::npos) << e.what();
  }
  p = params(4, 8);
  p.material.loose_fraction = 0.55, p.material.max_compression = 0.46;  // denser than the solid rock
  try {
    chamber::FlowModel m(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2));
    FAIL() << "accepted a compaction limit beyond the solid";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("denser than solid"), std::string::npos) << e.what();
  }
  p.material.max_compression = 0.45;
  EXPECT_NO_THROW(chamber::FlowModel(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2)));
  p.material.solid_divergence = true;  // its pressure is infinite at the solid limit: the limit must lie below
  try {
    chamber::FlowModel m(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2));
    FAIL() << "accepted the diverging law's compaction limit at the solid's";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("solid_divergence needs max_compression below"), std::string::npos) << e.what();
  }
  p.material.max_compression = chamber::diverging_compaction_limit(0.55);
  EXPECT_NO_THROW(chamber::FlowModel(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2)));
  p.compaction_memory = true;
  EXPECT_THROW(chamber::FlowModel(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2)), std::invalid_argument);
  p = params(4, 8);
  p.feed_passing.pop_back();
  EXPECT_THROW(chamber::FlowModel(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2)), std::invalid_argument);
}

// A cell full of loose rock at rest, pressed by a sideways shift of the mantle and released: one event whose
// compression ratio the gap gives; the cell's classes afterwards are exactly the breakage of the feed at that ratio,
// and the work booked over the loop is the law's loss (1 - rebound) E s^(n+1) / (n + 1) per loose volume.
TEST(FlowModel, OneCompressionEventBreaksTheClassesAsTheMatricesSay) {
  auto p = params(6, 8);
  chamber::FlowModel m(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2));
  const std::size_t k = 2 * 8 + 0;  // band 2, sector 0 (azimuth 22.5 deg)
  const double g_rest = 0.05, A = m.cell_area(k), V0 = A * g_rest;
  std::vector<double> feed(m.classes(), 0.0);
  feed[m.classes() - 2] = 0.6 * V0 * m.loose_density();  // 50-63 mm
  feed[m.classes() - 4] = 0.4 * V0 * m.loose_density();  // 31.5-40 mm
  m.deposit(k, feed);
  m.step(kRest, kRest, kComM, kComC, 1e-3, 0.0);
  const double d = 0.012;  // mantle shifted 12 mm towards sector 0, in small steps, and back
  const int n = 2000;
  for (int i = 1; i <= n; ++i) m.step(shifted({d * i / n, 0, 0}), kRest, kComM, kComC, 1e-3, 0.0);
  const double g = m.cell_gap(k), s = 1 - g / g_rest;
  EXPECT_NEAR(g, std::hypot(0.35 * std::cos(M_PI / 8) - d, 0.35 * std::sin(M_PI / 8)) - 0.30, 1e-12);
  const auto& mat = p.material;
  EXPECT_NEAR(m.cell_pressure(k), mat.modulus_Pa * std::pow(s, mat.exponent), 1e-6 * mat.modulus_Pa);
  EXPECT_EQ(m.events(), 0);
  for (int i = n - 1; i >= 0; --i) m.step(shifted({d * i / n, 0, 0}), kRest, kComM, kComC, 1e-3, 0.0);
  EXPECT_EQ(m.events(), 1);
  std::vector<double> expect = feed;
  m.breakage().apply(s, expect.data());
  for (std::size_t j = 0; j < m.classes(); ++j) EXPECT_NEAR(m.cell_classes(k)[j], expect[j], 1e-12) << "class " << j;
  EXPECT_GT(expect[m.classes() - 3], 0.0);  // something did break
  // Every cell loops; this one's loss against the closed form, through its share: all cells of band 2 sector 0 only
  // hold rock, so the booked work is this cell's.
  const double loss = V0 * (1 - mat.rebound) * mat.modulus_Pa * std::pow(s, mat.exponent + 1) / (mat.exponent + 1);
  EXPECT_NEAR(m.crushing_energy_J(), loss, 0.01 * loss);
  EXPECT_NEAR(m.cell_compressions(k), 1.0, 1e-15);
}

// The same event with the law that diverges at the solid's density (bed_compaction.hpp): the pressure is E u(s)^n, the
// classes break by the ratio s itself (not u), and the work booked over the loop is the diverging law's loss.
TEST(FlowModel, ADivergingBedPressesByItsLawAndBreaksByTheCompressionRatio) {
  auto p = params(6, 8);
  auto& mat = p.material;
  mat.solid_divergence = true;
  mat.max_compression = chamber::diverging_compaction_limit(mat.loose_fraction);
  const chamber::CompactionScale scale = chamber::compaction_scale(mat);
  chamber::FlowModel m(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2));
  const std::size_t k = 2 * 8 + 0;
  const double g_rest = 0.05, A = m.cell_area(k), V0 = A * g_rest;
  std::vector<double> feed(m.classes(), 0.0);
  feed[m.classes() - 2] = 0.6 * V0 * m.loose_density();
  feed[m.classes() - 4] = 0.4 * V0 * m.loose_density();
  m.deposit(k, feed);
  m.step(kRest, kRest, kComM, kComC, 1e-3, 0.0);
  const double d = 0.012;
  const int n = 4000;
  for (int i = 1; i <= n; ++i) m.step(shifted({d * i / n, 0, 0}), kRest, kComM, kComC, 1e-3, 0.0);
  const double s = 1 - m.cell_gap(k) / g_rest;
  ASSERT_GT(scale.u(s), 1.5 * s);  // deep enough that the two laws differ
  EXPECT_NEAR(m.cell_pressure(k), mat.modulus_Pa * std::pow(scale.u(s), mat.exponent), 1e-6 * m.cell_pressure(k));
  for (int i = n - 1; i >= 0; --i) m.step(shifted({d * i / n, 0, 0}), kRest, kComM, kComC, 1e-3, 0.0);
  EXPECT_EQ(m.events(), 1);
  std::vector<double> expect = feed;
  m.breakage().apply(s, expect.data());
  for (std::size_t j = 0; j < m.classes(); ++j) EXPECT_NEAR(m.cell_classes(k)[j], expect[j], 1e-12) << "class " << j;
  const double loss = V0 * chamber::hysteretic_loop_loss(mat.modulus_Pa, mat.exponent, mat.rebound, s, scale);
  EXPECT_NEAR(m.crushing_energy_J(), loss, 0.01 * loss);
}

// The compacted bed (mbd::bed_compacted) in a cell: rock pressed, released half way (no gravity, so it is not
// re-poured) and pressed to the same gap again meets the first pressing's pressure there, breaks no further and counts no second
// event; the law that forgets the compaction at each release (compaction_memory false) meets almost nothing there.
TEST(FlowModel, RePressedRockKeepsItsCompaction) {
  for (bool memory : {true, false}) {
    auto p = params(6, 8);
    p.compaction_memory = memory;
    chamber::FlowModel m(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2));
    const std::size_t k = 2 * 8 + 0;
    const double V0 = m.cell_area(k) * 0.05;
    std::vector<double> feed(m.classes(), 0.0);
    feed[m.classes() - 2] = V0 * m.loose_density();  // 50-63 mm, loose in the 50 mm gap
    m.deposit(k, feed);
    m.step(kRest, kRest, kComM, kComC, 1e-3, 0.0);
    const int n = 1000;
    auto press = [&](int from, int to) { shift_steps(m, 0.012, n, from, to); };
    press(1, n);
    const double p1 = m.cell_pressure(k), s = 1 - m.cell_gap(k) / 0.05;
    EXPECT_NEAR(p1, p.material.modulus_Pa * std::pow(s, p.material.exponent), 1e-6 * p1);
    press(n - 1, n / 2);  // half way back: the liner leaves the rock (rebound 0.15 of s)
    ASSERT_EQ(m.cell_pressure(k), 0.0);
    ASSERT_EQ(m.events(), 1);
    const std::vector<double> after1(m.cell_classes(k), m.cell_classes(k) + m.classes());
    press(n / 2 + 1, n);
    if (memory) {
      EXPECT_NEAR(m.cell_pressure(k), p1, 1e-6 * p1);
      press(n - 1, n / 2);
      EXPECT_EQ(m.events(), 1) << "a reload within the compaction reached is no new event";
      for (std::size_t j = 0; j < m.classes(); ++j) EXPECT_EQ(m.cell_classes(k)[j], after1[j]) << "class " << j;
      EXPECT_NEAR(m.cell_compressions(k), 1.0, 1e-15);
    } else {
      EXPECT_LT(m.cell_pressure(k), 0.3 * p1);  // virgin from half way: about (1/2)^n of p1
    }
  }
}

// With memory, rock pressed half way (to s1), released and pressed on (to s2) breaks by the two pressings 0 -> s1 and
// s1 -> s2 (whose selections compose to one to s2): the cell's classes exactly; two events are counted.
TEST(FlowModel, PressingInTwoStepsBreaksAsOne) {
  auto p = params(6, 8);
  p.compaction_memory = true;
  chamber::FlowModel m(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2));
  const std::size_t k = 2 * 8 + 0, top = m.classes() - 2;  // 50-63 mm
  std::vector<double> feed(m.classes(), 0.0);
  feed[top] = m.cell_area(k) * 0.05 * m.loose_density();
  m.deposit(k, feed);
  m.step(kRest, kRest, kComM, kComC, 1e-3, 0.0);
  const int n = 1000;
  auto go = [&](int from, int to) { shift_steps(m, 0.016, n, from, to); };
  go(1, n / 2);
  const double s1 = 1 - m.cell_gap(k) / 0.05;
  go(n / 2 - 1, 0);
  go(1, n);
  const double s = 1 - m.cell_gap(k) / 0.05;
  go(n - 1, 0);
  EXPECT_EQ(m.events(), 2);
  std::vector<double> expect = feed;
  m.breakage().apply_between(0, s1, expect.data());
  m.breakage().apply_between(s1, s, expect.data());
  for (std::size_t j = 0; j < m.classes(); ++j)
    EXPECT_NEAR(m.cell_classes(k)[j], expect[j], 1e-12 * feed[top]) << "class " << j;
  EXPECT_LT(m.cell_classes(k)[top], 0.99 * feed[top]);
}

// Forces: -F on the mantle at its point, F on the concave, F = p A n: the sums cancel, torques about one point
// cancel, and the normal force is the sum of the cells' p A.
TEST(FlowModel, LinerWrenchIsActionAndReactionOfTheCellPressures) {
  auto p = params(6, 12);
  p.prefill = true;
  const auto mantle = cylinder(0.3), concave = cylinder(0.35, -0.8, -0.2);
  chamber::FlowModel m(p, mantle, concave);
  m.step(kRest, kRest, kComM, kComC, 1e-3, 0.0);  // prefilled loose at rest: no pressure
  Eigen::Isometry3d M = shifted({0.008, -0.003, 0.002});
  M.linear() = Eigen::AngleAxisd(0.01, Eigen::Vector3d(0.3, 1, 0).normalized()).toRotationMatrix();
  const auto L = m.step(M, kRest, kComM, kComC, 1e-3, 0.0);
  double pa = 0;
  int pressed = 0;
  for (std::size_t k = 0; k < m.cells(); ++k) pa += m.cell_pressure(k) * m.cell_area(k), pressed += m.cell_pressure(k) > 0;
  ASSERT_GT(pressed, 4);
  ASSERT_LT(pressed, static_cast<int>(m.cells()));
  EXPECT_NEAR(L.normal_force, pa, 1e-9 * pa);
  EXPECT_NEAR((L.f_mantle + L.f_concave).norm(), 0.0, 1e-9 * pa);
  // Moments about the origin: each force's couple is along its own line, so the total vanishes.
  const Eigen::Vector3d moment = L.t_mantle + kComM.cross(L.f_mantle) + L.t_concave + kComC.cross(L.f_concave);
  EXPECT_NEAR(moment.norm(), 0.0, 1e-9 * pa);
  // The concave is pushed away from the side the mantle moved to (+x), nearly radially.
  EXPECT_GT(L.f_concave.x(), 0.5 * L.f_concave.norm());
  EXPECT_GT(L.f_concave.norm(), 0.5 * pa);
}

// A prescribed close-open loop of the mantle: the work the liners do on the rock (forces x displacement, trapezoid)
// equals the crushing energy the events booked.
TEST(FlowModel, LoopWorkEqualsTheCrushingEnergyBooked) {
  auto p = params(6, 16);
  p.prefill = true;
  chamber::FlowModel m(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2));
  m.step(kRest, kRest, kComM, kComC, 1e-3, 0.0);
  const int n = 4000;
  double work = 0;
  Eigen::Vector3d x_prev = Eigen::Vector3d::Zero(), f_prev = Eigen::Vector3d::Zero();
  for (int i = 1; i <= n; ++i) {
    const double a = 0.010 * std::sin(M_PI * i / n);  // out to 10 mm and back
    const Eigen::Vector3d x(a * std::cos(0.3), a * std::sin(0.3), 0);
    const auto L = m.step(shifted(x), kRest, kComM, kComC, 1e-3, 0.0);
    work += 0.5 * (L.f_mantle + f_prev).dot(x - x_prev) * -1.0;  // work done on the rock = -(force on mantle) . dx
    x_prev = x, f_prev = L.f_mantle;
  }
  ASSERT_GT(m.events(), 3);
  EXPECT_GT(work, 0.0);
  EXPECT_NEAR(work, m.crushing_energy_J(), 0.01 * m.crushing_energy_J());
}

// Past max_compression the rock cannot compact: the cell keeps A g rho0 / (1 - s_max), the rest goes to the cell
// below, the pressure stays at E s_max^n, and the work of closing the gap further (p A dg) is booked with the loop's.
TEST(FlowModel, RockPressedPastTheCompactionLimitIsExtrudedAndItsWorkBooked) {
  auto p = params(6, 1);
  p.prefill = true;
  chamber::FlowModel m(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2));
  const std::size_t top = 5;  // the top band's one sector (azimuth 180 deg): nothing is pressed into it from above
  m.step(kRest, kRest, kComM, kComC, 1e-3, 0.0);
  const double total = m.mass_kg();
  const auto& mat = p.material;
  const int n = 3000;
  test_liners::PushAlongX push{m, kComM, kComC};
  for (int i = 1; i <= n; ++i) push.to(0.030 * i / n);  // gap 50 -> 20 mm: s = 0.6 > s_max 0.4
  EXPECT_NEAR(m.cell_gap(top), 0.020, 1e-9);
  EXPECT_NEAR(m.cell_mass(top), m.cell_area(top) * 0.020 * m.loose_density() / (1 - mat.max_compression),
              1e-9 * total);
  EXPECT_NEAR(m.mass_kg() + m.discharged_kg(), total, 1e-9 * total);  // extruded downwards and out, not lost
  EXPECT_GT(m.discharged_kg(), 0.0);
  EXPECT_NEAR(m.cell_pressure(top), mat.modulus_Pa * std::pow(mat.max_compression, mat.exponent),
              1e-6 * mat.modulus_Pa);
  EXPECT_GT(m.extrusion_energy_J(), 0.2 * m.crushing_energy_J());
  for (int i = n; i >= 0; --i) push.to(0.030 * i / n);  // released
  ASSERT_GE(m.events(), 1);
  EXPECT_NEAR(push.work, m.crushing_energy_J(), 0.01 * push.work);
}

// Rock pressed out of the nip at the compaction limit has had that pressing: one class of lumps, loose in the bottom
// band, pressed from loose to past s_max; what leaves is [B S(s_max) + I - S] of the mass pushed out, not unbroken
// lumps (the shipped 400 rpm run discharged 89 % of its product this way, half of it above 12 mm, before this law).
TEST(FlowModel, RockExtrudedAtTheCompactionLimitLeavesBrokenByThatPressing) {
  auto p = params(2, 1);
  p.prefill = false;
  p.choke_feed = false;
  chamber::FlowModel m(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2));
  const std::size_t k = 0, j = m.classes() - 4;  // the bottom band; 31.5-40 mm lumps
  std::vector<double> lumps(m.classes(), 0.0);
  lumps[j] = m.cell_area(k) * 0.050 * m.loose_density();  // loose in the 50 mm gap
  m.deposit(k, lumps);
  m.step(kRest, kRest, kComM, kComC, 1e-3, 0.0);
  ASSERT_EQ(m.discharged_kg(), 0.0);
  const int n = 300;
  for (int i = 1; i <= n; ++i) m.step(shifted({-0.03 * i / n, 0, 0}), kRest, kComM, kComC, 1e-3, 0.0);  // to 20 mm
  const double out = m.discharged_kg();
  ASSERT_GT(out, 0.2 * lumps[j]);
  std::vector<double> expect(m.classes(), 0.0);
  expect[j] = out;
  m.breakage().apply(p.material.max_compression, expect.data());
  ASSERT_GT(out - expect[j], 0.05 * out);  // the pressing breaks a fair share of the class
  for (std::size_t i = 0; i < m.classes(); ++i)
    EXPECT_NEAR(m.discharged_by_class()[i], expect[i], 1e-12 * out) << "class " << i;
  EXPECT_NEAR(m.mass_kg() + out, lumps[j], 1e-12 * lumps[j]);
  EXPECT_NEAR(m.product_compressions(), 1.0, 1e-12);  // the pressing counts as the rock's event
  // All of it was pressed out, A rho0 / (1 - s_max) x 0.1 mm in each step from the gap 30 mm (s = s_max) on, through
  // the gaps 29.9 ... 20.0 mm: their mean, 24.95 mm.
  EXPECT_NEAR(m.extruded_out_kg(), out, 1e-12 * out);
  EXPECT_NEAR(m.extruded_out_gap_kg_m() / m.extruded_out_kg(), 0.02495, 1e-9);
}

// One pressing breaks a lump once, however many bands it flows through: every band of one class of lumps, loose, is
// pressed from loose past s_max at once; rock pressed out of a band joins the pressing below, which it has had, and is
// pressed out again band after band. What leaves is [B S(s_max) + I - S] of the mass pushed out and has had one event,
// with 2, 5 or 12 bands (broken again in each band it crossed, the 12-band product had 2.7 events: the shipped model's
// product was finer with every band added, 58 -> 95 % passing 12 mm from 10 to 120 bands).
TEST(FlowModel, OnePressingBreaksRockOnceHoweverManyBandsItIsPressedThrough) {
  for (int bands : {2, 5, 12}) {
    auto p = params(bands, 1);
    p.prefill = false;
    p.choke_feed = false;
    chamber::FlowModel m(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2));
    const std::size_t j = m.classes() - 4;  // 31.5-40 mm lumps
    double fed = 0;
    for (std::size_t k = 0; k < m.cells(); ++k) {
      std::vector<double> lumps(m.classes(), 0.0);
      lumps[j] = m.cell_area(k) * 0.050 * m.loose_density();  // loose in the 50 mm gap
      m.deposit(k, lumps);
      fed += lumps[j];
    }
    m.step(kRest, kRest, kComM, kComC, 1e-3, 0.0);
    const int n = 300;
    for (int i = 1; i <= n; ++i) m.step(shifted({-0.03 * i / n, 0, 0}), kRest, kComM, kComC, 1e-3, 0.0);  // to 20 mm
    const double out = m.discharged_kg();
    ASSERT_GT(out, 0.2 * fed) << bands << " bands";
    std::vector<double> expect(m.classes(), 0.0);
    expect[j] = out;
    m.breakage().apply(p.material.max_compression, expect.data());
    for (std::size_t i = 0; i < m.classes(); ++i)
      EXPECT_NEAR(m.discharged_by_class()[i], expect[i], 1e-12 * out) << bands << " bands, class " << i;
    EXPECT_NEAR(m.mass_kg() + out, fed, 1e-12 * fed);
    EXPECT_NEAR(m.product_compressions(), 1.0, 1e-12) << bands << " bands";
  }
}

// Pressed-out rock keeps its pressing until its new cell releases: the top band at the limit, the bottom band loose with
// room (no load when the top's rock arrives), both pressed on to 30 mm; all that leaves has had one pressing to s_max
// (marked only when it arrived in a loaded cell, it was broken a second time in the bottom band).
TEST(FlowModel, RockPressedOutIntoALooseCellHasHadItsPressing) {
  auto p = params(2, 1);
  p.prefill = false;
  p.choke_feed = false;
  chamber::FlowModel m(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2));
  const double s_max = p.material.max_compression;
  const std::size_t j = m.classes() - 4;  // 31.5-40 mm lumps
  std::vector<double> loose(m.classes(), 0.0), full(m.classes(), 0.0);
  loose[j] = 0.8 * m.cell_area(0) * 0.050 * m.loose_density();  // room for the top's rock, no load
  full[j] = m.cell_area(1) * 0.050 * m.loose_density() / (1 - s_max);
  m.deposit(0, loose);
  m.deposit(1, full);
  m.step(kRest, kRest, kComM, kComC, 1e-3, 0.0);
  ASSERT_EQ(m.cell_pressure(0), 0.0);
  ASSERT_GT(m.cell_pressure(1), 0.0);
  const int n = 200;
  for (int i = 1; i <= n; ++i) m.step(shifted({-0.02 * i / n, 0, 0}), kRest, kComM, kComC, 1e-3, 0.0);  // to 30 mm
  const double out = m.discharged_kg();
  ASSERT_GT(out, 0.1 * (loose[j] + full[j]));
  std::vector<double> expect(m.classes(), 0.0);
  expect[j] = out;
  m.breakage().apply(s_max, expect.data());
  for (std::size_t i = 0; i < m.classes(); ++i)
    EXPECT_NEAR(m.discharged_by_class()[i], expect[i], 1e-12 * out) << "class " << i;
  EXPECT_NEAR(m.product_compressions(), 1.0, 1e-12);
}

// Rock at the compaction limit does not compact further: a column of bands all at the limit, closed by one more step,
// presses out of the bottom in that step all the rock the bands lose, with 2, 5 or 12 bands (one band per step before:
// only the bottom band's share left in the step, and the flow out of the nip slowed with every band added; the shipped
// 400 rpm throughput fell from 95 to 68 t/h from 10 to 240 bands).
TEST(FlowModel, RockPressedPastTheLimitLeavesAColumnAtTheLimitInTheSameStep) {
  for (int bands : {2, 5, 12}) {
    auto p = params(bands, 1);
    p.prefill = false;
    p.choke_feed = false;
    chamber::FlowModel m(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2));
    const double s_max = p.material.max_compression;
    const double g0 = 0.030, g1 = 0.029;  // the gap at the limit, then one step narrower
    double lost = 0;
    for (std::size_t k = 0; k < m.cells(); ++k) {
      std::vector<double> rock(m.classes(), 0.0);
      rock[m.classes() - 6] = m.cell_area(k) * g0 * m.loose_density() / (1 - s_max);  // 16-22.4 mm, at the limit
      m.deposit(k, rock);
      lost += rock[m.classes() - 6] * (1 - g1 / g0);
    }
    m.step(shifted({-0.02, 0, 0}), kRest, kComM, kComC, 1e-3, 0.0);  // the 50 mm gap closed to 30 mm
    ASSERT_NEAR(m.discharged_kg(), 0.0, 1e-9 * lost) << bands << " bands";
    m.step(shifted({-0.021, 0, 0}), kRest, kComM, kComC, 1e-3, 0.0);  // one step on, to 29 mm
    EXPECT_NEAR(m.discharged_kg(), lost, 1e-9 * lost) << bands << " bands";
    for (std::size_t k = 0; k < m.cells(); ++k)
      EXPECT_NEAR(m.cell_mass(k), m.cell_area(k) * g1 * m.loose_density() / (1 - s_max), 1e-9 * lost) << "cell " << k;
  }
}

// An open chamber (gap 100 mm, wider than any lump), no feed: rock put in the top band falls out freely; half of
// it has left at the free-fall time of the band's height, sqrt(2 H / g).
TEST(FlowModel, RockFallsThroughAnOpenChamberInTheFreeFallTime) {
  auto p = params(60, 4);
  chamber::FlowModel m(p, cylinder(0.25), cylinder(0.35, -0.8, -0.2));
  const std::size_t top = m.cells() - 4;
  std::vector<double> lumps(m.classes(), 0.0);
  lumps[m.classes() - 3] = 0.5;  // 40-50 mm, a third of the cell's loose capacity
  m.deposit(top, lumps);
  const double H = m.cell_point(top).z() - (-0.8), g = 9.81, h = 1e-4;
  double t = 0, t_half = -1;
  while (t < 1.0 && m.discharged_kg() < 0.5 - 1e-9) {
    m.step(kRest, kRest, kComM, kComC, h, g);
    t += h;
    if (t_half < 0 && m.discharged_kg() >= 0.25) t_half = t;
  }
  EXPECT_NEAR(t_half, std::sqrt(2 * H / g), 0.05 * std::sqrt(2 * H / g));
  EXPECT_NEAR(m.discharged_kg(), 0.5, 1e-9);
  EXPECT_EQ(m.events(), 0);
}

// Evertsson's flow law: rock in an open cell (gap 100 mm, no pressure) does not fall while the mantle closes the gap
// on it, and falls once the gap opens.
TEST(FlowModel, RockIsHeldWhileTheGapClosesAndFallsWhileItOpens) {
  auto p = params(10, 1);
  chamber::FlowModel m(p, cylinder(0.25), cylinder(0.35, -0.8, -0.2));
  std::vector<double> lumps(m.classes(), 0.0);
  lumps[m.classes() - 4] = 0.2;  // 31.5-40 mm, far below the cell's loose capacity: never pressed
  const std::size_t k = 5;       // band 5 of 10, its one sector at azimuth 180 deg
  m.deposit(k, lumps);
  const double h = 1e-3;
  m.step(kRest, kRest, kComM, kComC, h, 9.81);  // the reference gap (a still mantle: the rock starts to fall)
  const double start = m.cell_mass(k);
  for (int i = 1; i <= 200; ++i)  // the mantle moves towards the cell (-x): the gap closes from 100 to 60 mm
    m.step(shifted({-0.04 * i / 200.0, 0, 0}), kRest, kComM, kComC, h, 9.81);
  EXPECT_EQ(m.cell_mass(k), start);
  EXPECT_EQ(m.cell_pressure(k), 0.0);
  EXPECT_EQ(m.discharged_kg(), 0.0);
  for (int i = 199; i >= 150; --i)  // back out: the gap opens, the rock falls from rest
    m.step(shifted({-0.04 * i / 200.0, 0, 0}), kRest, kComM, kComC, h, 9.81);
  const double t = 0.05, fell = 0.5 * 9.81 * t * t;  // 12 mm in 50 ms: about a fifth of the 60 mm band
  EXPECT_LT(m.cell_mass(k), start - 0.1 * fell / 0.06 * start);
  EXPECT_GT(m.cell_mass(k), start - 0.6 * start);
}

// A still mantle: with a gap wider than the feed (80 mm) the choke feed passes whole and unbroken; with a gap of
// 30 mm the lumps above 30 mm are held in the chamber and only smaller ones reach the product.
TEST(FlowModel, AGapWiderThanTheFeedPassesItAndANarrowerOneHoldsTheLumps) {
  for (double gap : {0.080, 0.030}) {
    auto p = params(20, 4);
    p.choke_feed = true;
    chamber::FlowModel m(p, cylinder(0.3), cylinder(0.3 + gap, -0.8, -0.2));
    for (int i = 0; i < 20000; ++i) m.step(kRest, kRest, kComM, kComC, 2e-4, 9.81);
    ASSERT_GT(m.discharged_kg(), 1.0) << gap;
    EXPECT_EQ(m.events(), 0);
    EXPECT_EQ(m.extruded_out_kg(), 0.0);  // all of it fell out
    const auto out = m.discharged_by_class();
    const auto pass = m.passing(out);
    const auto& feed = p.feed_passing;
    if (gap > 0.05) {
      for (std::size_t k = 0; k < pass.size(); ++k) EXPECT_NEAR(pass[k], feed[k], 1e-9) << "sieve " << k;
    } else {
      for (std::size_t j = 0; j < m.classes(); ++j)
        if (m.breakage().lower(j) >= gap) EXPECT_EQ(out[j], 0.0) << "class " << j;
      EXPECT_GT(out[5], 0.0);  // 12-16 mm passes
      double held = 0;  // lumps above the gap pile up in the chamber
      for (std::size_t k = 0; k < m.cells(); ++k)
        for (std::size_t j = 0; j < m.classes(); ++j)
          if (m.breakage().lower(j) >= gap) held += m.cell_classes(k)[j];
      EXPECT_GT(held, 0.5 * (1 - feed[7]) * m.mass_kg());
    }
  }
}

// A long run of a gyrating mantle (throw 8 mm, 7 Hz) on the shipped-like cone chamber with choke feed: rock is fed,
// compressed, broken and discharged; feed = chamber + product to round-off, and a resumed copy stays bit for bit.
TEST(FlowModel, LongRunBalancesItsMassAndResumesBitForBit) {
  const core::Profile mantle = test_liners::gyp_mantle(), concave = test_liners::gyp_concave();
  chamber::FlowParams p = test_liners::cone_chamber_params();
  chamber::FlowModel m(p, mantle, concave);
  test_liners::nutate({&m}, 0, 1500);
  const auto resumed = test_liners::resumed(m, p, mantle, concave);
  chamber::FlowModel& copy = *resumed;
  test_liners::nutate({&m, &copy}, 1500, 3000);
  EXPECT_GT(m.events(), 100);
  EXPECT_GT(m.discharged_kg(), 10.0);
  EXPECT_NEAR(m.fed_kg(), m.mass_kg() + m.discharged_kg(), 1e-9 * m.fed_kg());
  EXPECT_EQ(m.mass_kg(), copy.mass_kg());
  EXPECT_EQ(m.discharged_by_class(), copy.discharged_by_class());
  EXPECT_EQ(m.crushing_energy_J(), copy.crushing_energy_J());
  EXPECT_EQ(m.extruded_out_kg(), copy.extruded_out_kg());
  EXPECT_EQ(m.extruded_out_gap_kg_m(), copy.extruded_out_gap_kg_m());
  EXPECT_GT(m.extruded_out_kg(), 0.0);
  EXPECT_LT(m.extruded_out_kg(), m.discharged_kg());  // some fell out, some was pressed out
  // A state is refused by a model of another material.
  auto q = p;
  q.material.modulus_Pa *= 1.01;
  chamber::FlowModel other(q, mantle, concave);
  std::stringstream again;
  core::BinaryWriter w1(again);
  m.save_state(w1);
  core::BinaryReader r1(again, "flow test checkpoint");
  try {
    other.load_state(r1);
    ADD_FAILURE() << "a state of another material was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("parameters differ"), std::string::npos) << e.what();
  }
  // The product is finer than the feed: the events broke lumps.
  const auto out = m.passing(m.discharged_by_class());
  EXPECT_GT(out[4], p.feed_passing[4] + 0.05);  // 12 mm
}

// A saved state carries the model's fingerprint and is refused when it differs, so its order is a file format: the
// order written before the material's list was shared with the coupled chamber (chamber_checkpoint.cpp), value by
// value, for the default rock and for one with every optional law on (scatter, held elastic past the limit).
TEST(FlowModel, FingerprintKeepsTheOrderOfTheStatesAlreadyWritten) {
  const core::Profile mantle = test_liners::gyp_mantle(), concave = test_liners::gyp_concave();
  chamber::FlowParams p;
  p.bands = 4;
  p.sectors = 4;
  auto expected = [](const chamber::FlowParams& q, std::vector<double> tail) {
    const auto& m = q.material;
    const auto& b = m.breakage;
    std::vector<double> f = q.sieves_m;
    f.insert(f.end(), q.feed_passing.begin(), q.feed_passing.end());
    f.insert(f.end(), {m.solid_density, m.loose_fraction, m.modulus_Pa, m.exponent, m.rebound, m.max_compression,
                       b.s_c, b.m, b.q, b.x_ref, b.x_resolved, b.q_below, b.phi, b.gamma, b.beta, double(q.prefill),
                       double(q.choke_feed), double(q.compaction_memory)});
    f.insert(f.end(), tail.begin(), tail.end());
    return f;
  };
  EXPECT_EQ(chamber::FlowModel(p, mantle, concave).fingerprint(), expected(p, {}));
  p.material.lump_std = 0.5;
  p.seed = 7;
  p.material.elastic_limit = true;
  EXPECT_EQ(chamber::FlowModel(p, mantle, concave).fingerprint(), expected(p, {0.5, 7.0, -4.0}));
  EXPECT_EQ(chamber::law_fingerprint(p.material), std::vector<double>{-4.0});
  p.material.elastic_limit = false;
  p.material.solid_divergence = true;
  p.material.max_compression = 0.9 * chamber::solid_compaction_limit(p.material.loose_fraction);
  EXPECT_EQ(chamber::law_fingerprint(p.material), std::vector<double>{-2.0});
}

// With memory, pressed rock released springs back by the law's rebound (unloaded below er = (1 - rebound) c), so it
// takes that room: feed poured onto it fills the gap and the cell is unloaded at the fill, loading again only as the
// gap closes. (When the room counted the rock at c, the fill put the cell on its reload branch at E c'^n at once: the
// top band was never free to fall and the feed opening jammed.)
TEST(FlowModel, CompactedRockTakesItsReboundedRoomSoAFillIsUnloaded) {
  auto p = params(6, 8);
  p.compaction_memory = true;
  p.choke_feed = true;
  chamber::FlowModel m(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2));
  const std::size_t k = 5 * 8 + 0;  // top band
  const double V0 = m.cell_area(k) * 0.05;
  std::vector<double> feed(m.classes(), 0.0);
  feed[m.classes() - 2] = V0 * m.loose_density();  // the 50 mm gap full, loose
  m.deposit(k, feed);
  const double m0 = m.cell_mass(k);
  const int n = 1000;
  shift_steps(m, 0.012, n, 1, n);  // the gap at sector 0 closes by about 11 mm
  const double s = 1 - m.cell_gap(k) / 0.05;
  ASSERT_GT(m.cell_pressure(k), 0.0);
  shift_steps(m, 0.012, n, n - 1, 0);  // open again to 50 mm: released, the feed fills the room
  const double c = s, r = p.material.rebound, cap = V0 * m.loose_density();
  EXPECT_NEAR(m.cell_mass(k), m0 + (cap - m0 * (1 - (1 - r) * c)), 1e-9 * cap);
  m.step(kRest, kRest, kComM, kComC, 1e-3, 0.0);
  const double c_mix = m0 * c / m.cell_mass(k);
  const double p_reload = p.material.modulus_Pa * std::pow(c_mix, p.material.exponent);
  EXPECT_LT(m.cell_pressure(k), 1e-9 * p_reload) << "the fill loaded the cell";
  shift_steps(m, 0.012, n, 1, 20);  // 0.24 mm closer: the mixture reloads from zero
  EXPECT_GT(m.cell_pressure(k), 0.0);
  EXPECT_LT(m.cell_pressure(k), p_reload);
}
