// The effect helpers the diagnosis and make_recording use (analysis/mbd_model.hpp) for the new candidates: each name
// switches on its module at its main parameter in the YAML unit, and only it; chamber effects go to the flow
// parameters and are refused by the mechanism's helper.
#include <gtest/gtest.h>

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

}  // namespace
