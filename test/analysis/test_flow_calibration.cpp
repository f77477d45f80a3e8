// The flow mode's 400 rpm calibration (analysis/flow_calibration.hpp) and the jackknife standard error that
// `validate --rock-spread` takes over the recalibrations of the jackknife materials (analysis/jackknife.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "analysis/flow_calibration.hpp"
#include "analysis/jackknife.hpp"
#include "chamber/flow_config.hpp"

namespace {
std::string config(const std::string& name) { return std::string(CRUSHER_SOURCE_DIR) + "/launch_free_configs/" + name; }
}  // namespace

// For the mean, the leave-one-out means' jackknife std is the sample std / sqrt(K), exactly (Efron & Tibshirani 11.5).
TEST(Jackknife, OfTheMeanIsTheStandardErrorOfTheMean) {
  const std::vector<double> x{3.1, -0.4, 7.25, 2.0, 5.5};
  const double K = x.size();
  double mean = 0, var = 0;
  for (double v : x) mean += v / K;
  for (double v : x) var += (v - mean) * (v - mean) / (K - 1);
  std::vector<double> loo;
  for (std::size_t i = 0; i < x.size(); ++i) loo.push_back((mean * K - x[i]) / (K - 1));
  EXPECT_NEAR(analysis::jackknife_std(loo), std::sqrt(var / K), 1e-12);
  // a plain std of the leave-one-out values would be (K - 1) times too small: the jackknife's inflation matters
  EXPECT_GT(analysis::jackknife_std(loo), 3.5 * std::sqrt(var / K) / (K - 1));
  EXPECT_TRUE(std::isnan(analysis::jackknife_std({1.0})));
  EXPECT_TRUE(std::isnan(analysis::jackknife_std({1.0, std::nan("")})));
}

// The unknowns land where they should: the static moment as given, the radius changes at the discharge (the
// concave's lower end) and the feed opening (its upper end); the calibration refuses the validation speed.
TEST(FlowCalibration, UnknownsApplyToTheirEndsAndTheValidationSpeedIsRefused) {
  const auto c4 = chamber::load_flow_run_config(config("gyp1200_400rpm.yaml"));
  const auto m = analysis::apply_flow_unknowns(c4.mech, {100.0, -3.0, 5.0});
  EXPECT_EQ(m.vibrator_static_moment_kg_m, 100.0);
  const auto& z = c4.mech.chamber.concave.z;
  const std::size_t bottom = z.front() < z.back() ? 0 : z.size() - 1, top = z.size() - 1 - bottom;
  EXPECT_NEAR(m.chamber.concave.r[bottom] - c4.mech.chamber.concave.r[bottom], -3e-3, 1e-12);
  EXPECT_NEAR(m.chamber.concave.r[top] - c4.mech.chamber.concave.r[top], 5e-3, 1e-12);
  EXPECT_THROW(analysis::apply_flow_unknowns(c4.mech, {100.0}), std::invalid_argument);
  const auto c6 = chamber::load_flow_run_config(config("gyp1200_600rpm.yaml"));
  analysis::FlowRunOptions o;
  o.duration_s = 1, o.settle_s = 1;
  try {
    analysis::calibrate_flow_machine(c6.mech, c6.flow, o, 4);
    FAIL() << "calibrated at 600 rpm";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("600 rpm is the validation case"), std::string::npos) << e.what();
  }
}

// The config names its calibration's unknowns; bad names are refused by name, and the protocol's at most three.
TEST(FlowCalibration, UnknownsAreNamedInTheConfigAndCheckedByName) {
  EXPECT_EQ(analysis::parse_flow_unknowns(""), analysis::default_flow_unknowns());
  const std::vector<std::string> three{"static_moment", "discharge", "bearing_mu"};
  EXPECT_EQ(analysis::parse_flow_unknowns(" static_moment, discharge ,bearing_mu"), three);
  try {
    analysis::parse_flow_unknowns("static_moment,mu");
    FAIL() << "accepted 'mu'";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'mu' is not one of static_moment, discharge, feed, bearing_mu"),
              std::string::npos) << e.what();
  }
  const auto c4 = chamber::load_flow_run_config(config("gyp1200_400rpm.yaml"));
  const auto m = analysis::apply_flow_unknowns(c4.mech, {0.02}, {"bearing_mu"});
  EXPECT_TRUE(m.effects.bearing_friction.enabled);
  EXPECT_EQ(m.effects.bearing_friction.mu, 0.02);
  analysis::FlowRunOptions o;
  o.duration_s = 1, o.settle_s = 1;
  EXPECT_THROW(analysis::calibrate_flow_machine(c4.mech, c4.flow, o, 4, {}, {},
                                                {"static_moment", "discharge", "feed", "bearing_mu"}),
               std::invalid_argument);
  EXPECT_THROW(analysis::calibrate_flow_machine(c4.mech, c4.flow, o, 4, {}, {}, {"feed", "feed"}),
               std::invalid_argument);
}

// Closed loop: the figures of a run with a known bushing friction as the targets, the friction alone unknown: the
// calibration finds it back (the power rises with mu, about mu r S w^3 on top of the crushing).
TEST(FlowCalibration, RecoversAKnownBearingFrictionFromItsOwnRunsFigures) {
  auto c4 = chamber::load_flow_run_config(config("gyp1200_400rpm.yaml"));
  c4.mech.effects.bearing_friction.enabled = false;  // the search starts without friction (at 0.005)
  analysis::FlowRunOptions o;
  o.duration_s = 1.5, o.settle_s = 2;
  const auto truth = analysis::run_flow(analysis::apply_flow_unknowns(c4.mech, {0.012}, {"bearing_mu"}), c4.flow, o);
  analysis::FlowCalibrationTargets t;
  t.amplitude_mm = truth.summary.amplitude_x_mm.mean;
  t.power_kW = truth.summary.power_kW.mean;
  t.throughput_tph = truth.summary.product->throughput_tph;
  const auto none = analysis::run_flow(c4.mech, c4.flow, o);
  ASSERT_GT(t.power_kW - none.summary.power_kW.mean, 3.0);  // the friction shows in the power (kW)
  const auto cal = analysis::calibrate_flow_machine(c4.mech, c4.flow, o, 40, {}, t, {"bearing_mu"});
  EXPECT_NEAR(cal.x[0], 0.012, 0.0012);
  EXPECT_LT(cal.cost, 1e-4);
}
