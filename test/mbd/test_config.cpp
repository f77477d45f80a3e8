// Bad mbd configs are rejected before any simulation, naming the key; to_yaml round-trips.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>

#include "core/config.hpp"
#include "core/run_config.hpp"
#include "mbd/mechanism.hpp"
#include "mbd/mechanism_params.hpp"

namespace {

std::string read_400() {
  std::ifstream in(std::string(CRUSHER_SOURCE_DIR) + "/launch_free_configs/gyp1200_400rpm.yaml");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Loads the mbd section the way a node does (finish() on the root after reading run: too).
mbd::MechanismParams load_text(const std::string& text) {
  auto root = core::ConfigNode::load_string(text, "test.yaml");
  auto p = mbd::load_mechanism_params(root.child("mbd"));
  core::load_run_options(root.child("run"));
  core::load_coupling_options(root.child_or_empty("coupling"));
  root.ignore("dem");   // dem_node's section
  root.ignore("flow");  // the chamber flow model's
  root.ignore("diagnosis");  // crusher diagnose's uncertain values
  root.finish();
  return p;
}

std::string error_of(const std::string& text) {
  try {
    load_text(text);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto i = s.find(from);
  EXPECT_NE(i, std::string::npos) << from;
  if (i != std::string::npos) s.replace(i, from.size(), to);
  return s;
}

TEST(MbdConfig, ShippedConfigsLoad) {
  EXPECT_NO_THROW(load_text(read_400()));
  // The 600 rpm config names the 400 rpm one as its base (ConfigNode::load_file resolves it).
  auto root = core::ConfigNode::load_file(std::string(CRUSHER_SOURCE_DIR) + "/launch_free_configs/gyp1200_600rpm.yaml");
  const auto p = mbd::load_mechanism_params(root.child("mbd"));
  EXPECT_NEAR(p.drive_speed_rad_s, 600 * 2 * M_PI / 60, 1e-12);
  EXPECT_NEAR(p.dt_s, 5e-4, 1e-15);
}

TEST(MbdConfig, UnknownKeyNamed) {
  const auto msg = error_of(replace(read_400(), "    mu_static: 0.3", "    mu_statik: 0.3\n    mu_static: 0.3"));
  EXPECT_NE(msg.find("mbd.contact.mu_statik"), std::string::npos) << msg;
}

TEST(MbdConfig, MissingKeyNamed) {
  const auto msg = error_of(replace(read_400(), "    mass_kg: 784.5", "    # mass removed"));
  EXPECT_NE(msg.find("mbd.vibrator.mass_kg"), std::string::npos) << msg;
  EXPECT_NE(msg.find("missing"), std::string::npos) << msg;
}

TEST(MbdConfig, BedLawKeys) {
  const std::string law = "    law: viscous";  // the shipped line (its comment follows)
  const auto p = load_text(replace(read_400(), law, "    law: hysteretic\n    rebound: 0.2"));
  EXPECT_EQ(p.bed.law, mbd::BedLaw::Hysteretic);
  EXPECT_DOUBLE_EQ(p.bed.rebound, 0.2);
  auto msg = error_of(replace(read_400(), law, "    law: hysteretic"));
  EXPECT_NE(msg.find("mbd.bed.rebound"), std::string::npos) << msg;
  msg = error_of(replace(read_400(), law, law + "\n    rebound: 0.2"));
  EXPECT_NE(msg.find("hysteretic"), std::string::npos) << msg;
  msg = error_of(replace(read_400(), law, "    law: plastic"));
  EXPECT_NE(msg.find("viscous"), std::string::npos) << msg;
  // to_yaml keeps the law and its rebound.
  auto root = core::ConfigNode::load_string(mbd::to_yaml(p), "fitted.yaml");
  const auto q = mbd::load_mechanism_params(root.child("mbd"));
  EXPECT_EQ(q.bed.law, mbd::BedLaw::Hysteretic);
  EXPECT_NEAR(q.bed.rebound, 0.2, 1e-9);
}

TEST(MbdConfig, OutOfRangeNamedWithValueAndRange) {
  const auto msg = error_of(replace(read_400(), "    mu_static: 0.3", "    mu_static: 7"));
  EXPECT_NE(msg.find("mbd.contact.mu_static"), std::string::npos) << msg;
  EXPECT_NE(msg.find("7"), std::string::npos) << msg;
  EXPECT_NE(msg.find("[0, 2]"), std::string::npos) << msg;
}

TEST(MbdConfig, UnstableTimeStepNamed) {
  // 4 ms: the drive turns 0.17 rad per step (accepted <= 0.05 rad).
  const auto msg = error_of(std::regex_replace(read_400(), std::regex("time_step_s: [0-9.e-]+"), "time_step_s: 4.0e-3"));
  EXPECT_NE(msg.find("mbd.time_step_s"), std::string::npos) << msg;
  EXPECT_NE(msg.find("0.004"), std::string::npos) << msg;
  EXPECT_NE(msg.find("<= 0.00119"), std::string::npos) << msg;
  // A stiffer bed lowers the bound: 1 ms becomes unstable with a 100x modulus, for a run with the bed load (the
  // mechanism refuses it); idle or under another load the bed's stiffness does not bound the step.
  const auto stiff = load_text(std::regex_replace(read_400(), std::regex("modulus_MPa: [0-9.]+"), "modulus_MPa: 1000"));
  std::string msg2;
  try {
    mbd::Mechanism m(stiff, mbd::LoadModel::Bed);
  } catch (const std::exception& e) {
    msg2 = e.what();
  }
  EXPECT_NE(msg2.find("mbd.time_step_s"), std::string::npos) << msg2;
  EXPECT_NE(msg2.find("modulus"), std::string::npos) << msg2;
  EXPECT_NO_THROW(mbd::Mechanism(stiff, mbd::LoadModel::None));
}

TEST(MbdConfig, GeometryOrderChecked) {
  const auto msg = error_of(replace(read_400(), "    universal_z_mm: -2100", "    universal_z_mm: -1000"));
  EXPECT_NE(msg.find("universal_z_mm"), std::string::npos) << msg;
}

TEST(MbdConfig, ChamberMustEnclose) {
  const auto msg = error_of(std::regex_replace(read_400(), std::regex("    concave_r_mm: \\[[0-9., ]+\\]"),
                                                "    concave_r_mm: [194, 560]"));
  EXPECT_NE(msg.find("mbd.chamber.mantle_r_mm"), std::string::npos) << msg;
}

TEST(MbdConfig, ToYamlRoundTrip) {
  auto p = load_text(read_400());
  p.effects.motor_droop.enabled = true;
  p.effects.motor_droop.droop_rad_s_per_Nm = 0.4e-3;
  p.effects.cardan_misalignment.enabled = true;
  p.effects.cardan_misalignment.angle_rad = 0.1;
  p.vibrator_static_moment_kg_m = 111.5;
  const std::string y = mbd::to_yaml(p);
  auto root = core::ConfigNode::load_string(y, "fitted.yaml");
  const auto q = mbd::load_mechanism_params(root.child("mbd"));
  EXPECT_NO_THROW(root.finish());
  EXPECT_NEAR(q.vibrator_static_moment_kg_m, 111.5, 1e-9);
  EXPECT_NEAR(q.contact.k, p.contact.k, 1e-6 * p.contact.k);
  EXPECT_NEAR(q.contact.c, p.contact.c, 1e-6 * p.contact.c);
  EXPECT_NEAR(q.bed.viscosity_Pa_s, p.bed.viscosity_Pa_s, 1e-6);
  EXPECT_NEAR(q.dt_s, p.dt_s, 1e-15);
  EXPECT_TRUE(q.effects.motor_droop.enabled);
  EXPECT_NEAR(q.effects.motor_droop.droop_rad_s_per_Nm, 0.4e-3, 1e-12);
  EXPECT_NEAR(q.effects.cardan_misalignment.angle_rad, 0.1, 1e-12);
  EXPECT_NEAR(q.connecting_shaft.com_z_m, p.connecting_shaft.com_z_m, 1e-12);
  EXPECT_EQ(q.chamber.concave.r.size(), p.chamber.concave.r.size());
}

TEST(MbdConfig, ValidateRejectsBadParamsDirectly) {
  mbd::MechanismParams p;
  p.dt_s = 1e-3;
  EXPECT_NO_THROW(mbd::validate(p));
  p.contact.mu_d = 0.5;  // above mu_static
  try {
    mbd::validate(p);
    FAIL() << "expected a throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mbd.contact.mu_dynamic"), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(MbdConfig, ToolsLoadEveryShippedRunConfig) {
  // The tools (bench, diagnosis, generator) read the same files as the nodes: run, coupling, dem sections.
  for (const char* f : {"gyp1200_400rpm.yaml", "gyp1200_600rpm.yaml", "quick_demo.yaml"}) {
    EXPECT_NO_THROW(mbd::load_mechanism_params_file(std::string(CRUSHER_SOURCE_DIR) + "/launch_free_configs/" + f))
        << f;
  }
  EXPECT_THROW(mbd::load_mechanism_params_file("/nonexistent.yaml"), core::ConfigError);
}

// Issue 22: a value inside its range but ~1000x off is refused as a unit slip, naming the likely unit.
TEST(MbdConfig, UnitSlipsRefusedNamingTheLikelyUnit) {
  const auto metres = error_of(replace(read_400(), "    com_z_mm: -700", "    com_z_mm: -0.7"));
  EXPECT_NE(metres.find("mbd.fixed_cone.com_z_mm"), std::string::npos) << metres;
  EXPECT_NE(metres.find("-700"), std::string::npos) << metres;
  EXPECT_NE(metres.find("metres given for mm?"), std::string::npos) << metres;
  const auto per_m = error_of(replace(read_400(), "stiffness_N_per_mm: [320, 320, 970]",
                                      "stiffness_N_per_mm: [320000, 320000, 970000]"));
  EXPECT_NE(per_m.find("mbd.absorbers.stiffness_N_per_mm"), std::string::npos) << per_m;
  EXPECT_NE(per_m.find("N/m given for N/mm?"), std::string::npos) << per_m;
  const auto tonnes = error_of(replace(read_400(), "    mass_kg: 24124.4", "    mass_kg: 24.1244"));
  EXPECT_NE(tonnes.find("mbd.fixed_cone.mass_kg"), std::string::npos) << tonnes;
  EXPECT_NE(tonnes.find("tonnes given for kg?"), std::string::npos) << tonnes;
  // Inside the band, however far from the shipped value, and 0 (a point on O1): accepted.
  EXPECT_EQ(error_of(replace(read_400(), "    com_z_mm: -700", "    com_z_mm: -15")), "");
  EXPECT_EQ(error_of(replace(read_400(), "test_point_mm: [1000, 0, -700]", "test_point_mm: [1000, 0, 0]")), "");
  EXPECT_EQ(error_of(replace(read_400(), "stiffness_N_per_mm: [320, 320, 970]", "stiffness_N_per_mm: [32, 32, 97000]")), "");
}
