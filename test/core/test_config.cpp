#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <set>
#include <vector>

#include "core/config.hpp"
#include "core/units.hpp"

using core::ConfigError;
using core::ConfigNode;

namespace {
std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Config, ReadsNumbersAndConvertsUnits) {
  auto root = ConfigNode::load_string("a:\n  k: 320\n  c: 100\n");
  auto a = root.child("a");
  EXPECT_DOUBLE_EQ(a.number("k", 0, 1e4, "N/mm", core::units::N_per_mm), 320e3);
  EXPECT_DOUBLE_EQ(a.number("c", 0, 1e4, "N s/mm", core::units::Ns_per_mm), 100e3);
  EXPECT_NO_THROW(root.finish());
}

// An absent optional key takes its fallback, given in the file's unit and converted like a given value
// (the fallback was once returned unconverted: a default 40 mm became 40 m).
TEST(Config, OptionalNumberFallbackIsConvertedLikeAGivenValue) {
  auto root = ConfigNode::load_string("a:\n  given_mm: 40\n");
  auto a = root.child("a");
  EXPECT_DOUBLE_EQ(a.number_or("given_mm", 7.0, 0, 100, "mm", 1e-3), 0.040);
  EXPECT_DOUBLE_EQ(a.number_or("absent_mm", 40.0, 0, 100, "mm", 1e-3), 0.040);
  EXPECT_DOUBLE_EQ(a.number_or("absent_s", 2.5, 0, 100, "s"), 2.5);
}

TEST(Config, PowerLawStiffnessConversion) {
  // Table 1: k = 1e5 N/mm^1.5 -> F(1 mm) = 1e5 N; in SI F(1e-3 m) must be the same 1e5 N.
  double k_si = core::units::power_law_stiffness_to_si(1e5, 1.5);
  EXPECT_NEAR(k_si * std::pow(1e-3, 1.5), 1e5, 1e-6);
}

TEST(Config, MissingKeyIsNamed) {
  auto root = ConfigNode::load_string("a:\n  k: 1\n");
  auto msg = message_of([&] { root.child("a").number("c", 0, 10); });
  EXPECT_NE(msg.find("a.c"), std::string::npos) << msg;
  EXPECT_NE(msg.find("missing"), std::string::npos) << msg;
}

