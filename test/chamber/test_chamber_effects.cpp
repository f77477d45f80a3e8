// The chamber candidates of the diagnosis (flow_model.hpp FlowEffects, liner_wear.hpp) against closed forms and
// clean limits: a feeder below the choke-fed throughput sets the throughput; a worn concave widens the gap by the
// wear depth (times the liners' slope ratio) and lets more, coarser rock through.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "../common/coaxial_liners.hpp"
#include "../common/flow_params.hpp"
#include "chamber/flow_config.hpp"
#include "chamber/flow_model.hpp"
#include "chamber/liner_wear.hpp"
#include "chamber/squeeze_flow.hpp"
#include "core/config.hpp"

namespace {

const Eigen::Isometry3d kRest = Eigen::Isometry3d::Identity();
const Eigen::Vector3d kComM(0, 0, -0.5), kComC(0, 0, -0.6);

// The shipped-like cone chamber of test_flow_model's long run (bottom to top).
void cone(core::Profile* mantle, core::Profile* concave) {
  mantle->z = {-0.715, -0.2};
  mantle->r = {0.600, 0.168};
  concave->z = {-0.760, -0.1};
  concave->r = {0.662, 0.194};
}

struct Window {
  double throughput_kg_s = 0, feed_kg_s = 0, passing_12mm = 0, chamber_kg = 0, crushing_W = 0;
};

// A gyrating mantle (0.014 rad, 7 Hz) with choke feed: the figures over [t0, t1] s.
Window gyrate(const chamber::FlowParams& p, double t0, double t1) {
  core::Profile mantle, concave;
  cone(&mantle, &concave);
  chamber::FlowModel m(p, mantle, concave);
  const double h = 1e-3, w = 2 * M_PI * 7;
  auto pose = [&](double t) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(0.014, Eigen::Vector3d(-std::sin(w * t), std::cos(w * t), 0)).toRotationMatrix();
    return T;
  };
  const long n0 = std::lround(t0 / h), n1 = std::lround(t1 / h);
  std::vector<double> out0;
  double fed0 = 0, e0 = 0;
  for (long i = 0; i < n1; ++i) {
    if (i == n0) out0 = m.discharged_by_class(), fed0 = m.fed_kg(), e0 = m.crushing_energy_J();
    m.step(pose(i * h), kRest, kComM, kComC, h, 9.81);
  }
  std::vector<double> c = m.discharged_by_class();
  double kg = 0;
  for (std::size_t j = 0; j < c.size(); ++j) kg += (c[j] -= out0[j]);
  Window r;
  r.throughput_kg_s = kg / (t1 - t0);
  r.feed_kg_s = (m.fed_kg() - fed0) / (t1 - t0);
  r.passing_12mm = m.passing(c)[4];
  r.chamber_kg = m.mass_kg();
  r.crushing_W = (m.crushing_energy_J() - e0) / (t1 - t0);
  return r;
}

// A feeder at half the choke-fed throughput: the chamber drains to the level that passes the feed, and then the
// throughput is the feeder's rate (mass balance), to 2 %; the feed is the rate exactly while the top has room.
TEST(FeedLimited, AFeederBelowTheChokeThroughputSetsTheThroughput) {
  const Window choke = gyrate(test_liners::cone_chamber_params(), 2.0, 4.0);
  auto p = test_liners::cone_chamber_params();
  p.effects.feed_limited.enabled = true;
  p.effects.feed_limited.max_feed_kg_s = 0.5 * choke.throughput_kg_s;
  p.prefill = false;  // starts empty: fills to the feed-limited level
  const Window lim = gyrate(p, 10.0, 16.0);
  std::printf("feed limited: choke-fed throughput %.3f kg/s (feed %.3f, charge %.1f kg, 12 mm %.3f); feeder %.3f kg/s -> "
              "throughput %.3f kg/s, feed %.3f kg/s, charge %.1f kg, passing 12 mm %.3f\n",
              choke.throughput_kg_s, choke.feed_kg_s, choke.chamber_kg, choke.passing_12mm,
              p.effects.feed_limited.max_feed_kg_s, lim.throughput_kg_s, lim.feed_kg_s, lim.chamber_kg,
              lim.passing_12mm);
  const double cap = p.effects.feed_limited.max_feed_kg_s;
  ASSERT_GT(choke.throughput_kg_s, 0.5);
  EXPECT_NEAR(lim.feed_kg_s, cap, 1e-9 * cap);
  EXPECT_NEAR(lim.throughput_kg_s, cap, 0.02 * cap);
  EXPECT_LT(lim.chamber_kg, choke.chamber_kg);  // a starved chamber holds less rock
}

