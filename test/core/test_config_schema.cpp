// The config schema (core/config_schema.hpp) of every section on it: round trip of the shipped configs, every key
// refused by name when unknown, missing (if required) or out of range, duplicate keys, the inherited 600 rpm config.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <set>

#include "chamber/flow_config.hpp"
#include "coupling/chamber_params.hpp"
#include "core/config_schema.hpp"
#include "core/run_config.hpp"
#include "mbd/mechanism_params.hpp"
#include "mbd/mechanism_schema.hpp"
#include "rocks/bpm_config.hpp"

using core::ConfigError;
using core::ConfigNode;

namespace {

const std::string kDir = std::string(CRUSHER_SOURCE_DIR) + "/launch_free_configs/";

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

std::string dump(const YAML::Node& n) {
  YAML::Emitter e;
  e << n;
  return e.c_str();
}

// One schema section: its name, its keys, and "load the section of this root and write it back" (finish() checked).
struct Section {
  std::string name;
  std::vector<core::KeyInfo> keys;
  std::function<YAML::Node(const ConfigNode& root)> load_write;
};

template <class T>
Section section(const std::string& name, const core::Schema<T>& s,
                std::function<T(const ConfigNode&)> load) {
  return {name, s.keys(), [name, &s, load](const ConfigNode& root) {
            T v = load(root.child(name));
            root.finish();
            return s.write(v);
          }};
}

// A plant's own config in its own folder, on the shipped one as its base: the base's relative bpm_file is found
// beside the base (it was looked for beside the plant's file).
TEST(ConfigSchema, ADerivedConfigElsewhereFindsItsBasesFiles) {
  const std::string file = ::testing::TempDir() + "/plant_gyp1200.yaml";
  std::ofstream(file) << "base: " << kDir << "gyp1200_400rpm.yaml\nmbd: {drive: {speed_rpm: 450}}\n";
  const auto root = ConfigNode::load_file(file);
  EXPECT_NO_THROW(coupling::load_chamber_params(root.child("dem"), {}, 0, 0));
}

// Loaded as if it were a file in launch_free_configs (relative bpm_file).
ConfigNode load_text(const std::string& text) { return ConfigNode::load_string(text, kDir + "schema_test.yaml"); }

std::vector<Section> sections() {
  Section dem{"dem", coupling::chamber_schema().keys(), [](const ConfigNode& root) {
                const auto v = coupling::load_chamber_params(root.child("dem"), {}, 0, 0);
                root.finish();
                YAML::Node w = coupling::chamber_schema().write(v);
                for (const char* k : {"bpm", "bpm_file"})  // not on the schema: passed through as given
                  if (root.raw()["dem"][k]) w[k] = root.raw()["dem"][k];
                return w;
              }};
  return {dem,
          section<core::RunOptions>("run", core::run_schema(), core::load_run_options),
          section<mbd::MechanismParams>("mbd", mbd::mechanism_schema(), mbd::load_mechanism_params),
          section<core::CouplingOptions>("coupling", core::coupling_schema(), core::load_coupling_options),
          section<chamber::FlowParams>("flow", chamber::flow_schema(), chamber::load_flow_params),
          section<chamber::FlowMaterial>("flow_material", chamber::flow_material_schema(),
                                         [](const ConfigNode& n) { return chamber::flow_material_from_config(n); }),
          // bpm.bond and bpm.packing as top-level keys of that name (the test only needs the key path).
          section<rocks::BondSettings>("bpm.bond", rocks::bond_schema(), rocks::bond_settings_from_config),
          section<rocks::PackingOptions>("bpm.packing", rocks::packing_schema(), rocks::packing_from_config),
          section<rocks::MetaparticleKeys>("bpm.metaparticles", rocks::metaparticles_schema(),
                                           rocks::metaparticle_keys_from_config)};
}

// A valid document holding only `name`: the section of a shipped config as the schema writes it (flow_material: the
// 400 rpm config's flow.material; bpm.*: bpm_calibrated.yaml's).
YAML::Node valid_doc(const Section& s) {
  std::string file = "gyp1200_400rpm.yaml";
  std::vector<std::string> at{s.name};
  if (s.name == "flow_material") at = {"flow", "material"};
  if (s.name.rfind("bpm.", 0) == 0) file = "bpm_calibrated.yaml", at = {"bpm", s.name.substr(4)};
  YAML::Node sec = YAML::Clone(ConfigNode::load_file(kDir + file).raw());
  for (const auto& k : at) sec.reset(YAML::Node(sec[k]));
  YAML::Node doc;
  doc[s.name] = sec;
  YAML::Node written = s.load_write(load_text(dump(doc)));
  YAML::Node out;
  out[s.name] = written;
  return out;
}

YAML::Node remove_path(YAML::Node n, const std::string& path) {
  const auto dot = path.find('.');
  if (dot == std::string::npos) {
    n.remove(path);
  } else {
    YAML::Node c = n[path.substr(0, dot)];
    remove_path(c, path.substr(dot + 1));
  }
  return n;
}

}  // namespace

