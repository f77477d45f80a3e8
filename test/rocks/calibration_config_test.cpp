// Calibration config (Table 2 factors in SI), DOE rows and the calibrated-model file.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "rocks/calibration.hpp"

using namespace rocks;

namespace {
std::string source(const std::string& rel) { return std::string(CRUSHER_SOURCE_DIR) + "/" + rel; }
std::string write_temp(const std::string& name, const std::string& text) {
  const std::string f = ::testing::TempDir() + "/" + name;
  std::ofstream(f) << text;
  return f;
}
}  // namespace

TEST(CalibrationConfig, ShippedConfigsHoldTable2) {
  for (const char* file : {"launch_free_configs/calibration.yaml", "launch_free_configs/calibration_paper_bimodal.yaml"}) {
    const CalibrationConfig c = CalibrationConfig::load(source(file));
    EXPECT_DOUBLE_EQ(c.diameter, 0.05);
    EXPECT_DOUBLE_EQ(c.target_force, 14.8e3);
    EXPECT_DOUBLE_EQ(c.stiffness_ratio, 2.5);
    EXPECT_EQ(c.normal_strength, (std::vector<double>{22e6, 17e6, 25e6, 20e6}));
    EXPECT_EQ(c.shear_strength, (std::vector<double>{16e6, 13e6, 9e6, 11e6}));
    EXPECT_EQ(c.shear_stiffness, (std::vector<double>{100e9, 120e9, 160e9, 200e9}));
    ASSERT_EQ(c.disk_radius.size(), 4u);
    EXPECT_NEAR(c.disk_radius[2], 3.3e-3, 1e-15);
  }
  const CalibrationConfig c = CalibrationConfig::load(source("launch_free_configs/calibration.yaml"));
  // L16 row 6 is (2, 2, 1, 4, 3): 17 MPa, 13 MPa, error level 1, 200 GPa/m, 3.3 mm
  const BondSettings s = doe_settings(c, 5);
  EXPECT_DOUBLE_EQ(s.sigma_c, 17e6);
  EXPECT_DOUBLE_EQ(s.tau_c, 13e6);
  EXPECT_DOUBLE_EQ(s.kt, 200e9);
  EXPECT_DOUBLE_EQ(s.kn, 500e9);
  EXPECT_NEAR(s.disk_radius, 3.3e-3, 1e-15);
  EXPECT_NEAR(s.params().radius_multiplier, 1.1, 1e-12);  // Eq. 20 with the 3 mm reference radius
  EXPECT_THROW(doe_settings(c, 16), std::invalid_argument);
}

TEST(CalibrationConfig, BadConfigsNameTheKey) {
  std::string text;
  {
    std::ifstream in(source("launch_free_configs/calibration.yaml"));
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  auto expect_error = [&](const std::string& from, const std::string& to, const std::string& key) {
    std::string t = text;
    const auto pos = t.find(from);
    ASSERT_NE(pos, std::string::npos) << from;
    t.replace(pos, from.size(), to);
    const std::string f = write_temp("bad_calibration.yaml", t);
    try {
      CalibrationConfig::load(f);
      FAIL() << "accepted " << to;
    } catch (const core::ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
    std::remove(f.c_str());
  };
  expect_error("[22, 17, 25, 20]", "[22, 17, 25]", "normal_strength_MPa");
  expect_error("stiffness_ratio: 2.5", "stiffness_ratio: -1", "stiffness_ratio");
  expect_error("record_every: 100", "record_evry: 100", "record_evry");
}

TEST(CalibrationConfig, BpmModelRoundTrip) {
  BpmModel m;
  m.bond.sigma_c = 31.5e6;
  m.bond.tau_c = 11.25e6;
  m.bond.kt = 120e9;
  m.bond.kn = 300e9;
  m.bond.disk_radius = 3.2e-3;
  m.packing.density = 0.6;
  const std::string f = write_temp("bpm.yaml", "# comment\nbpm:\n" + bpm_model_yaml(m));
  const BpmModel l = load_bpm_model(f);
  EXPECT_DOUBLE_EQ(l.bond.sigma_c, 31.5e6);
  EXPECT_DOUBLE_EQ(l.bond.tau_c, 11.25e6);
  EXPECT_DOUBLE_EQ(l.bond.kn, 300e9);
  EXPECT_NEAR(l.bond.disk_radius, 3.2e-3, 1e-15);
  EXPECT_DOUBLE_EQ(l.packing.density, 0.6);
  EXPECT_EQ(l.metaparticles.modes().size(), 2u);
  std::remove(f.c_str());
  // the shipped calibrated model loads
  const BpmModel shipped = load_bpm_model(source("launch_free_configs/bpm_calibrated.yaml"));
  EXPECT_GT(shipped.bond.sigma_c, 0.0);
}