// A feeder above what the chamber passes changes nothing that matters: the chamber stays choke fed.
TEST(FeedLimited, AFeederAboveTheChokeThroughputLeavesTheChamberChokeFed) {
  const Window choke = gyrate(test_liners::cone_chamber_params(), 2.0, 3.0);
  auto p = test_liners::cone_chamber_params();
  p.effects.feed_limited.enabled = true;
  p.effects.feed_limited.max_feed_kg_s = 1e3;
  const Window lim = gyrate(p, 2.0, 3.0);
  EXPECT_NEAR(lim.throughput_kg_s, choke.throughput_kg_s, 0.02 * choke.throughput_kg_s);
}

TEST(WornLiners, WearDepthIsFullAtTheDischargeAndZeroAboveTheWornZone) {
  chamber::WornLiners w;
  w.enabled = true;
  w.setting_increase_m = 0.012;
  w.worn_height_fraction = 0.4;
  EXPECT_DOUBLE_EQ(chamber::wear_depth(w, -0.7, -0.2, -0.7), 0.012);
  EXPECT_NEAR(chamber::wear_depth(w, -0.7, -0.2, -0.5), 0.0, 1e-15);  // the top of the worn zone
  EXPECT_DOUBLE_EQ(chamber::wear_depth(w, -0.7, -0.2, -0.3), 0.0);
  EXPECT_NEAR(chamber::wear_depth(w, -0.7, -0.2, -0.6), 0.006, 1e-15);  // linear in between
}

// The gap each cell sees, new and worn, at rest: it grows by the wear depth times |t_z,mantle| / |t_z,concave| (the
// concave moved out along its normal by the depth; the gap measured along the mantle's normal), exactly, wherever the
// gap's foot lies on the mantle (on the cone the bottom bands' gap runs to the mantle's lower edge: more); on coaxial
// cylinders by the depth itself.
TEST(WornLiners, TheGapGrowsByTheWearDepthAlongTheChamber) {
  for (bool cylinders : {true, false}) {
    core::Profile mantle, concave;
    if (cylinders) {
      mantle = test_liners::cylinder(0.30);
      concave = test_liners::cylinder(0.33);
    } else {
      cone(&mantle, &concave);
    }
    auto p = test_liners::flow_params(40, 4);
    auto q = p;
    q.effects.worn_liners.enabled = true;
    q.effects.worn_liners.setting_increase_m = 0.010;
    q.effects.worn_liners.worn_height_fraction = 0.5;
    chamber::FlowModel m(p, mantle, concave), worn(q, mantle, concave);
    m.step(kRest, kRest, kComM, kComC, 1e-3, 0.0);
    worn.step(kRest, kRest, kComM, kComC, 1e-3, 0.0);
    auto tz = [](const core::Profile& f) {
      return std::fabs(f.z[1] - f.z[0]) / std::hypot(f.z[1] - f.z[0], f.r[1] - f.r[0]);
    };
    const double slope = tz(mantle) / tz(concave);
    const double z_lo = m.band_bottom(0), z_hi = m.band_bottom(m.bands());
    // The mantle's outward normal's z component: the gap's foot lies g n_z below the cell's point.
    const double n_z = (mantle.r[0] - mantle.r[1]) / std::hypot(mantle.z[1] - mantle.z[0], mantle.r[1] - mantle.r[0]) *
                       (mantle.z[1] > mantle.z[0] ? 1 : -1);
    const double mantle_bottom = std::min(mantle.z[0], mantle.z[1]);
    int checked = 0;
    for (int b = 0; b < m.bands(); ++b) {
      const std::size_t k = static_cast<std::size_t>(b) * m.sectors();
      const double z = m.cell_point(k).z();
      if (z - worn.cell_gap(k) * n_z < mantle_bottom + 1e-9) continue;  // the foot is the mantle's edge
      ++checked;
      const double depth = chamber::wear_depth(q.effects.worn_liners, z_lo, z_hi, z);
      EXPECT_NEAR(worn.cell_gap(k) - m.cell_gap(k), depth * slope, 1e-12) << (cylinders ? "cylinders" : "cone")
                                                                            << ", band " << b;
    }
    EXPECT_GE(checked, m.bands() - 4);
    std::printf("worn liners (%s): %d of %d bands on the closed form; bottom band gap %.2f -> %.2f mm (depth there "
                "%.2f mm, slope ratio %.4f)\n",
                cylinders ? "cylinders" : "cone", checked, m.bands(), m.cell_gap(0) * 1e3, worn.cell_gap(0) * 1e3,
                chamber::wear_depth(q.effects.worn_liners, z_lo, z_hi, m.cell_point(0).z()) * 1e3, slope);
  }
}

