// End-to-end diagnosis on the mechanism itself (mbd::simulate, bed load): recordings made from the
// model with one concealed effect, 0.3 % sensor noise, a time offset and a 3 % gain error, 2 s at
// 400 rpm (training) and 600 rpm (held out); and a null recording.
#include <gtest/gtest.h>

#include "analysis/diagnosis.hpp"
#include "analysis/mbd_model.hpp"
#include "analysis/param_set.hpp"
#include "analysis/sensor_model.hpp"
#include "core/config.hpp"
#include "core/units.hpp"
#include "mbd/simulate.hpp"

using namespace analysis;

namespace {

mbd::MechanismParams base_params() {
  auto root = core::ConfigNode::load_file(std::string(CRUSHER_SOURCE_DIR) + "/launch_free_configs/gyp1200_400rpm_bed.yaml");
  return mbd::load_mechanism_params(root.child("mbd"));
}

// 2 s at 400 and 600 rpm of `mech` (time step scaled by at_speed) with sensor errors: noise, a time offset
// tau0 + dtau per speed, a gain, seeds seed, seed + 1.
std::vector<Recording> recordings_of(const mbd::MechanismParams& mech, double noise, double tau0, double dtau,
                                     double gain, std::uint64_t seed) {
  std::vector<Recording> recs;
  int i = 0;
  for (double rpm : {400.0, 600.0}) {
    mbd::SimOptions so;
    so.duration_s = 2.0;
    so.settle_s = MbdModelOptions().settle_s;
    const auto p = at_speed(mech, rpm * core::units::rpm);
    SensorErrors e;
    e.noise_rel = noise;
    e.time_offset_s = tau0 + dtau * i;
    e.gain = gain;
    e.seed = seed + i;
    recs.push_back(apply_sensor_errors(from_fields(mbd::simulate(p, so), ""), e));
    recs.back().source = "rec" + std::to_string(static_cast<int>(rpm));
    ++i;
  }
  return recs;
}

std::vector<Recording> make_recordings(const mbd::MechanismParams& base, const std::string& effect, double value) {
  return recordings_of(with_effect(base, effect, value), 0.003, 0.031, -0.014, 0.97, 100);
}

// The plant's control system knows the drive set points (400 and 600 rpm).
DiagnosisOptions options() {
  DiagnosisOptions o;
  o.setpoints_rad_s = {400 * core::units::rpm, 600 * core::units::rpm};
  return o;
}

}  // namespace

struct MbdCase {
  const char* effect;
  double value;
};
class DiagMbd : public ::testing::TestWithParam<MbdCase> {};

TEST_P(DiagMbd, NamesEffectFitsParameterAndHalvesHeldOutError) {
  const auto c = GetParam();
  const auto base = base_params();
  DiagnosisResult r = diagnose(make_recordings(base, c.effect, c.value), make_mbd_model(base), mbd_candidates(), options());
  ASSERT_EQ(r.effect, c.effect) << r.reason << "\n" << diagnosis_markdown(r);
  const auto& fit = r.candidates[r.chosen];
  EXPECT_NEAR(fit.value, c.value, 0.15 * c.value);
  EXPECT_GT(fit.sigma, 0.0);
  EXPECT_LT(fit.sigma, 0.15 * c.value);  // the stated uncertainty is small enough to support the claim
  ASSERT_EQ(r.before_heldout.size(), 1u);
  EXPECT_LT(r.after_heldout[0].nrmse_overall, 0.5 * r.before_heldout[0].nrmse_overall) << diagnosis_markdown(r);
  // The non-physical differences are recovered once the physics is right.
  EXPECT_NEAR(r.after_train[0].alignment.gain, 0.97, 0.01);
  EXPECT_NEAR(r.after_train[0].alignment.tau_s, 0.031, 2e-3);
}

INSTANTIATE_TEST_SUITE_P(Effects, DiagMbd,
                         ::testing::Values(MbdCase{"joint_friction", 300.0},
                                           MbdCase{"absorber_nonlinearity", 5e10},
                                           MbdCase{"motor_droop", 0.2},
                                           MbdCase{"cardan_misalignment", 4.0}),
                         [](const auto& info) { return std::string(info.param.effect); });

TEST(DiagMbd, NullRecordingClaimsNothing) {
  const auto base = base_params();
  DiagnosisResult r = diagnose(make_recordings(base, "none", 0.0), make_mbd_model(base), mbd_candidates(), options());
  EXPECT_EQ(r.effect, "none") << r.reason << "\n" << diagnosis_markdown(r);
  EXPECT_EQ(r.chosen, -1);
  EXPECT_NEAR(r.before_train[0].alignment.gain, 0.97, 0.01);
}

// The recording's clock 0.2 ms behind the model's (an offset just below 0, i.e. just below one period):
// the alignment must find it on the far side of 0. With a bracket clipped at 0 the phase error
// (0.2 ms x w = 0.9 % of order 1 at 400 rpm) was read as structured residual: `unexplained`, for some
// noise draws (the seeds 5 and 6 of make_recording did so in the CLI).
TEST(DiagMbd, NullRecordingClockJustBehindTheModelClaimsNothing) {
  const auto base = base_params();
  for (std::uint64_t seed : {5u, 11u, 23u}) {
    const auto recs = recordings_of(with_effect(base, "none", 0.0), 0.01, -2e-4, 0.0, 1.0, seed);
    DiagnosisResult r = diagnose(recs, make_mbd_model(base), mbd_candidates(), options());
    EXPECT_EQ(r.effect, "none") << "seed " << seed << ": " << r.reason << "\n" << diagnosis_markdown(r);
    // Found behind 0 (the model's own phase lag adds another 0.2 ms), not at the clipped 0.
    const auto& a = r.before_train[0].alignment;
    EXPECT_GT(a.tau_s, a.period_s - 1e-3) << "seed " << seed;
  }
}

