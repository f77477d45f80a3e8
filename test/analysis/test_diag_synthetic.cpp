// End-to-end diagnosis on the closed-form stand-in mechanism (diag_synthetic_model.hpp): every candidate
// effect concealed in a recording with noise, time offset and gain error, plus a null recording.
#include <gtest/gtest.h>

#include "analysis/diagnosis.hpp"
#include "analysis/sensor_model.hpp"
#include "diag_synthetic_model.hpp"

using namespace analysis;

namespace {
const double kW400 = 400 * 2 * M_PI / 60, kW600 = 600 * 2 * M_PI / 60;

// The stand-in's drive speed argument is the mean measured speed (its droop keeps the mean).
DiagnosisOptions options() {
  DiagnosisOptions o;
  o.setpoint_whole_rpm = false;
  return o;
}

ModelFn stand_in() {
  return [](const ParamSet& p, double speed, double seconds) { return diagtest::synthetic_run(p, speed, seconds); };
}

std::vector<Recording> recordings(const ParamSet& concealed, std::uint64_t seed, double noise = 0.01) {
  std::vector<Recording> recs;
  int i = 0;
  for (double w : {kW400, kW600}) {
    SensorErrors e;
    e.noise_rel = noise;
    e.time_offset_s = 0.021 + 0.01 * i;
    e.gain = 0.95;
    e.seed = seed + i;
    recs.push_back(apply_sensor_errors(diagtest::synthetic_run(concealed, w, 2.0), e));
    recs.back().source = "rec" + std::to_string(++i);
  }
  return recs;
}

DiagnosisResult run_case(const std::string& effect, double value, std::uint64_t seed) {
  ParamSet p;
  if (effect != "none") p[effect] = value;
  return diagnose(recordings(p, seed), stand_in(), default_candidates(), options());
}

// The candidates with the stand-in's uncertain value (frame.mass_scale, plausible 0.7-1.3).
std::vector<Term> with_uncertain() {
  auto c = default_candidates();
  Term t;
  t.kind = Term::Miscalibrated;
  t.name = t.parameter = "frame.mass_scale";
  t.unit = "factor";
  t.lo = 0.7;
  t.hi = 1.3;
  t.nominal = 1.0;
  t.reason = "test";
  c.push_back(t);
  return c;
}
}  // namespace

struct DiagCase {
  const char* effect;
  double value;
};
class DiagSynthetic : public ::testing::TestWithParam<DiagCase> {};

TEST_P(DiagSynthetic, NamesEffectFitsParameterAndImprovesHeldOut) {
  const auto p = GetParam();
  DiagnosisResult r = run_case(p.effect, p.value, 11);
  ASSERT_EQ(r.effect, p.effect) << r.reason << "\n" << diagnosis_json(r);
  const auto& c = r.candidates[r.chosen];
  EXPECT_NEAR(c.value, p.value, 0.15 * p.value);
  EXPECT_GT(c.sigma, 0.0);
  EXPECT_LT(c.sigma, 0.15 * p.value);
  ASSERT_EQ(r.before_heldout.size(), 1u);
  EXPECT_LT(r.after_heldout[0].nrmse_overall, 0.5 * r.before_heldout[0].nrmse_overall) << diagnosis_markdown(r);
  // Non-physical differences separated: with the effect in the model, the sensor gain is recovered
  // (without it, an amplitude-changing effect is partly mistaken for gain).
  EXPECT_NEAR(r.after_train[0].alignment.gain, 0.95, 0.01);
  EXPECT_NEAR(r.after_heldout[0].alignment.tau_s, 0.031, 1e-3);
}

INSTANTIATE_TEST_SUITE_P(Effects, DiagSynthetic,
                         ::testing::Values(DiagCase{"joint_friction", 600.0},
                                           DiagCase{"absorber_nonlinearity", 1.5e11},
                                           DiagCase{"motor_droop", 1.5},
                                           DiagCase{"cardan_misalignment", 6.0}),
                         [](const auto& info) { return std::string(info.param.effect); });

TEST(DiagSynthetic, NullRecordingClaimsNothing) {
  DiagnosisResult r = run_case("none", 0.0, 5);
  EXPECT_EQ(r.effect, "none") << r.reason;
  EXPECT_FALSE(r.residual_significant);
  EXPECT_NEAR(r.before_train[0].alignment.tau_s, 0.021, 1e-3);
}