// load -> write -> load is the identity for every shipped run config and every schema section.
TEST(ConfigSchema, ShippedConfigsRoundTrip) {
  for (const char* file : {"gyp1200_400rpm.yaml", "gyp1200_600rpm.yaml", "gyp1200_400rpm_bed.yaml",
                           "gyp1200_600rpm_bed.yaml", "quick_demo.yaml", "gyp1200_400rpm_solid_divergence.yaml",
                           "gyp1200_600rpm_solid_divergence.yaml"}) {
    for (const auto& s : sections()) {
      if (s.name == "flow_material" || s.name.rfind("bpm.", 0) == 0) continue;  // not sections of a run config
      const auto root = ConfigNode::load_file(kDir + file);
      if (!root.has(s.name)) continue;
      YAML::Node doc;
      doc[s.name] = root.raw()[s.name];
      const YAML::Node once = s.load_write(load_text(dump(doc)));
      YAML::Node doc2;
      doc2[s.name] = once;
      const YAML::Node twice = s.load_write(load_text(dump(doc2)));
      EXPECT_EQ(dump(once), dump(twice)) << file << " " << s.name;
      // Every value the file gives is the value written back (numbers compared as numbers).
      std::function<void(const YAML::Node&, const YAML::Node&, const std::string&)> same =
          [&](const YAML::Node& given, const YAML::Node& w, const std::string& path) {
            if (given.IsMap()) {
              for (const auto& kv : given) {
                const std::string k = kv.first.as<std::string>();
                if (k == "material_file") continue;  // read only: its values are written under material
                ASSERT_TRUE(w[k].IsDefined()) << file << ": " << path << "." << k << " not written back";
                same(kv.second, w[k], path + "." + k);
              }
            } else if (given.IsSequence()) {
              ASSERT_EQ(given.size(), w.size()) << file << ": " << path;
              for (std::size_t i = 0; i < given.size(); ++i) same(given[i], w[i], path);
            } else {
              double a = 0, b = 0;
              if (YAML::convert<double>::decode(given, a) && YAML::convert<double>::decode(w, b))
                EXPECT_NEAR(a, b, 1e-10 * std::abs(a)) << file << ": " << path;
              else
                EXPECT_EQ(given.as<std::string>(), w.as<std::string>()) << file << ": " << path;
            }
          };
      same(root.raw()[s.name], once, s.name);
    }
  }
}