// The effect modules of series_candidates() (bearing friction, drive efficiency), recovered the same way.
class DiagMbdModules : public ::testing::TestWithParam<MbdCase> {};

TEST_P(DiagMbdModules, NamesEffectAndFitsParameter) {
  const auto c = GetParam();
  const auto base = base_params();
  const auto terms = series_candidates();
  const auto model = make_mbd_model(ConfigModel::from_mechanism(with_effect(base, "none", 0.0)), terms);
  DiagnosisResult r = diagnose(make_recordings(base, c.effect, c.value), model, terms, options());
  ASSERT_EQ(r.effect, c.effect) << r.reason << "\n" << diagnosis_markdown(r);
  const auto& fit = r.candidates[r.chosen];
  EXPECT_NEAR(fit.value, c.value, 0.15 * std::abs(c.value - fit.term.nominal)) << "within 15 % of the offset";
  // The structured residual (beyond the sensor noise) it removes on the held-out speed: the overall NRMSE
  // is no measure here, as a drive efficiency moves only the power's mean, under the motion channels' noise.
  EXPECT_GT(fit.explained_heldout, 0.9) << diagnosis_markdown(r);
}

INSTANTIATE_TEST_SUITE_P(Modules, DiagMbdModules,
                         ::testing::Values(MbdCase{"bearing_friction", 0.02}, MbdCase{"drive_efficiency", 0.9}),
                         [](const auto& info) { return std::string(info.param.effect); });

TEST(DiagMbd, EffectHelpersRejectUnknownNames) {
  const auto base = base_params();
  EXPECT_THROW(with_effect(base, "bearing_wear", 1.0), std::invalid_argument);
  const auto p = with_effect(base, "cardan_misalignment", 3.0);
  EXPECT_TRUE(p.effects.cardan_misalignment.enabled);
  EXPECT_NEAR(p.effects.cardan_misalignment.angle_rad, 3.0 * M_PI / 180, 1e-12);
  EXPECT_NEAR(with_effect(base, "motor_droop", 2.0).effects.motor_droop.droop_rad_s_per_Nm, 2e-3, 1e-15);
  // w dt kept when the speed changes (600 rpm config: 0.667 ms for 1 ms at 400 rpm).
  const auto q = at_speed(base, 600 * core::units::rpm);
  EXPECT_NEAR(q.dt_s * q.drive_speed_rad_s, base.dt_s * base.drive_speed_rad_s, 1e-12);
}

// With the config's uncertain values as candidates (diagnosis.uncertain of the bed config, inherited from
// gyp1200_400rpm.yaml): recordings of a mechanism whose parameter set `concealed` differs from the config.
namespace {
struct ConfigCase {
  ConfigModel cfg{std::string(CRUSHER_SOURCE_DIR) + "/launch_free_configs/gyp1200_400rpm_bed.yaml"};
  std::vector<Term> terms = [this] {
    auto t = mbd_candidates();
    for (const auto& u : cfg.uncertain()) t.push_back(u);
    return t;
  }();
  DiagnosisResult run(const ParamSet& concealed, std::uint64_t seed) const {
    const auto recs = recordings_of(cfg.mechanism(concealed, terms), 0.004, 0.017, 0.011, 1.02, seed);
    return diagnose(recs, make_mbd_model(cfg, terms), terms, options());
  }
};
}  // namespace

TEST(DiagMbd, AFixedConeMassTenPercentLowIsMiscalibratedNotAnOmittedEffect) {
  const ConfigCase c;
  ASSERT_GE(c.cfg.uncertain().size(), 5u);
  const DiagnosisResult r = c.run({{"mbd.fixed_cone.mass_kg", 0.9}}, 300);
  ASSERT_EQ(r.effect, "miscalibrated") << r.reason << "\n" << diagnosis_markdown(r);
  ASSERT_EQ(r.named.size(), 1u) << diagnosis_markdown(r);
  EXPECT_EQ(r.named[0].term.key(), "mbd.fixed_cone.mass_kg");
  EXPECT_NEAR(r.named[0].value, 0.9, 0.015) << "within 15 % of the 10 % offset";
  EXPECT_LT(r.after_heldout[0].nrmse_overall, 0.5 * r.before_heldout[0].nrmse_overall);
}

TEST(DiagMbd, TwoConcealedEffectsAreBothNamedWithUncertainValuesAsCandidates) {
  const ConfigCase c;
  const ParamSet concealed = {{"joint_friction", 350.0}, {"absorber_nonlinearity", 8e10}};
  const DiagnosisResult r = c.run(concealed, 400);
  ASSERT_EQ(r.named.size(), 2u) << r.reason << "\n" << diagnosis_markdown(r);
  for (const auto& [name, value] : concealed) {
    ASSERT_EQ(r.fitted.count(name), 1u) << name << " not named: " << r.effect;
    EXPECT_NEAR(r.fitted.at(name), value, 0.15 * value) << name;
  }
}