// Gyrating, choke fed: the wider lower chamber lets more rock through, and coarser.
TEST(WornLiners, AWiderSettingRaisesTheThroughputAndCoarsensTheProduct) {
  const Window base = gyrate(test_liners::cone_chamber_params(), 2.0, 4.0);
  auto p = test_liners::cone_chamber_params();
  p.effects.worn_liners.enabled = true;
  p.effects.worn_liners.setting_increase_m = 0.010;
  const Window worn = gyrate(p, 2.0, 4.0);
  std::printf("worn liners 10 mm: throughput %.3f -> %.3f kg/s, passing 12 mm %.3f -> %.3f, crushing %.2f -> %.2f kW\n",
              base.throughput_kg_s, worn.throughput_kg_s, base.passing_12mm, worn.passing_12mm,
              base.crushing_W / 1e3, worn.crushing_W / 1e3);
  EXPECT_GT(worn.throughput_kg_s, 1.05 * base.throughput_kg_s);
  EXPECT_LT(worn.passing_12mm, base.passing_12mm);
}

TEST(ChamberEffects, KeysLoadWithTheirUnitsAndBadValuesAreRefusedByName) {
  const auto f = chamber::load_flow_params(core::ConfigNode::load_string(
      "effects:\n  feed_limited: {enabled: true, max_feed_tph: 36}\n"
      "  worn_liners: {enabled: true, setting_increase_mm: 8, worn_height_fraction: 0.3}\n",
      "test"));
  EXPECT_TRUE(f.effects.feed_limited.enabled);
  EXPECT_NEAR(f.effects.feed_limited.max_feed_kg_s, 10.0, 1e-12);
  EXPECT_NEAR(f.effects.worn_liners.setting_increase_m, 0.008, 1e-15);
  EXPECT_DOUBLE_EQ(f.effects.worn_liners.worn_height_fraction, 0.3);
  try {
    chamber::load_flow_params(
        core::ConfigNode::load_string("effects:\n  worn_liners: {enabled: true, setting_increase_mm: 300}\n", "test"));
    FAIL() << "expected a throw";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("setting_increase_mm"), std::string::npos) << e.what();
  }
}

// Issue 22: flow sizes given in metres (inside the keys' ranges but ~1000x small) are refused as a unit slip, naming the
// key and the likely unit; 0 (no wear, no resolved size) and small-but-real sizes (a 63 um sieve) pass.
TEST(ChamberEffects, SizesGivenInMetresAreRefusedAsAUnitSlip) {
  auto error_of = [](const std::string& yaml) -> std::string {
    try {
      chamber::load_flow_params(core::ConfigNode::load_string(yaml, "test"));
      return "";
    } catch (const core::ConfigError& e) {
      return e.what();
    }
  };
  const std::pair<const char*, const char*> slips[] = {
      {"sieves_mm: [0.016, 0.0224, 0.0315, 0.05]\n", "sieves_mm"},
      {"effects:\n  worn_liners: {enabled: true, setting_increase_mm: 0.01}\n", "setting_increase_mm"},
      {"material:\n  selection: {x_ref_mm: 0.01}\n", "x_ref_mm"},
      {"material:\n  selection: {resolved_mm: 0.0224}\n", "resolved_mm"},
  };
  for (const auto& [yaml, key] : slips) {
    const std::string e = error_of(yaml);
    EXPECT_NE(e.find(key), std::string::npos) << yaml << ": " << e;
    EXPECT_NE(e.find("metres given for mm?"), std::string::npos) << yaml << ": " << e;
  }
  EXPECT_EQ(error_of("sieves_mm: [0.063, 1, 4, 12, 50]\n"), "");
  EXPECT_EQ(error_of("effects:\n  worn_liners: {enabled: true, setting_increase_mm: 0}\n"), "");
  EXPECT_EQ(error_of("material:\n  selection: {resolved_mm: 0}\n"), "");
}