// Every key of every section: out of range (or of the wrong kind) is refused naming it; a required one missing is
// refused naming it; an unknown key beside it is refused naming that. Loops over the schema, not a hand list.
TEST(ConfigSchema, EveryKeyIsRefusedByNameWhenBad) {
  for (const auto& s : sections()) {
    const YAML::Node good = valid_doc(s);
    ASSERT_EQ(message_of([&] { s.load_write(load_text(dump(good))); }), "") << s.name;
    ASSERT_FALSE(s.keys.empty());
    for (const auto& k : s.keys) {
      const std::string full = s.name + "." + k.name;
      YAML::Node bad = YAML::Clone(good);
      YAML::Node sec = bad[s.name];
      std::string expect;
      switch (k.kind) {
        case core::KeyKind::Number:
        case core::KeyKind::Integer:
          core::set_path(sec, k.name, YAML::Node(k.hi + std::abs(k.hi) + 1));
          expect = "out of range";
          break;
        case core::KeyKind::Numbers: {
          YAML::Node l(YAML::NodeType::Sequence);
          for (int i = 0; i < std::max(1, k.length); ++i) l.push_back(k.lo - std::abs(k.lo) - 1);
          core::set_path(sec, k.name, l);
          expect = "out of range";
          break;
        }
        case core::KeyKind::Boolean:
          core::set_path(sec, k.name, YAML::Node("maybe"));
          expect = "true or false";
          break;
        case core::KeyKind::Choice:
          core::set_path(sec, k.name, YAML::Node("bogus"));
          expect = "not accepted";
          break;
        case core::KeyKind::Text: {
          YAML::Node l(YAML::NodeType::Sequence);
          l.push_back(1);
          core::set_path(sec, k.name, l);
          expect = "must be a string";
          break;
        }
      }
      if (!k.applies_to.empty()) expect = "applies to " + k.applies_to;  // not in this config (mbd.bed.rebound)
      std::string msg = message_of([&] { s.load_write(load_text(dump(bad))); });
      EXPECT_NE(msg.find("'" + full + "'"), std::string::npos) << full << ": " << msg;
      EXPECT_NE(msg.find(expect), std::string::npos) << full << ": " << msg;
      if ((k.kind == core::KeyKind::Number || k.kind == core::KeyKind::Numbers) && k.applies_to.empty()) {
        std::ostringstream range;
        range << "[" << k.lo << ", " << k.hi << "]" << (k.unit.empty() ? "" : " " + k.unit);
        EXPECT_NE(msg.find(range.str()), std::string::npos) << full << ": " << msg;
      }
      // An unknown key beside it.
      YAML::Node typo = YAML::Clone(good);
      YAML::Node tsec = typo[s.name];
      core::set_path(tsec, k.name + "_typo", YAML::Node(1));
      msg = message_of([&] { s.load_write(load_text(dump(typo))); });
      EXPECT_NE(msg.find("unknown key(s): " + full + "_typo"), std::string::npos) << full << ": " << msg;
      if (k.required && k.applies_to.empty()) {
        YAML::Node missing = YAML::Clone(good);
        remove_path(missing[s.name], k.name);
        msg = message_of([&] { s.load_write(load_text(dump(missing))); });
        EXPECT_NE(msg.find("'" + full + "': missing (required)"), std::string::npos) << full << ": " << msg;
      }
    }
  }
}

// The checkpoint fingerprint (mbd::to_yaml) of the shipped config is byte for byte what the code before the schema
// wrote (test/fixtures/mbd_fingerprint_gyp1200_400rpm.yaml), so checkpoints written before it still resume.
TEST(ConfigSchema, MechanismFingerprintIsUnchanged) {
  std::ifstream in(std::string(CRUSHER_SOURCE_DIR) + "/test/fixtures/mbd_fingerprint_gyp1200_400rpm.yaml");
  std::stringstream old;
  old << in.rdbuf();
  const auto root = ConfigNode::load_file(kDir + "gyp1200_400rpm.yaml");
  EXPECT_EQ(mbd::to_yaml(mbd::load_mechanism_params(root.child("mbd"))), old.str());
}