TEST(Config, OutOfRangeNamesKeyValueAndRange) {
  auto root = ConfigNode::load_string("dt: -0.5\n");
  auto msg = message_of([&] { root.number("dt", 1e-7, 1e-2, "s"); });
  EXPECT_NE(msg.find("'dt'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("-0.5"), std::string::npos) << msg;
  EXPECT_NE(msg.find("[1e-07, 0.01] s"), std::string::npos) << msg;
}

TEST(Config, UnknownKeyIsReportedWithPath) {
  auto root = ConfigNode::load_string("a:\n  k: 1\n  damping_cofficient: 3\nb: 2\n");
  root.child("a").number("k", 0, 10);
  root.number("b", 0, 10);
  auto msg = message_of([&] { root.finish(); });
  EXPECT_NE(msg.find("a.damping_cofficient"), std::string::npos) << msg;
  EXPECT_EQ(msg.find("a.k"), std::string::npos) << msg;
}

TEST(Config, UnreadTopLevelSectionIsUnknown) {
  auto root = ConfigNode::load_string("a: {k: 1}\nextra: {x: 1}\n");
  root.child("a").number("k", 0, 10);
  auto msg = message_of([&] { root.finish(); });
  EXPECT_NE(msg.find("extra"), std::string::npos) << msg;
}

TEST(Config, ChoiceListsAcceptedValues) {
  auto root = ConfigNode::load_string("load: granite\n");
  auto msg = message_of([&] { root.choice("load", {"none", "bed", "dem"}); });
  EXPECT_NE(msg.find("none, bed, dem"), std::string::npos) << msg;
}

TEST(Config, NotANumberAndBadListsRejected) {
  auto root = ConfigNode::load_string("k: abc\nv: [1, 2]\n");
  EXPECT_THROW(root.number("k", 0, 1), ConfigError);
  auto msg = message_of([&] { root.vector3("v", -1, 10); });
  EXPECT_NE(msg.find("exactly 3"), std::string::npos) << msg;
}

TEST(Config, InvalidYamlAndMissingFile) {
  EXPECT_THROW(ConfigNode::load_string("a: [1, 2"), ConfigError);
  EXPECT_THROW(ConfigNode::load_file("/nonexistent/x.yaml"), ConfigError);
  EXPECT_THROW(ConfigNode::load_string("- 1\n- 2\n"), ConfigError);
}

TEST(Config, IgnoredSectionIsNotUnknown) {
  auto root = ConfigNode::load_string("mbd: {k: 1}\ndem: {anything: 2}\n");
  root.child("mbd").number("k", 0, 10);
  root.ignore("dem");
  EXPECT_NO_THROW(root.finish());
}

#include "core/run_config.hpp"

TEST(RunConfig, ReadsRunSectionAndRejectsBadLoad) {
  auto root = ConfigNode::load_string("run: {duration_s: 5, load: bed, publish_hz: 1000}\n");
  auto o = core::load_run_options(root.child("run"));
  EXPECT_DOUBLE_EQ(o.duration_s, 5);
  EXPECT_EQ(o.load, "bed");
  EXPECT_DOUBLE_EQ(o.publish_hz, 1000);
  EXPECT_NO_THROW(root.finish());
  auto bad = ConfigNode::load_string("run: {duration_s: 5, load: rocks}\n");
  auto msg = message_of([&] { core::load_run_options(bad.child("run")); });
  EXPECT_NE(msg.find("run.load"), std::string::npos) << msg;
  EXPECT_NE(msg.find("none, bed, flow, dem"), std::string::npos) << msg;
}

TEST(RunConfig, CheckpointIntervalIsOffByDefaultAndMustNotBeNegative) {
  auto root = ConfigNode::load_string("run: {duration_s: 5, load: dem}\n");
  EXPECT_EQ(core::load_run_options(root.child("run")).checkpoint_every_s, 0.0);
  auto on = ConfigNode::load_string("run: {duration_s: 5, load: dem, checkpoint_every_s: 0.02}\n");
  EXPECT_DOUBLE_EQ(core::load_run_options(on.child("run")).checkpoint_every_s, 0.02);
  auto bad = ConfigNode::load_string("run: {duration_s: 5, load: dem, checkpoint_every_s: -1}\n");
  auto msg = message_of([&] { core::load_run_options(bad.child("run")); });
  EXPECT_NE(msg.find("run.checkpoint_every_s"), std::string::npos) << msg;
}

TEST(RunConfig, CoupledOverridesApplyToDemRunsOnly) {
  auto root = ConfigNode::load_string(
      "run: {duration_s: 10, load: bed, settle_s: 4, checkpoint_every_s: 2,\n"
      "      coupled: {warm_start_s: 6, settle_s: 0.15, checkpoint_every_s: 0.02}}\n");
  auto o = core::load_run_options(root.child("run"));
  EXPECT_NO_THROW(root.finish());
  auto bed = o;
  core::apply_coupled_overrides(bed);
  EXPECT_EQ(bed.settle_s, 4.0);
  EXPECT_EQ(bed.warm_start_s, 0.0);
  EXPECT_EQ(bed.checkpoint_every_s, 2.0);
  auto dem = o;
  dem.load = "dem";  // as mbd_node's ~load:=dem
  core::apply_coupled_overrides(dem);
  EXPECT_EQ(dem.settle_s, 0.15);
  EXPECT_EQ(dem.warm_start_s, 6.0);
  EXPECT_EQ(dem.checkpoint_every_s, 0.02);
  auto bad = ConfigNode::load_string("run: {duration_s: 10, load: dem, coupled: {settle_s: -1}}\n");
  auto msg = message_of([&] { core::load_run_options(bad.child("run")); });
  EXPECT_NE(msg.find("run.coupled.settle_s"), std::string::npos) << msg;
}

// The mechanism advances whole steps between exchanges: an interval of 1.5 steps was rounded to 2 without a word
// (the 600 rpm config exchanged every 1.33 ms instead of its 1 ms, and checkpointed every 26.7 ms instead of 20).
TEST(RunConfig, CouplingIntervalIsAWholeNumberOfMechanismSteps) {
  EXPECT_EQ(core::coupling_steps(1e-3, 1e-3), 1);
  EXPECT_EQ(core::coupling_steps(1e-3, 5e-4), 2);
  EXPECT_EQ(core::coupling_steps(1e-3, 1e-3 / 3), 3);
  auto msg = message_of([&] { core::coupling_steps(1e-3, 6.67e-4); });
  EXPECT_NE(msg.find("coupling.dt_s"), std::string::npos) << msg;
  EXPECT_NE(msg.find("mbd.time_step_s"), std::string::npos) << msg;
  EXPECT_NE(msg.find("1.49"), std::string::npos) << msg;
  EXPECT_THROW(core::coupling_steps(4e-4, 1e-3), ConfigError);  // shorter than one step
  for (const char* name : {"quick_demo.yaml", "gyp1200_400rpm.yaml", "gyp1200_600rpm.yaml"}) {
    auto root = ConfigNode::load_file(std::string(CRUSHER_SOURCE_DIR) + "/launch_free_configs/" + name);
    const double coupling_dt = root.child("coupling").number("dt_s", 1e-5, 0.05);
    const double mech_dt = root.child("mbd").number("time_step_s", 1e-6, 5e-3);
    EXPECT_NO_THROW(core::coupling_steps(coupling_dt, mech_dt)) << name;
    EXPECT_DOUBLE_EQ(coupling_dt, 1e-3) << name << ": the paper's 1000 Hz exchange (Table 4)";
  }
}

// `base:` inheritance: mappings merge key by key, lists and values replace, the base path is relative to the file
// naming it, a cycle is refused by name.
TEST(Config, BaseConfigIsLaidUnderTheFile) {
  const std::string dir = ::testing::TempDir();
  std::ofstream(dir + "/cfg_base.yaml") << "a:\n  k: 1\n  list: [1, 2, 3]\n  sub: {x: 1, y: 2}\nb: 5\n";
  std::ofstream(dir + "/cfg_over.yaml") << "base: cfg_base.yaml\na:\n  list: [9]\n  sub: {y: 7}\n";
  auto root = ConfigNode::load_file(dir + "/cfg_over.yaml");
  auto a = root.child("a");
  EXPECT_EQ(a.number("k", 0, 10), 1);
  EXPECT_EQ(a.numbers("list", 0, 10), std::vector<double>{9});
  auto sub = a.child("sub");
  EXPECT_EQ(sub.number("x", 0, 10), 1);
  EXPECT_EQ(sub.number("y", 0, 10), 7);
  EXPECT_EQ(root.number("b", 0, 10), 5);
  EXPECT_FALSE(root.has("base"));
  EXPECT_NO_THROW(root.finish());
  std::ofstream(dir + "/cfg_loop.yaml") << "base: cfg_loop.yaml\n";
  const auto msg = message_of([&] { ConfigNode::load_file(dir + "/cfg_loop.yaml"); });
  EXPECT_NE(msg.find("cycle"), std::string::npos) << msg;
}

// A relative path in a config is beside the file that names it: a base in another folder keeps its files, a key the
// derived file gives is beside the derived file; absolute paths and load_string's file name as they are.
TEST(Config, RelativePathsAreBesideTheFileThatNamesThem) {
  const std::string dir = ::testing::TempDir() + "/rel_paths";
  ASSERT_EQ(std::system(("mkdir -p " + dir + "/a " + dir + "/b").c_str()), 0);
  std::ofstream(dir + "/a/base.yaml") << "flow: {material_file: m.yaml, bands: 4}\ndem: {bpm_file: /abs/bpm.yaml}\n";
  std::ofstream(dir + "/b/over.yaml") << "base: ../a/base.yaml\nflow: {bands: 5}\nextra: {file: x.yaml}\n";
  std::ofstream(dir + "/b/over2.yaml") << "base: over.yaml\nflow: {material_file: mine.yaml}\n";
  const auto over = ConfigNode::load_file(dir + "/b/over.yaml");
  EXPECT_EQ(over.child("flow").path_beside("material_file", "m.yaml"), dir + "/b/../a/m.yaml");
  EXPECT_EQ(over.child("flow").file_of("bands"), dir + "/b/over.yaml");
  EXPECT_EQ(over.child("extra").path_beside("file", "x.yaml"), dir + "/b/x.yaml");
  EXPECT_EQ(over.child("dem").path_beside("bpm_file", "/abs/bpm.yaml"), "/abs/bpm.yaml");
  EXPECT_EQ(over.path_beside("missing", "y.yaml"), dir + "/b/y.yaml");  // not in any file: the loaded one's folder
  const auto over2 = ConfigNode::load_file(dir + "/b/over2.yaml");
  EXPECT_EQ(over2.child("flow").path_beside("material_file", "mine.yaml"), dir + "/b/mine.yaml");
  EXPECT_EQ(over2.child("dem").file_of("bpm_file"), dir + "/b/../a/base.yaml");
  EXPECT_EQ(ConfigNode::load_string("a: 1", "/some/where/c.yaml").path_beside("a", "z.yaml"), "/some/where/z.yaml");
}

// The shipped 600 rpm config is the 400 rpm one plus the drive speed and the time step, nothing else.
TEST(Config, The600RpmConfigDiffersFromThe400RpmOneInSpeedAndStepOnly) {
  const std::string dir = std::string(CRUSHER_SOURCE_DIR) + "/launch_free_configs/";
  const auto c400 = ConfigNode::load_file(dir + "gyp1200_400rpm.yaml").raw();
  const auto c600 = ConfigNode::load_file(dir + "gyp1200_600rpm.yaml").raw();
  std::vector<std::string> differ;
  std::function<void(const YAML::Node&, const YAML::Node&, const std::string&)> walk =
      [&](const YAML::Node& x, const YAML::Node& y, const std::string& path) {
        if (x.IsMap() && y.IsMap()) {
          std::set<std::string> keys;
          for (const auto& kv : x) keys.insert(kv.first.as<std::string>());
          for (const auto& kv : y) keys.insert(kv.first.as<std::string>());
          for (const auto& k : keys) walk(x[k], y[k], path.empty() ? k : path + "." + k);
        } else if (YAML::Dump(x) != YAML::Dump(y)) {
          differ.push_back(path);
        }
      };
  walk(c400, c600, "");
  EXPECT_EQ(differ, (std::vector<std::string>{"mbd.drive.speed_rpm", "mbd.time_step_s"}));
}

// Issue 22: a 60 MB list in a config took 7.7 GB. Oversize files and lists are refused by name before parsing.
TEST(Config, OversizeFilesAndListsRefusedByName) {
  std::string list = "a:\n  b: [";
  for (int i = 0; i <= core::kMaxConfigList; ++i) list += i ? ", 1" : "1";
  list += "]\n";
  const auto m = message_of([&] { ConfigNode::load_string(list, "long.yaml"); });
  EXPECT_NE(m.find("config long.yaml: 'a.b' is a list of more than 10000 elements"), std::string::npos) << m;
  std::string ok = "a:\n  b: [";
  for (int i = 0; i < core::kMaxConfigList; ++i) ok += i ? ", 1" : "1";
  ok += "]\n";
  EXPECT_EQ(ConfigNode::load_string(ok, "ok.yaml").child("a").numbers("b", 0, 2).size(), 10000u);

  const std::string path = testing::TempDir() + "/big_config.yaml";
  {
    std::ofstream f(path);
    f << "a: 1\n";
    const std::string pad(1023, '#');
    for (int i = 0; i < 1100; ++i) f << pad << "\n";  // 1.1 MB of comments
  }
  const auto big = message_of([&] { ConfigNode::load_file(path); });
  EXPECT_NE(big.find("config " + path + ": "), std::string::npos) << big;
  EXPECT_NE(big.find("bytes; accepted at most 1048576"), std::string::npos) << big;
  std::remove(path.c_str());
}