// The friction hill: a slice of a layer of thickness g between walls of friction mu balances g dp/dx = 2 mu p
// (integrated here step by step, RK4), so p(x) / p0 = exp(2 mu x / g); no friction or no length: no rise; a closed
// gap: finite.
TEST(SqueezeFlow, PressureRisesAsTheSlabBalanceOfALayerBetweenRoughWalls) {
  for (double mu : {0.3, 0.7})
    for (double g : {0.004, 0.02}) {
      const double x = 0.0085;
      const int n = 2000;
      const double h = x / n;
      auto dp = [&](double q) { return 2 * mu * q / g; };
      double p = 1.0;
      for (int i = 0; i < n; ++i) {
        const double k1 = dp(p), k2 = dp(p + 0.5 * h * k1), k3 = dp(p + 0.5 * h * k2), k4 = dp(p + h * k3);
        p += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      }
      EXPECT_NEAR(chamber::squeeze_flow_factor(mu, x, g), p, 1e-9 * p) << "mu " << mu << " g " << g;
    }
  EXPECT_EQ(chamber::squeeze_flow_factor(0.0, 0.01, 0.001), 1.0);
  EXPECT_EQ(chamber::squeeze_flow_factor(0.7, 0.0, 0.001), 1.0);
  EXPECT_TRUE(std::isfinite(chamber::squeeze_flow_factor(0.7, 0.01, 0.0)));
}

// In the model: coaxial cylinders, every band pressed past the compaction limit (gap 50 -> 20 mm). With the effect,
// each band holds E s_max^n exp(2 mu x / g) (mu 0.7, escape length x 15 mm: e^1.05), whatever the number of bands
// (6 or 12: the law does not see the grid); off, E s_max^n. The top band keeps the limit's mass either way (the
// limit is the solid's), and the liners' work on the rock is still the energy booked, to 1 %.
TEST(SqueezeFlow, CellsPressedOutAtTheLimitHoldTheFrictionHillWhateverTheGrid) {
  for (int bands : {6, 12})
    for (bool on : {false, true}) {
      auto p = test_liners::flow_params(bands, 1);
      p.prefill = true;
      p.effects.squeeze_flow.enabled = on;
      p.effects.squeeze_flow.escape_length_m = 0.015;
      chamber::FlowModel m(p, test_liners::cylinder(0.3), test_liners::cylinder(0.35, -0.8, -0.2));
      m.step(kRest, kRest, kComM, kComC, 1e-3, 0.0);
      const auto& mat = p.material;
      const int n = 3000;
      test_liners::PushAlongX push{m, kComM, kComC};
      for (int i = 1; i <= n; ++i) push.to(0.030 * i / n);
      const double p_lim = mat.modulus_Pa * std::pow(mat.max_compression, mat.exponent);
      const double expect = on ? p_lim * std::exp(2 * 0.7 * 0.015 / 0.020) : p_lim;
      for (std::size_t b = 0; b < static_cast<std::size_t>(bands); ++b) {
        ASSERT_NEAR(m.cell_gap(b), 0.020, 1e-9);
        EXPECT_NEAR(m.cell_pressure(b), expect, 1e-6 * expect) << bands << " bands, " << (on ? "on" : "off")
                                                               << ", band " << b;
      }
      const std::size_t top = bands - 1;
      EXPECT_NEAR(m.cell_mass(top), m.cell_area(top) * 0.020 * m.loose_density() / (1 - mat.max_compression),
                  1e-9 * m.cell_mass(top));
      for (int i = n; i >= 0; --i) push.to(0.030 * i / n);
      EXPECT_NEAR(push.work, m.crushing_energy_J(), 0.01 * push.work) << bands << " bands, " << (on ? "on" : "off");
    }
}

// Each YAML of effects.<effect> is refused with an error naming its words.
void expect_refused(const std::string& effect, const std::vector<std::pair<const char*, const char*>>& bad) {
  for (const auto& [yaml, words] : bad) {
    try {
      chamber::load_flow_params(core::ConfigNode::load_string("effects:\n  " + effect + ": " + yaml, "test"));
      ADD_FAILURE() << "expected a throw: " << yaml;
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << yaml << ": " << e.what();
    }
  }
}