// A key that exists only for one bed law: required with it, refused without it, written back only with it.
TEST(ConfigSchema, BedReboundBelongsToTheHystereticLaw) {
  auto root = ConfigNode::load_file(kDir + "gyp1200_400rpm.yaml");
  YAML::Node doc;
  doc["mbd"] = YAML::Clone(root.raw()["mbd"]);
  doc["mbd"]["bed"]["law"] = "hysteretic";
  auto msg = message_of([&] { mbd::load_mechanism_params(load_text(dump(doc)).child("mbd")); });
  EXPECT_NE(msg.find("'mbd.bed.rebound': missing (required)"), std::string::npos) << msg;
  doc["mbd"]["bed"]["rebound"] = 0.2;
  const auto p = mbd::load_mechanism_params(load_text(dump(doc)).child("mbd"));
  EXPECT_DOUBLE_EQ(p.bed.rebound, 0.2);
  EXPECT_NE(mbd::to_yaml(p).find("rebound: 0.2\n"), std::string::npos);
  doc["mbd"]["bed"]["law"] = "viscous";
  msg = message_of([&] { mbd::load_mechanism_params(load_text(dump(doc)).child("mbd")); });
  EXPECT_NE(msg.find("'mbd.bed.rebound': applies to law: hysteretic only"), std::string::npos) << msg;
}

// A default outside its range means "not set": it is neither printed as a value nor written back.
TEST(ConfigSchema, UnsetDefaultsAreNotWritten) {
  core::RunOptions r;
  const YAML::Node y = core::run_schema().write(r);
  EXPECT_FALSE(y["coupled"].IsDefined()) << dump(y);
  bool seen = false;
  for (const auto& k : core::run_schema().keys())
    if (k.name == "coupled.settle_s") seen = (k.default_text == "unset");
  EXPECT_TRUE(seen);
}

// The key reference names every key of every section with its unit, range and default.
TEST(ConfigSchema, KeyReferenceListsEveryKey) {
  for (const auto& s : sections()) {
    const std::string ref = core::key_reference(s.name, s.keys);
    std::istringstream lines(ref);
    std::string line;
    std::size_t i = 0;
    while (std::getline(lines, line)) {
      ASSERT_LT(i, s.keys.size()) << ref;
      const auto& k = s.keys[i++];
      EXPECT_EQ(line.rfind(s.name + "." + k.name + " ", 0), 0u) << line;
      EXPECT_NE(line.find(k.default_text), std::string::npos) << line;
      EXPECT_NE(line.find(k.meaning), std::string::npos) << line;
      if (!k.unit.empty()) EXPECT_NE(line.find(" " + k.unit + " "), std::string::npos) << line;
    }
    EXPECT_EQ(i, s.keys.size()) << ref;
  }
}

// Duplicate keys are refused by name, at any depth, in a file and in its base (yaml-cpp keeps the first silently).
TEST(ConfigSchema, DuplicateKeysAreRefusedByName) {
  auto msg = message_of([] { ConfigNode::load_string("run:\n  load: flow\n  load: dem\n", "dup.yaml"); });
  EXPECT_NE(msg.find("config dup.yaml: key 'run.load' appears twice"), std::string::npos) << msg;
  msg = message_of([] { ConfigNode::load_string("flow:\n  material:\n    pressure: {exponent: 2, exponent: 3}\n"); });
  EXPECT_NE(msg.find("key 'flow.material.pressure.exponent' appears twice"), std::string::npos) << msg;
  msg = message_of([] { ConfigNode::load_string("a: 1\nb: 2\na: 3\n"); });
  EXPECT_NE(msg.find("key 'a' appears twice"), std::string::npos) << msg;
  // The same key in different mappings, or in a list of mappings, is not a duplicate.
  EXPECT_EQ(message_of([] { ConfigNode::load_string("a: {x: 1}\nb: {x: 1}\nc: [{x: 1}, {x: 2}]\n"); }), "");
  const std::string dir = ::testing::TempDir();
  std::ofstream(dir + "/dup_base.yaml") << "mbd:\n  drive:\n    speed_rpm: 400\n    speed_rpm: 600\n";
  std::ofstream(dir + "/dup_over.yaml") << "base: dup_base.yaml\nrun: {load: flow}\n";
  msg = message_of([&] { ConfigNode::load_file(dir + "/dup_over.yaml"); });
  EXPECT_NE(msg.find("dup_base.yaml: key 'mbd.drive.speed_rpm' appears twice"), std::string::npos) << msg;
}

