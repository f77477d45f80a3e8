#pragma once
// Validated access to YAML run configurations.
// Every read names the key path, the accepted range and the unit, so a bad config fails before any
// simulation with a message a user can act on. Keys never read are reported by finish().
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace core {

// Input bounds: a config file (each file of a `base:` chain) of at most kMaxConfigBytes, lists of at most
// kMaxConfigList elements; larger ones are refused by name before they are parsed into memory. The shipped configs
// are under 15 KB with lists of at most 11 elements.
constexpr long long kMaxConfigBytes = 1 << 20;
constexpr int kMaxConfigList = 10000;

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A view of one YAML mapping with its key path ("mbd.absorber.k") for messages.
class ConfigNode {
 public:
  ConfigNode(YAML::Node node, std::string path, std::string file);

  // Throws ConfigError. A top-level `base: FILE` (relative to this file) is loaded first and this file's keys laid
  // over it: mappings merge key by key, lists and values replace (the 600 rpm config is the 400 rpm one plus what
  // differs). A relative path inside a config (material_file, bpm_file) is relative to the file that names it (a
  // base in another folder keeps its files): resolve it with path_beside().
  static ConfigNode load_file(const std::string& file);
  static ConfigNode load_string(const std::string& text, const std::string& name = "<string>");

  // Plausible bands (config_schema.hpp) guard what a person types. A config a program writes in the keys' own units
  // (the diagnosis's candidates at values near their nominal 0, e.g. 0.15 mm of wear) skips them; the hard ranges
  // still hold. Children inherit it.
  ConfigNode& without_unit_slip_checks() {
    unit_slip_checks_ = false;
    return *this;
  }
  bool unit_slip_checks() const { return unit_slip_checks_; }

  bool has(const std::string& key) const;
  ConfigNode child(const std::string& key) const;            // required mapping
  ConfigNode child_or_empty(const std::string& key) const;   // optional mapping

  // Required number in [lo, hi]; `scale` converts the file's unit to SI (e.g. 1e3 for N/mm -> N/m).
  double number(const std::string& key, double lo, double hi, const std::string& unit = "",
                double scale = 1.0) const;
  // Optional number; `fallback` is in the file's unit too (converted like a given value).
  double number_or(const std::string& key, double fallback, double lo, double hi,
                   const std::string& unit = "", double scale = 1.0) const;
  int integer(const std::string& key, long lo, long hi) const;
  int integer_or(const std::string& key, int fallback, long lo, long hi) const;
  bool boolean(const std::string& key) const;
  bool boolean_or(const std::string& key, bool fallback) const;
  std::string text(const std::string& key) const;
  std::string choice(const std::string& key, const std::vector<std::string>& accepted) const;
  std::string choice_or(const std::string& key, const std::string& fallback,
                        const std::vector<std::string>& accepted) const;
  // Fixed-length or free-length list of numbers, each in [lo, hi], scaled to SI.
  std::vector<double> numbers(const std::string& key, double lo, double hi, const std::string& unit = "",
                              double scale = 1.0, int exact_length = -1) const;
  Eigen::Vector3d vector3(const std::string& key, double lo, double hi, const std::string& unit = "",
                          double scale = 1.0) const;
  Eigen::Vector3d vector3_or(const std::string& key, const Eigen::Vector3d& fallback, double lo,
                             double hi, const std::string& unit = "", double scale = 1.0) const;

  // Throws ConfigError naming every key of this mapping (recursively, for children taken with
  // child()) that no read consumed: catches typos such as "damping_cofficient".
  void finish() const;
  // Marks a key as read by another program (e.g. the `dem:` section in mbd_node) without checking it.
  void ignore(const std::string& key) const { if (has(key)) mark(key); }

  const std::string& path() const { return path_; }
  const std::string& file() const { return file_; }
  // The file whose text gives `key` (a base's, when the loaded file does not override it); file() otherwise.
  const std::string& file_of(const std::string& key) const;
  // `relative` (a value of `key`) made relative to the folder of the file that gives `key`; absolute or "": as it is.
  std::string path_beside(const std::string& key, const std::string& relative) const;
  YAML::Node raw() const { return node_; }
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;

 private:
  YAML::Node get(const std::string& key) const;  // required
  std::string where(const std::string& key) const;
  void mark(const std::string& key) const;

  YAML::Node node_;
  std::string path_;
  std::string file_;
  std::shared_ptr<std::set<std::string>> used_;  // full key paths consumed, shared across children
  std::shared_ptr<std::vector<std::string>> children_;  // child paths to check in finish()
  // Full key path of each value -> the file of the base chain that gives it (load_file; none for load_string).
  std::shared_ptr<const std::map<std::string, std::string>> origin_;
  bool unit_slip_checks_ = true;
};

}  // namespace core
