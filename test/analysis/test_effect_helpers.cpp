// The effect helpers the diagnosis and make_recording use (analysis/mbd_model.hpp) for the new candidates: each name
// switches on its module at its main parameter in the YAML unit, and only it; chamber effects go to the flow
// parameters and are refused by the mechanism's helper.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <stdexcept>
#include <string>

#include "analysis/mbd_model.hpp"

namespace {

TEST(EffectHelpers, NewMechanismEffectsTakeTheirMainParameterAndSwitchTheOthersOff) {
  mbd::MechanismParams base;
  base.effects.joint_friction.enabled = true;
  base.effects.drive_efficiency.no_load_W = 2e3;  // a secondary parameter of the base is kept
  const auto b = analysis::with_effect(base, "bearing_friction", 0.02);
  EXPECT_TRUE(b.effects.bearing_friction.enabled);
  EXPECT_DOUBLE_EQ(b.effects.bearing_friction.mu, 0.02);
  EXPECT_FALSE(b.effects.joint_friction.enabled);
  EXPECT_FALSE(b.effects.drive_efficiency.enabled);
  const auto d = analysis::with_effect(base, "drive_efficiency", 0.88);
  EXPECT_TRUE(d.effects.drive_efficiency.enabled);
  EXPECT_DOUBLE_EQ(d.effects.drive_efficiency.efficiency, 0.88);
  EXPECT_DOUBLE_EQ(d.effects.drive_efficiency.no_load_W, 2e3);
  EXPECT_FALSE(d.effects.bearing_friction.enabled);
  const auto n = analysis::with_effect(b, "none", 0);
  EXPECT_FALSE(n.effects.bearing_friction.enabled);
}

TEST(EffectHelpers, ChamberEffectsGoToTheFlowParametersInTheirUnits) {
  EXPECT_TRUE(analysis::is_flow_effect("feed_limited"));
  EXPECT_TRUE(analysis::is_flow_effect("worn_liners"));
  EXPECT_FALSE(analysis::is_flow_effect("bearing_friction"));
  chamber::FlowParams base;
  const auto f = analysis::with_flow_effect(base, "feed_limited", 72.0);
  EXPECT_TRUE(f.effects.feed_limited.enabled);
  EXPECT_NEAR(f.effects.feed_limited.max_feed_kg_s, 20.0, 1e-12);  // 72 t/h
  EXPECT_FALSE(f.effects.worn_liners.enabled);
  const auto w = analysis::with_flow_effect(f, "worn_liners", 7.5);
  EXPECT_TRUE(w.effects.worn_liners.enabled);
  EXPECT_NEAR(w.effects.worn_liners.setting_increase_m, 7.5e-3, 1e-15);
  EXPECT_FALSE(w.effects.feed_limited.enabled);
  EXPECT_TRUE(analysis::is_flow_effect("squeeze_flow"));
  const auto q = analysis::with_flow_effect(w, "squeeze_flow", 4.0);
  EXPECT_TRUE(q.effects.squeeze_flow.enabled);
  EXPECT_NEAR(q.effects.squeeze_flow.escape_length_m, 4e-3, 1e-15);
  EXPECT_FALSE(q.effects.worn_liners.enabled);
  EXPECT_TRUE(analysis::is_flow_effect("liner_friction"));
  const auto lf = analysis::with_flow_effect(q, "liner_friction", 0.35);
  EXPECT_TRUE(lf.effects.liner_friction.enabled);
  EXPECT_DOUBLE_EQ(lf.effects.liner_friction.wall_friction, 0.35);
  EXPECT_FALSE(lf.effects.squeeze_flow.enabled);
  EXPECT_THROW(analysis::with_flow_effect(base, "liner_friction", 3.0), std::invalid_argument);
  // A mechanism effect (or none) leaves every chamber effect off.
  EXPECT_FALSE(analysis::with_flow_effect(w, "bearing_friction", 0.02).effects.worn_liners.enabled);
  EXPECT_THROW(analysis::with_flow_effect(base, "worn_liner", 1.0), std::invalid_argument);
  EXPECT_THROW(analysis::with_flow_effect(base, "feed_limited", 0.0), std::invalid_argument);
  try {
    analysis::with_effect(mbd::MechanismParams(), "worn_liners", 5.0);
    FAIL() << "expected a throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("flow.effects.worn_liners"), std::string::npos) << e.what();
  }
}

// The one list of modules (effect_modules) agrees with the helpers: each name is switched on by its section's helper
// and is then the only module on; the names lists and is_flow_effect follow it; its test files exist.
TEST(EffectHelpers, TheModuleListSwitchesEachModuleAndOnlyIt) {
  const std::map<std::string, double> value = {
      {"joint_friction", 10.0},    {"absorber_nonlinearity", 1e9}, {"motor_droop", 0.5}, {"cardan_misalignment", 1.0},
      {"bearing_friction", 0.01},  {"drive_efficiency", 0.9},      {"feed_limited", 50}, {"worn_liners", 5.0},
      {"squeeze_flow", 4.0},       {"liner_friction", 0.3}};
  const auto& modules = analysis::effect_modules();
  ASSERT_EQ(modules.size(), value.size());
  for (const auto& m : modules) {
    ASSERT_TRUE(value.count(m.name)) << m.name;
    const bool flow = std::string(m.section) == "flow";
    EXPECT_EQ(analysis::is_flow_effect(m.name), flow) << m.name;
    const std::string names = flow ? analysis::flow_effect_names() : analysis::mbd_effect_names();
    EXPECT_NE((", " + names + ",").find(", " + std::string(m.name) + ","), std::string::npos) << m.name;
    const mbd::MechanismParams mech = analysis::with_effect(mbd::MechanismParams(), flow ? "none" : m.name,
                                                            flow ? 0.0 : value.at(m.name));
    const chamber::FlowParams fp = analysis::with_flow_effect(chamber::FlowParams(), m.name, value.at(m.name));
    for (const auto& o : modules) EXPECT_EQ(o.enabled(mech, fp), &o == &m) << m.name << " switched " << o.name;
    EXPECT_TRUE(std::ifstream(std::string(CRUSHER_SOURCE_DIR) + "/" + m.test).good()) << m.test;
  }
}

// The module terms go through the diagnosis's config model (ConfigModel::with: YAML keys): each switches its module on
// at the value given, and at its nominal value leaves it off.
TEST(EffectHelpers, ModuleTermsSwitchTheirModulesThroughTheConfigKeys) {
  const analysis::ConfigModel cfg(std::string(CRUSHER_SOURCE_DIR) + "/launch_free_configs/gyp1200_400rpm.yaml");
  const auto terms = analysis::module_candidates();
  ASSERT_EQ(terms.size(), 6u);
  for (const auto& t : terms) {
    EXPECT_TRUE(t.lo <= t.nominal && t.nominal <= t.hi) << t.name;
    const double v = 0.5 * (t.lo + t.hi);
    const auto on = cfg.flow_run({{t.name, v}}, terms), off = cfg.flow_run({{t.name, t.nominal}}, terms);
    // The selection's uncertainty steps next to the nominal (1 and 2 % of the range, selection.cpp) are real values
    // in the keys' units: no unit-slip band refuses them (0.3 mm of wear, 0.15 mm escape length).
    const double step = 0.01 * (t.hi - t.lo) * (t.nominal < t.hi ? 1.0 : -1.0);
    EXPECT_NO_THROW(cfg.flow_run({{t.name, t.nominal + step}}, terms)) << t.name;
    EXPECT_NO_THROW(cfg.flow_run({{t.name, t.nominal + 2 * step}}, terms)) << t.name;
    const auto& e = on.mech.effects;
    const auto& f = on.flow.effects;
    if (t.name == "bearing_friction") {
      EXPECT_TRUE(e.bearing_friction.enabled);
      EXPECT_DOUBLE_EQ(e.bearing_friction.mu, v);
      EXPECT_FALSE(off.mech.effects.bearing_friction.enabled);
    } else if (t.name == "drive_efficiency") {
      EXPECT_TRUE(e.drive_efficiency.enabled);
      EXPECT_DOUBLE_EQ(e.drive_efficiency.efficiency, v);
      EXPECT_FALSE(off.mech.effects.drive_efficiency.enabled);
    } else if (t.name == "feed_limited") {
      EXPECT_TRUE(f.feed_limited.enabled);
      EXPECT_NEAR(f.feed_limited.max_feed_kg_s, v / 3.6, 1e-12);
      EXPECT_FALSE(off.flow.effects.feed_limited.enabled);
    } else if (t.name == "worn_liners") {
      EXPECT_TRUE(f.worn_liners.enabled);
      EXPECT_NEAR(f.worn_liners.setting_increase_m, v * 1e-3, 1e-15);
      EXPECT_FALSE(off.flow.effects.worn_liners.enabled);
    } else if (t.name == "squeeze_flow") {
      EXPECT_TRUE(f.squeeze_flow.enabled);
      EXPECT_NEAR(f.squeeze_flow.escape_length_m, v * 1e-3, 1e-15);
      EXPECT_FALSE(off.flow.effects.squeeze_flow.enabled);
    } else if (t.name == "liner_friction") {
      EXPECT_TRUE(f.liner_friction.enabled);
      EXPECT_DOUBLE_EQ(f.liner_friction.wall_friction, v);
      EXPECT_FALSE(off.flow.effects.liner_friction.enabled);
    } else {
      ADD_FAILURE() << "unexpected term " << t.name;
    }
  }
}

}  // namespace