// gyp1200_600rpm.yaml names the 400 rpm file as its base: it equals the old full copy (the 400 rpm file with the
// speed and the time step set) key for key, as read by every loader.
TEST(ConfigSchema, Inherited600RpmConfigEqualsTheFullOne) {
  const auto inherited = ConfigNode::load_file(kDir + "gyp1200_600rpm.yaml");
  std::ifstream in(kDir + "gyp1200_400rpm.yaml");
  std::stringstream text;
  text << in.rdbuf();
  YAML::Node full = YAML::Load(text.str());
  full["mbd"]["time_step_s"] = 5.0e-4;
  full["mbd"]["drive"]["speed_rpm"] = 600;
  const auto old = ConfigNode::load_string(dump(full), kDir + "gyp1200_600rpm_full.yaml");
  std::vector<std::string> differ;
  std::function<void(const YAML::Node&, const YAML::Node&, const std::string&)> walk =
      [&](const YAML::Node& x, const YAML::Node& y, const std::string& path) {
        if (x.IsMap() && y.IsMap()) {
          std::set<std::string> keys;
          for (const auto& kv : x) keys.insert(kv.first.as<std::string>());
          for (const auto& kv : y) keys.insert(kv.first.as<std::string>());
          for (const auto& k : keys) walk(x[k], y[k], path.empty() ? k : path + "." + k);
          return;
        }
        double a = 0, b = 0;  // numbers as numbers (5.0e-4 is 0.0005)
        if (x.IsScalar() && y.IsScalar() && YAML::convert<double>::decode(x, a) &&
            YAML::convert<double>::decode(y, b)) {
          if (a != b) differ.push_back(path);
        } else if (dump(x) != dump(y)) {
          differ.push_back(path);
        }
      };
  walk(inherited.raw(), old.raw(), "");
  EXPECT_TRUE(differ.empty()) << differ.size() << " keys differ, first " << differ.front();
  EXPECT_EQ(mbd::to_yaml(mbd::load_mechanism_params(inherited.child("mbd"))),
            mbd::to_yaml(mbd::load_mechanism_params(old.child("mbd"))));
  for (const auto& s : sections()) {
    if (s.name == "flow_material" || s.name.rfind("bpm.", 0) == 0) continue;
    const auto a = ConfigNode::load_file(kDir + "gyp1200_600rpm.yaml");
    const auto b = ConfigNode::load_string(dump(full), kDir + "gyp1200_600rpm_full.yaml");
    for (const auto& other : sections())
      if (other.name != s.name) a.ignore(other.name), b.ignore(other.name);
    a.ignore("diagnosis"), b.ignore("diagnosis");  // crusher diagnose's, not a loader's section
    EXPECT_EQ(dump(s.load_write(a)), dump(s.load_write(b))) << s.name;
  }
}

