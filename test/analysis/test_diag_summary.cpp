// The diagnosis on summary recordings (Table 5 style: averages per speed) against the fast model: reading and
// refusing files, a summary made from the model with a concealed effect, and one with nothing concealed.
#include <gtest/gtest.h>

#include <fstream>

#include <cmath>

#include "analysis/diagnosis.hpp"
#include "analysis/mbd_model.hpp"
#include "analysis/summary_diagnosis.hpp"
#include "core/units.hpp"

using namespace analysis;

namespace {

const char* kTable = R"(source: "test"
uncertainty_pct: {amplitude_x_mm_mean: 2, power_kW_mean: 3, throughput_tph: 5}
rows:
  - {speed_rpm: 400, amplitude_x_mm_mean: 5.46, power_kW_mean: 76.8, throughput_tph: 80.8, power_kW_std: 3.97}
  - {speed_rpm: 600, amplitude_x_mm_mean: 5.74, power_kW_mean: 146.2, throughput_tph: 51.8}
)";

void expect_refused(const std::string& text, const std::string& words) {
  try {
    parse_summary(text, "t.yaml");
    ADD_FAILURE() << "accepted: " << text;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

// A short fast-mode model (3 s after a 3 s settle) of the shipped 400 rpm config, and a few candidates.
struct FlowCase {
  explicit FlowCase(const std::string& file = std::string(CRUSHER_SOURCE_DIR) + "/launch_free_configs/gyp1200_400rpm.yaml")
      : cfg(file) {}
  ConfigModel cfg;
  std::vector<Term> terms = [this] {
    std::vector<Term> t;
    for (const auto& e : mbd_candidates())
      if (e.name == "joint_friction" || e.name == "cardan_misalignment") t.push_back(e);
    for (const auto& u : cfg.uncertain())
      if (u.name == "mbd.vibrator.static_moment_kg_m" || u.name == "mbd.chamber.concave_r_mm[1]") t.push_back(u);
    return t;
  }();
  SummaryModelFn model = make_flow_summary_model(cfg, terms, 3.0, 3.0);
  // The model's own statistics with `concealed`, as a plant summary.
  SummaryRecording plant(const ParamSet& concealed) const {
    SummaryRecording s = parse_summary(kTable, "plant");
    for (auto& row : s.rows) {
      const Stats m = model(concealed, row.speed_rad_s);
      row.values.clear();
      for (const char* q : {"amplitude_x_mm_mean", "power_kW_mean", "throughput_tph", "specific_energy_kWh_per_t"})
        row.values[q] = m.at(q);
    }
    return s;
  }
};

}  // namespace

TEST(SummaryRecording, ReadsTheShippedTable5AndRoundTrips) {
  const auto s = read_summary(std::string(CRUSHER_SOURCE_DIR) + "/launch_free_configs/table5_gyp1200_plant.yaml");
  ASSERT_EQ(s.rows.size(), 2u);
  EXPECT_NEAR(s.rows[1].speed_rad_s, 600 * core::units::rpm, 1e-12);
  EXPECT_DOUBLE_EQ(s.rows[1].values.at("power_kW_mean"), 146.2);
  EXPECT_DOUBLE_EQ(s.uncertainty_pct.at("power_kW_mean"), 3.0);
  EXPECT_NE(s.source.find("Table 5"), std::string::npos);
  const auto back = parse_summary(summary_yaml(s), "again");
  EXPECT_EQ(back.rows[0].values, s.rows[0].values);
  EXPECT_EQ(back.uncertainty_pct, s.uncertainty_pct);
}

TEST(SummaryRecording, RefusesBadFilesNamingRowAndKey) {
  EXPECT_NO_THROW(parse_summary(kTable, "t.yaml"));
  expect_refused("uncertainty_pct: {power_kW_mean: 3}\nrows: [{speed_rpm: 400, power_kW_mean: 7}]\n", "'source'");
  expect_refused(std::string(kTable) + "colour: red\n", "unknown key 'colour'");
  expect_refused("source: s\nuncertainty_pct: {power_kw: 3}\nrows: [{speed_rpm: 400, power_kW_mean: 7}]\n",
                 "uncertainty_pct.power_kw: unknown quantity");
  expect_refused("source: s\nuncertainty_pct: {power_kW_mean: 3}\nrows: [{speed_rpm: 400, power_kW_mean: 7}, {power_kW_mean: 9}]\n",
                 "rows[1]: speed_rpm is missing");
  expect_refused("source: s\nuncertainty_pct: {power_kW_mean: 3}\nrows: [{speed_rpm: 400, throughput_tph: 7}]\n",
                 "rows[0]: none of the compared quantities");
  expect_refused("source: s\nuncertainty_pct: {power_kW_mean: 3}\nrows: [{speed_rpm: 400, power_kW_mean: fast}]\n",
                 "rows[0].power_kW_mean: not a number");
  expect_refused("source: s\nuncertainty_pct: {power_kW_mean: 0}\nrows: [{speed_rpm: 400, power_kW_mean: 7}]\n",
                 "must be in (0, 100]");
  expect_refused("source: s\nuncertainty_pct: {power_kW_mean: 3}\nrows: [{speed_rpm: 400, power_kW_mean: 7}, {speed_rpm: 400, power_kW_mean: 8}]\n",
                 "same speed");
}

TEST(SummaryDiagnosis, NamesAConcealedEffectAndFitsIt) {
  const FlowCase c;
  const double torque = 260.0;  // N m: about +10 kW at 400 rpm, +16 kW at 600 rpm
  const SummaryDiagnosis d = diagnose_summary(c.plant({{"joint_friction", torque}}), c.model, c.terms);
  ASSERT_EQ(d.effect, "joint_friction") << d.reason << "\n" << summary_diagnosis_markdown(d);
  EXPECT_NEAR(d.selection.fitted.at("joint_friction"), torque, 0.15 * torque);
  double chi2_before = 0, chi2_after = 0;
  for (const auto& r : d.before) chi2_before += r.chi2;
  for (const auto& r : d.after) chi2_after += r.chi2;
  EXPECT_LT(chi2_after, 0.1 * chi2_before);
}

TEST(SummaryDiagnosis, TheModelsOwnFiguresClaimNothing) {
  const FlowCase c;
  const SummaryDiagnosis d = diagnose_summary(c.plant({}), c.model, c.terms);
  EXPECT_EQ(d.effect, "none") << d.reason;
  EXPECT_TRUE(d.selection.named.empty());
}

// A chamber effect concealed in the plant's summaries, among the mechanism's friction, the bearing's and the drive's
// static moment: the diagnosis names it and fits its main parameter within 15 %.
static void expect_chamber_effect_named(const std::string& effect, double value, const std::string& config = "") {
  FlowCase c = config.empty() ? FlowCase() : FlowCase(config);
  c.terms.clear();
  for (const auto& e : summary_candidates())
    if (e.name == "joint_friction" || e.name == effect || e.name == "bearing_friction") c.terms.push_back(e);
  for (const auto& u : c.cfg.uncertain())
    if (u.name == "mbd.vibrator.static_moment_kg_m") c.terms.push_back(u);
  c.model = make_flow_summary_model(c.cfg, c.terms, 3.0, 3.0);
  const SummaryDiagnosis d = diagnose_summary(c.plant({{effect, value}}), c.model, c.terms);
  ASSERT_EQ(d.effect, effect) << d.reason << "\n" << summary_diagnosis_markdown(d);
  EXPECT_NEAR(d.selection.fitted.at(effect), value, 0.15 * value);
}

// Worn liners, 20 mm at the discharge. (The discharge radius, concave_r_mm[1], is left out of the candidates: a worn
// concave and a wider discharge are nearly one change to these four figures.)
TEST(SummaryDiagnosis, NamesConcealedWornLiners) { expect_chamber_effect_named("worn_liners", 20.0); }

// The friction of rock pressed out of the nip: squeeze_flow, escape length 4 mm, on the shipped rock pressed out at the
// compaction limit (pressure.at_limit: extrude; the shipped rock is held there and presses none out) with the machine
// values its own 400 rpm calibration gave (+6 kW at 400 rpm, +24 kW at 600).
TEST(SummaryDiagnosis, NamesConcealedSqueezeFlow) {
  const std::string file = ::testing::TempDir() + "/extruding_400rpm.yaml";
  std::ofstream(file) << "base: " << CRUSHER_SOURCE_DIR << "/launch_free_configs/gyp1200_400rpm.yaml\n"
                      << "mbd: {vibrator: {static_moment_kg_m: 90.740467}, chamber: {concave_r_mm: [229.8, 653.53734]},\n"
                      << "      effects: {bearing_friction: {mu: 0.000409}}}\n"
                      << "flow: {material: {pressure: {at_limit: extrude}}}\n";
  expect_chamber_effect_named("squeeze_flow", 4.0, file);
}

// The rock's friction on the liners at 0.6 (rock on steel 0.7, Table 4): power +9 kW at 400 rpm, +36 kW at 600 on
// the shipped model (at 0.35 the figures move within the 5-sigma test of the plant's uncertainty: named `none`).
TEST(SummaryDiagnosis, NamesConcealedLinerFriction) { expect_chamber_effect_named("liner_friction", 0.6); }

// A candidate that fits the means but makes the model's cycles scatter more than the plant's (its 400 rpm power std
// above the plant's 3.97 kW: a mechanism near a blow-up, as squeeze_flow at 1.8 mm on the shipped model) makes a row
// worse and is not named; the steady candidate that explains a little less is. Synthetic model: the plant's means
// with 10 kW missing at 400 rpm and 30 kW at 600; `wobbly` adds a x (10, 30) kW and a x 10 kW of power std, `steady`
// adds b x (10, 24) kW.
TEST(SummaryDiagnosis, ACandidateThatMakesTheModelUnsteadyIsNotNamed) {
  const SummaryRecording data = parse_summary(kTable, "plant");
  Term wobbly;
  wobbly.name = "wobbly";
  wobbly.parameter = "value";
  wobbly.lo = 0;
  wobbly.hi = 2;
  Term steady = wobbly;
  steady.name = "steady";
  const SummaryModelFn model = [&](const ParamSet& p, double w) {
    const double a = p.count("wobbly") ? p.at("wobbly") : 0, b = p.count("steady") ? p.at("steady") : 0;
    const bool fast = w > 500 * core::units::rpm;
    const auto& plant = data.rows[fast ? 1 : 0].values;
    Stats s = {{"amplitude_x_mm_mean", plant.at("amplitude_x_mm_mean")},
               {"throughput_tph", plant.at("throughput_tph")},
               {"power_kW_std", 0.1 + 10 * a}};
    s["power_kW_mean"] = plant.at("power_kW_mean") - (fast ? 30 : 10) + a * (fast ? 30 : 10) + b * (fast ? 24 : 10);
    return s;
  };
  const SummaryDiagnosis d = diagnose_summary(data, model, {wobbly, steady});
  ASSERT_EQ(d.effect, "steady") << d.reason << "\n" << summary_diagnosis_markdown(d);
  ASSERT_FALSE(d.selection.steps.empty());
  for (const auto& f : d.selection.steps[0].fits) {
    if (f.term.name != "wobbly") continue;
    EXPECT_NEAR(f.value, 1.0, 0.01);  // it fits the means exactly ...
    EXPECT_TRUE(f.heldout_worse);     // ... with 10 kW of power std at 400 rpm against the plant's 3.97
  }
}