TEST(SqueezeFlow, KeysLoadAndBadValuesAreRefusedByName) {
  const auto f = chamber::load_flow_params(core::ConfigNode::load_string(
      "effects:\n  squeeze_flow: {enabled: true, wall_friction: 0.5, escape_length_mm: 12}\n", "test"));
  EXPECT_TRUE(f.effects.squeeze_flow.enabled);
  EXPECT_DOUBLE_EQ(f.effects.squeeze_flow.wall_friction, 0.5);
  EXPECT_NEAR(f.effects.squeeze_flow.escape_length_m, 0.012, 1e-15);
  EXPECT_DOUBLE_EQ(chamber::FlowParams().effects.squeeze_flow.wall_friction, 0.7);  // Table 4, rock on steel
  expect_refused("squeeze_flow", {{"{enabled: true, wall_friction: 7}", "wall_friction"},
                                  {"{enabled: true, escape_length_mm: 0.012}", "metres given for mm?"},
                                  // blows up the explicit coupling
                                  {"{enabled: true, escape_length_mm: 30}", "escape_length_mm"}});
}

}  // namespace

// The rock's friction on the liners (liner_friction.hpp): mu N tanh(|v_t| / v_reg) against the mantle's tangential
// slip, the normal part of the relative velocity left out; no load or no slip: none; far above v_reg: Coulomb's mu N.
TEST(LinerFriction, CoulombAgainstTheTangentialSlip) {
  chamber::LinerFriction f;
  f.wall_friction = 0.7;
  f.regularisation_m_s = 0.05;
  const Eigen::Vector3d n = Eigen::Vector3d(1, 2, 2) / 3.0, t = Eigen::Vector3d(2, -2, 1) / 3.0;  // n . t = 0
  chamber::LinerTwists tw;
  tw.v_mantle = 0.3 * n + 0.02 * t;  // closing at 0.3 m/s, sliding at 20 mm/s
  const Eigen::Vector3d com(0.1, -0.2, 0.4), x(0.5, 0.1, -0.3);
  const Eigen::Vector3d v_t = chamber::liner_slip(tw, x, n, com, com);
  EXPECT_NEAR((v_t - 0.02 * t).norm(), 0.0, 1e-15);
  const Eigen::Vector3d F = chamber::liner_friction_force(f, 1000.0, v_t);
  EXPECT_NEAR(F.norm(), 0.7 * 1000.0 * std::tanh(0.02 / 0.05), 1e-9);
  EXPECT_NEAR(F.normalized().dot(t), -1.0, 1e-12);
  EXPECT_NEAR(chamber::liner_friction_force(f, 1000.0, 0.6 * t).norm(), 700.0, 1e-6);  // 12 v_reg: mu N to 1e-9
  EXPECT_EQ(chamber::liner_friction_force(f, 0.0, v_t), Eigen::Vector3d::Zero());
  EXPECT_EQ(chamber::liner_friction_force(f, 1000.0, Eigen::Vector3d::Zero()), Eigen::Vector3d::Zero());
  // A spinning concave under a still mantle slips the other way: the slip is the mantle's relative to the concave.
  chamber::LinerTwists spin;
  spin.w_concave = Eigen::Vector3d(0, 0, 2.0);
  const Eigen::Vector3d xr(0.5, 0, 0), nr(1, 0, 0);
  EXPECT_NEAR((chamber::liner_slip(spin, xr, nr, com, Eigen::Vector3d::Zero()) - Eigen::Vector3d(0, -1.0, 0)).norm(),
              0.0, 1e-15);
}