// bpm.metaparticles: a preset, or explicit modes read through the schema. The paper's bimodal distribution written
// as modes equals its preset; a mode key out of range, a second mode without its volume share, and modes beside a
// preset are refused by name.
TEST(ConfigSchema, MetaparticleModesOrAPreset) {
  auto load = [](const std::string& yaml) {
    return rocks::SizeDistribution::from_config(load_text("m: " + yaml).child("m"));
  };
  const auto modes = load("{coarse: {mean_radius_mm: 3, sd_mm: 0.525}, fine: {mean_radius_mm: 1, sd_mm: 0.225}, "
                          "coarse_volume_fraction: 0.7}");
  const auto preset = rocks::SizeDistribution::preset("paper_bimodal");
  ASSERT_EQ(modes.modes().size(), preset.modes().size());
  for (std::size_t i = 0; i < modes.modes().size(); ++i) {
    EXPECT_DOUBLE_EQ(modes.modes()[i].mean_radius, preset.modes()[i].mean_radius);
    EXPECT_DOUBLE_EQ(modes.modes()[i].sd, preset.modes()[i].sd);
    EXPECT_DOUBLE_EQ(modes.modes()[i].volume_fraction, preset.modes()[i].volume_fraction);
  }
  EXPECT_DOUBLE_EQ(modes.truncate_sd(), preset.truncate_sd());
  EXPECT_EQ(load("{coarse: {mean_radius_mm: 2, sd_mm: 0.1}}").modes().size(), 1u);
  auto msg = message_of([&] { load("{coarse: {mean_radius_mm: 2, sd_mm: 60}}"); });
  EXPECT_NE(msg.find("'m.coarse.sd_mm'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("[0, 50] mm"), std::string::npos) << msg;
  msg = message_of([&] { load("{coarse: {mean_radius_mm: 2, sd_mm: 0.1}, fine: {mean_radius_mm: 1, sd_mm: 0.1}}"); });
  EXPECT_NE(msg.find("'m.coarse_volume_fraction': missing (required)"), std::string::npos) << msg;
  msg = message_of([&] { load("{preset: mono3, coarse: {mean_radius_mm: 2, sd_mm: 0.1}}"); });
  EXPECT_NE(msg.find("'m.coarse.mean_radius_mm': applies to modes (no preset)"), std::string::npos) << msg;
  msg = message_of([&] { load("{}"); });
  EXPECT_NE(msg.find("'m.coarse': missing (required)"), std::string::npos) << msg;
}

// A value refused by its range whose 1000x (or 1/1000) lies in the key's plausible band is refused naming the likely
// slip (issue 22: metres in a mm key whose range starts at 0.01 mm, kPa where MPa are read); other refusals as before.
TEST(ConfigSchema, ARangeRefusalNamesTheLikelySlip) {
  struct Toy {
    double size = 0, strength = 0;
    std::vector<double> sieves;
  };
  core::Schema<Toy> s;
  s.number("size_mm", "mm", 1e-3, 0.01, 1000, [](Toy& t) -> double& { return t.size; }, "a size")
      .plausible(1, 1000, "metres given for mm?", "")
      .number("strength_MPa", "MPa", 1e6, 0.01, 1000, [](Toy& t) -> double& { return t.strength; }, "a strength")
      .plausible(0.1, 1000, "GPa given for MPa?", "kPa given for MPa?")
      .numbers("sieves_mm", "mm", 1e-3, 0.01, 1000, [](Toy& t) -> std::vector<double>& { return t.sieves; }, "sieves")
      .plausible(0.02, 1000, "metres given for mm?", "");
  auto error_of = [&](const std::string& yaml) {
    return message_of([&] { s.read(ConfigNode::load_string("t: " + yaml, "toy.yaml").child("t")); });
  };
  std::string msg = error_of("{size_mm: 0.005}");  // 5 mm in metres: below the range
  EXPECT_NE(msg.find("'t.size_mm': value 0.005 is out of range; accepted [0.01, 1000] mm"), std::string::npos) << msg;
  EXPECT_NE(msg.find("1000x that (5) would fit: metres given for mm? (refused as a likely unit slip)"),
            std::string::npos) << msg;
  msg = error_of("{strength_MPa: 25000}");  // 25 MPa in kPa: above the range
  EXPECT_NE(msg.find("'t.strength_MPa'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("1/1000 of it (25) would fit: kPa given for MPa?"), std::string::npos) << msg;
  msg = error_of("{sieves_mm: [0.001, 0.004, 0.016]}");  // sieves in metres: the first refused
  EXPECT_NE(msg.find("element 0 value 0.001 is out of range"), std::string::npos) << msg;
  EXPECT_NE(msg.find("1000x that (1) would fit: metres given for mm?"), std::string::npos) << msg;
  // Out of range and no slip fits, or no number at all: the refusal as before, no guess.
  for (const char* yaml : {"{size_mm: 0.000001}", "{size_mm: 5000000}", "{size_mm: abc}", "{strength_MPa: .nan}"}) {
    msg = error_of(yaml);
    EXPECT_NE(msg.find("'t."), std::string::npos) << yaml << ": " << msg;
    EXPECT_EQ(msg.find("would fit"), std::string::npos) << yaml << ": " << msg;
  }
  EXPECT_EQ(error_of("{size_mm: 5, strength_MPa: 25, sieves_mm: [1, 4, 16]}"), "");
}
