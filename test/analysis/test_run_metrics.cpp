#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "analysis/run_metrics.hpp"

namespace {
constexpr double kPi = 3.14159265358979323846;
}

TEST(RunMetrics, AmplitudeOfSineIsHalfPeakToPeak) {
  analysis::RunSignals s;
  const double w = 400 * 2 * kPi / 60, A = 5.46e-3;
  for (int i = 0; i < 20000; ++i) {
    double t = i * 1e-4;
    s.t_s.push_back(t);
    s.x_m.push_back(A * std::sin(w * t + 0.3) + 1e-3);  // offset must not matter
    s.y_m.push_back(0.5 * A * std::cos(w * t));
    s.z_m.push_back(0);
    s.power_W.push_back(76.8e3 + 3e3 * std::sin(2 * w * t));
    s.speed_rad_s.push_back(w);
  }
  auto r = analysis::summarize(s, w, 0.2);
  EXPECT_NEAR(r.amplitude_x_mm.mean, 5.46, 5.46 * 2e-3);  // 1e-4 s sampling of a 0.15 s cycle
  EXPECT_LT(r.amplitude_x_mm.std, 0.01);
  EXPECT_NEAR(r.amplitude_y_mm.mean, 2.73, 2.73 * 2e-3);
  EXPECT_NEAR(r.power_kW.mean, 76.8, 0.05);  // whole cycles average the 2x ripple out
  // whole cycles only: the last sample is at 1.9999 s
  EXPECT_EQ(r.amplitude_x_mm.samples, static_cast<int>((1.9999 - 0.2) / (2 * kPi / w)));
}

TEST(RunMetrics, AmplitudeStdSeesCycleToCycleVariation) {
  std::vector<double> t, v;
  const double w = 2 * kPi * 10;
  for (int i = 0; i < 10000; ++i) {
    double ti = i * 1e-4;
    int cycle = static_cast<int>(ti * 10);
    t.push_back(ti);
    v.push_back((cycle % 2 ? 2.0 : 1.0) * std::sin(w * ti));
  }
  auto m = analysis::cycle_amplitude(t, v, w);
  // 9 whole cycles (the 10th ends after the last sample): amplitudes 1,2,1,2,1,2,1,2,1
  ASSERT_EQ(m.samples, 9);
  EXPECT_NEAR(m.mean, 13.0 / 9.0, 1e-3);
  double var = (5 * std::pow(4.0 / 9, 2) + 4 * std::pow(5.0 / 9, 2)) / 8;
  EXPECT_NEAR(m.std, std::sqrt(var), 1e-3);
}

TEST(RunMetrics, JsonHasContractFieldsAndNullsWithoutParticles) {
  analysis::RunSummary s;
  auto j = analysis::to_json(s);
  for (const char* key : {"amplitude_x_mm", "amplitude_y_mm", "amplitude_z_mm", "power_kW", "throughput_tph",
                          "specific_energy_kWh_per_t", "psd", "simulated_s", "wall_s"})
    EXPECT_NE(j.find(std::string("\"") + key + "\""), std::string::npos) << key;
  for (const char* key : {"psd", "throughput_tph", "mass_discharged_kg", "p80_mm", "passing_12mm_pct"})
    EXPECT_NE(j.find(std::string("\"") + key + "\": null"), std::string::npos) << key;
  s.product = analysis::ProductSummary{80.0, 10.0, {1, 12}, {2.0, 85.0}, 0.25};
  s.power_kW.mean = 76.0;
  s.power_kW.samples = 12;
  j = analysis::to_json(s);
  EXPECT_NE(j.find("\"specific_energy_kWh_per_t\": 0.95"), std::string::npos) << j;
  EXPECT_NE(j.find("\"sieve_mm\": [1, 12]"), std::string::npos) << j;
  EXPECT_NE(j.find("\"mass_lost_kg\": 0.25"), std::string::npos) << j;
  // 85 % passing 12 mm, 2 % passing 1 mm: P80 by log interpolation between them, both passing figures exact
  EXPECT_NE(j.find("\"passing_12mm_pct\": 85"), std::string::npos) << j;
  EXPECT_NE(j.find("\"passing_1mm_pct\": 2,"), std::string::npos) << j;
  const double p80 = std::exp(std::log(1.0) + (80.0 - 2.0) / 83.0 * std::log(12.0));
  EXPECT_NE(j.find("\"p80_mm\": " + std::to_string(p80).substr(0, 6)), std::string::npos) << j << " " << p80;
}

TEST(RunMetrics, RejectsNonPositiveSpeed) {
  std::vector<double> t{0, 1}, v{0, 1};
  EXPECT_THROW(analysis::cycle_amplitude(t, v, 0.0), std::invalid_argument);
}

// JSON has no inf or nan (a damaged checkpoint once wrote "mean": inf): null, and the field named for a warning.
TEST(RunMetrics, JsonWritesNonFiniteAsNullAndNamesTheField) {
  analysis::RunSummary s;
  s.amplitude_x_mm.mean = std::numeric_limits<double>::infinity();
  s.amplitude_x_mm.samples = 3;
  s.product = analysis::ProductSummary{std::nan(""), 10.0, {1, 12}, {2.0, -std::numeric_limits<double>::infinity()}, 0.25};
  s.stopped = "stopped by a signal (SIGTERM)";
  std::vector<std::string> bad;
  const auto j = analysis::to_json(s, &bad);
  for (const char* word : {"inf", "nan", "INF", "NAN"}) EXPECT_EQ(j.find(word), std::string::npos) << word << "\n" << j;
  EXPECT_NE(j.find("\"amplitude_x_mm\": {\"mean\": null"), std::string::npos) << j;
  EXPECT_NE(j.find("\"throughput_tph\": null"), std::string::npos) << j;
  EXPECT_NE(j.find("\"passing_pct\": [2, null]"), std::string::npos) << j;
  EXPECT_NE(j.find("\"stopped\": \"stopped by a signal (SIGTERM)\""), std::string::npos) << j;
  EXPECT_EQ(bad, (std::vector<std::string>{"amplitude_x_mm.mean", "throughput_tph", "psd.passing_pct", "passing_12mm_pct"}));
  EXPECT_NE(analysis::to_json(analysis::RunSummary{}).find("\"stopped\": null"), std::string::npos);
}

// A run too short for one whole drive cycle after the settle has no cycle statistics: null, not 0 (DESIGN: summary.json
// holds null only where a value does not exist, never 0 in its place); so has its specific energy, even with a product.
TEST(RunMetrics, NoWholeCycleWritesNullStatisticsNotZeros) {
  analysis::RunSummary s;
  s.product = analysis::ProductSummary{80.0, 10.0, {1, 12}, {2.0, 85.0}, 0.25};
  const auto j = analysis::to_json(s);
  for (const char* key : {"amplitude_x_mm", "amplitude_y_mm", "amplitude_z_mm", "power_kW", "drive_speed_rad_s"})
    EXPECT_NE(j.find(std::string("\"") + key + "\": {\"mean\": null, \"std\": null, \"cycles\": 0}"), std::string::npos)
        << key << "\n" << j;
  EXPECT_NE(j.find("\"specific_energy_kWh_per_t\": null"), std::string::npos) << j;
  EXPECT_NE(j.find("\"throughput_tph\": 80"), std::string::npos) << j;
}