// In the model: coaxial cylinders, the mantle pressed 20 mm to one side, then spinning about its own axis at w. Every
// pressed cell adds mu p A tanh(w rho / v_reg) against the slip at the middle of its gap (rho from the mantle's axis), so
// the mantle's torque about its axis is minus the sum of mu p A tanh(.) rho; the concave gets the reaction (forces and
// torques about a common point sum to zero); the friction's work booked is the sum of mu p A tanh(.) w rho h, apart
// from the crushing energy; without the effect the twists change nothing. A checkpoint carries the friction's work and
// the effect (a model without it refuses the file).
TEST(LinerFriction, ASpinningMantleGetsTheFrictionTorqueAndTheConcaveItsReaction) {
  const auto mantle = test_liners::cylinder(0.3), concave = test_liners::cylinder(0.35, -0.8, -0.2);
  const double h = 1e-3, w = 0.8, dx = 0.02;
  const Eigen::Vector3d com_m(dx, 0, -0.5);
  auto run = [&](bool on, chamber::FlowParams* params) {
    auto p = test_liners::flow_params(6, 16, true);
    p.effects.liner_friction.enabled = on;
    *params = p;
    auto m = std::make_unique<chamber::FlowModel>(p, mantle, concave);
    m->step(kRest, kRest, kComM, kComC, h, 0.0);
    for (int i = 1; i <= 200; ++i) m->step(test_liners::shifted({dx * i / 200, 0, 0}), kRest, com_m, kComC, h, 0.0);
    return m;
  };
  chamber::LinerTwists tw;
  tw.w_mantle = Eigen::Vector3d(0, 0, w);
  const auto pose = test_liners::shifted({dx, 0, 0});
  chamber::FlowParams p_off, p_on;
  auto off = run(false, &p_off);
  const auto plain = off->step(pose, kRest, com_m, kComC, h, 0.0);
  auto off2 = run(false, &p_off);
  const auto twisted = off2->step(pose, kRest, com_m, kComC, h, 0.0, &tw);
  EXPECT_EQ(plain.f_mantle, twisted.f_mantle);
  EXPECT_EQ(plain.t_mantle, twisted.t_mantle);
  EXPECT_EQ(off2->friction_energy_J(), 0.0);

  auto m = run(true, &p_on);
  const double e0 = m->crushing_energy_J();
  const auto L = m->step(pose, kRest, com_m, kComC, h, 0.0, &tw);
  const auto& lf = p_on.effects.liner_friction;
  double torque = 0, power = 0, normal = 0;
  int pressed = 0;
  for (std::size_t k = 0; k < m->cells(); ++k) {
    const double N = m->cell_pressure(k) * m->cell_area(k);
    if (N <= 0) continue;
    ++pressed;
    const Eigen::Vector3d x = m->cell_point(k);
    const double rho = std::hypot(x.x() - dx, x.y()) - 0.5 * m->cell_gap(k);  // middle of the gap, from the mantle's axis
    const double f = lf.wall_friction * N * std::tanh(w * rho / lf.regularisation_m_s);
    torque -= f * rho, power += f * w * rho, normal += N;
  }
  ASSERT_GT(pressed, 0);
  EXPECT_NEAR(L.normal_force, normal, 1e-9 * normal);
  EXPECT_NEAR(L.t_mantle.z(), torque, 1e-9 * std::abs(torque));
  EXPECT_LT(torque, -0.1 * 0.7 * normal * 0.3);  // the friction is not small beside mu N rho
  EXPECT_NEAR((L.f_mantle + L.f_concave).norm(), 0.0, 1e-9 * normal);
  const Eigen::Vector3d about_origin = L.t_mantle + com_m.cross(L.f_mantle) + L.t_concave + kComC.cross(L.f_concave);
  EXPECT_NEAR(about_origin.norm(), 0.0, 1e-9 * normal);
  EXPECT_NEAR(m->friction_energy_J(), power * h, 1e-9 * power * h);
  EXPECT_NEAR(m->crushing_energy_J(), e0, 1e-9 * e0);  // the pose did not change: no crushing work in that step

  auto copy = test_liners::resumed(*m, p_on, mantle, concave);
  EXPECT_EQ(copy->friction_energy_J(), m->friction_energy_J());
  std::stringstream file;
  core::BinaryWriter wr(file);
  m->save_state(wr);
  chamber::FlowModel without(p_off, mantle, concave);
  core::BinaryReader rd(file, "flow test checkpoint");
  EXPECT_THROW(without.load_state(rd), std::exception);
}

TEST(LinerFriction, KeysLoadAndBadValuesAreRefusedByName) {
  const auto f = chamber::load_flow_params(core::ConfigNode::load_string(
      "effects:\n  liner_friction: {enabled: true, wall_friction: 0.5, regularisation_mm_s: 20}\n", "test"));
  EXPECT_TRUE(f.effects.liner_friction.enabled);
  EXPECT_DOUBLE_EQ(f.effects.liner_friction.wall_friction, 0.5);
  EXPECT_NEAR(f.effects.liner_friction.regularisation_m_s, 0.02, 1e-15);
  EXPECT_DOUBLE_EQ(chamber::FlowParams().effects.liner_friction.wall_friction, 0.7);  // Table 4, rock on steel
  EXPECT_FALSE(chamber::FlowParams().effects.liner_friction.enabled);
  expect_refused("liner_friction", {{"{enabled: true, wall_friction: 7}", "wall_friction"},
                                    {"{enabled: true, regularisation_mm_s: 0}", "regularisation_mm_s"}});
}