TEST(DiagSynthetic, UnmodelledMismatchIsUnexplained) {
  // A mismatch no candidate can produce: a 5th-harmonic wobble of z (e.g. a liner defect).
  std::vector<Recording> recs;
  int i = 0;
  for (double w : {kW400, kW600}) {
    Recording r = diagtest::synthetic_run("none", 0, w, 2.0);
    for (std::size_t k = 0; k < r.size(); ++k) r.z_m[k] += 4e-4 * std::cos(5 * w * r.t_s[k]);
    SensorErrors e;
    e.noise_rel = 0.03;
    e.seed = 40 + i;
    recs.push_back(apply_sensor_errors(r, e));
    recs.back().source = "rec" + std::to_string(++i);
  }
  DiagnosisResult r = diagnose(recs, stand_in(), default_candidates(), options());
  EXPECT_EQ(r.effect, "unexplained") << r.reason;
  ASSERT_FALSE(r.located.empty());
  EXPECT_EQ(r.located[0].channel, "z_m");
  EXPECT_EQ(r.located[0].order, 5);
}

TEST(DiagSynthetic, AValueOffIsNamedMiscalibratedNotAnOmittedEffect) {
  for (double m : {0.9, 1.12}) {
    DiagnosisResult r = diagnose(recordings({{"frame.mass_scale", m}}, 21), stand_in(), with_uncertain(), options());
    ASSERT_EQ(r.effect, "miscalibrated") << r.reason << "\n" << diagnosis_markdown(r);
    ASSERT_EQ(r.named.size(), 1u);
    EXPECT_EQ(r.named[0].term.name, "frame.mass_scale");
    EXPECT_NEAR(r.named[0].value, m, 0.15 * std::abs(m - 1.0)) << "within 15 % of the offset";
    EXPECT_LT(r.after_heldout[0].nrmse_overall, 0.5 * r.before_heldout[0].nrmse_overall);
  }
}

TEST(DiagSynthetic, AnEffectIsStillNamedWhenUncertainValuesAreCandidates) {
  DiagnosisResult r = diagnose(recordings({{"cardan_misalignment", 5.0}}, 31), stand_in(), with_uncertain(), options());
  ASSERT_EQ(r.effect, "cardan_misalignment") << r.reason << "\n" << diagnosis_markdown(r);
  EXPECT_NEAR(r.named[0].value, 5.0, 0.75);
}

TEST(DiagSynthetic, TwoConcealedEffectsAreBothNamed) {
  const ParamSet concealed = {{"joint_friction", 450.0}, {"cardan_misalignment", 5.0}};
  DiagnosisResult r = diagnose(recordings(concealed, 41), stand_in(), with_uncertain(), options());
  ASSERT_EQ(r.named.size(), 2u) << r.reason << "\n" << diagnosis_markdown(r);
  for (const auto& [name, value] : concealed) {
    ASSERT_EQ(r.fitted.count(name), 1u) << name << " not named: " << r.effect;
    EXPECT_NEAR(r.fitted.at(name), value, 0.15 * value) << name;
  }
  EXPECT_NE(r.effect.find(" + "), std::string::npos);
  EXPECT_LT(r.after_heldout[0].nrmse_overall, 0.5 * r.before_heldout[0].nrmse_overall);
}

TEST(DiagSynthetic, AnEffectAndAMiscalibrationTogether) {
  const ParamSet concealed = {{"motor_droop", 1.2}, {"frame.mass_scale", 1.1}};
  DiagnosisResult r = diagnose(recordings(concealed, 51), stand_in(), with_uncertain(), options());
  ASSERT_EQ(r.named.size(), 2u) << r.reason << "\n" << diagnosis_markdown(r);
  EXPECT_TRUE(r.effect == "motor_droop + miscalibrated" || r.effect == "miscalibrated + motor_droop") << r.effect;
  EXPECT_NEAR(r.fitted.at("motor_droop"), 1.2, 0.18);
  EXPECT_NEAR(r.fitted.at("frame.mass_scale"), 1.1, 0.015);
}
