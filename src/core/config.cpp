#include "core/config.hpp"
#include "core/config_schema.hpp"

#include <yaml-cpp/eventhandler.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

namespace core {

namespace {
std::string join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}
std::string range_text(double lo, double hi, const std::string& unit) {
  std::ostringstream s;
  s << "[" << lo << ", " << hi << "]" << (unit.empty() ? "" : " " + unit);
  return s.str();
}
}  // namespace

ConfigNode::ConfigNode(YAML::Node node, std::string path, std::string file)
    : node_(std::move(node)),
      path_(std::move(path)),
      file_(std::move(file)),
      used_(std::make_shared<std::set<std::string>>()),
      children_(std::make_shared<std::vector<std::string>>()) {}

namespace {
// Walks the parse events of a YAML text and throws ConfigError at the first key that appears twice in one mapping
// (yaml-cpp would keep the first silently) and at a list longer than kMaxConfigList (before yaml-cpp builds it:
// issue 22, a 60 MB list took 7.7 GB).
class DuplicateKeys : public YAML::EventHandler {
 public:
  explicit DuplicateKeys(std::string name) : name_(std::move(name)) {}
  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& m, YAML::anchor_t) override { node(m, "~"); }
  void OnAlias(const YAML::Mark& m, YAML::anchor_t) override { node(m, "*"); }
  void OnScalar(const YAML::Mark& m, const std::string&, YAML::anchor_t, const std::string& v) override { node(m, v); }
  void OnSequenceStart(const YAML::Mark& m, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    open(m, false);
  }
  void OnSequenceEnd() override { close(); }
  void OnMapStart(const YAML::Mark& m, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    open(m, true);
  }
  void OnMapEnd() override { close(); }

 private:
  struct Frame {
    bool map;
    std::string path;
    bool want_key = true;
    int index = 0;
    std::string key;
    std::map<std::string, int> lines;  // key -> line of its first appearance
  };
  std::string child_path() const {  // path of the value now being parsed
    if (stack_.empty()) return "";
    const Frame& f = stack_.back();
    if (!f.map) return f.path + "[" + std::to_string(f.index) + "]";
    return f.path.empty() ? f.key : f.path + "." + f.key;
  }
  void node(const YAML::Mark& m, const std::string& v) {
    if (!stack_.empty() && stack_.back().map && stack_.back().want_key) {
      Frame& f = stack_.back();
      const std::string full = f.path.empty() ? v : f.path + "." + v;
      auto [it, fresh] = f.lines.emplace(v, m.line + 1);
      if (!fresh)
        throw ConfigError("config " + name_ + ": key '" + full + "' appears twice (lines " +
                          std::to_string(it->second) + " and " + std::to_string(m.line + 1) + ")");
      f.key = v;
    }
    done();
  }
  void open(const YAML::Mark&, bool map) {
    Frame f;
    f.map = map;
    f.path = child_path();
    stack_.push_back(f);
  }
  void close() {
    stack_.pop_back();
    done();
  }
  void done() {  // a whole node (key or value) was parsed in the enclosing collection
    if (stack_.empty()) return;
    Frame& f = stack_.back();
    if (f.map) f.want_key = !f.want_key;
    else if (++f.index > kMaxConfigList)
      throw ConfigError("config " + name_ + ": '" + (f.path.empty() ? "the top level" : f.path) +
                        "' is a list of more than " + std::to_string(kMaxConfigList) +
                        " elements; accepted at most that many (a run config's lists are short: is it the right file?)");
  }
  std::string name_;
  std::vector<Frame> stack_;
};

// The text parsed as YAML, refusing duplicate keys by name.
YAML::Node parse(const std::string& text, const std::string& name) {
  try {
    std::istringstream in(text);
    YAML::Parser parser(in);
    DuplicateKeys dup(name);
    while (parser.HandleNextDocument(dup)) {
    }
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError("config " + name + ": not valid YAML: " + e.what());
  }
}

}  // namespace

YAML::Node merged(const YAML::Node& base, const YAML::Node& over) {
  if (!base.IsMap() || !over.IsMap()) return YAML::Clone(over);
  YAML::Node out = YAML::Clone(base);
  for (const auto& kv : over) {
    const std::string k = kv.first.as<std::string>();
    out[k] = out[k] ? merged(out[k], kv.second) : YAML::Clone(kv.second);
  }
  return out;
}

namespace {
// `relative` beside `file` (in its folder); absolute or "": as it is.
std::string beside(const std::string& file, const std::string& relative) {
  if (relative.empty() || relative[0] == '/') return relative;
  const auto slash = file.find_last_of('/');
  return slash == std::string::npos ? relative : file.substr(0, slash + 1) + relative;
}

// Records `file` as the origin of every key under the mapping n (full dotted paths).
void note_origins(const YAML::Node& n, const std::string& prefix, const std::string& file,
                  std::map<std::string, std::string>& origin) {
  if (!n.IsMap()) return;
  for (const auto& kv : n) {
    const std::string full = join(prefix, kv.first.as<std::string>());
    origin[full] = file;
    note_origins(kv.second, full, file, origin);
  }
}

// The file's mapping with its `base:` chain resolved (a base path is relative to the file naming it); origin: the
// file that gives each key (this file's keys over its base's).
YAML::Node resolved(const std::string& file, int depth, std::map<std::string, std::string>& origin) {
  std::ifstream in(file);
  if (!in) throw ConfigError("config: cannot open '" + file + "'");
  in.seekg(0, std::ios::end);
  const auto size = static_cast<long long>(in.tellg());
  in.seekg(0);
  if (size > kMaxConfigBytes)
    throw ConfigError("config " + file + ": " + std::to_string(size) + " bytes; accepted at most " +
                      std::to_string(kMaxConfigBytes) + " (1 MiB; a run config is a few KB: is it the right file?)");
  std::stringstream ss;
  ss << in.rdbuf();
  YAML::Node root = parse(ss.str(), file);
  if (!root.IsMap()) throw ConfigError("config " + file + ": the top level must be a mapping of keys");
  if (!root["base"]) {
    note_origins(root, "", file, origin);
    return root;
  }
  if (!root["base"].IsScalar()) throw ConfigError("config " + file + ": key 'base' must be a file name (a config)");
  if (depth >= 8) throw ConfigError("config " + file + ": 'base' chains deeper than 8 files (a cycle?)");
  const std::string base = beside(file, root["base"].as<std::string>());
  root.remove("base");
  YAML::Node out = merged(resolved(base, depth + 1, origin), root);
  note_origins(root, "", file, origin);
  return out;
}
}  // namespace

ConfigNode ConfigNode::load_file(const std::string& file) {
  auto origin = std::make_shared<std::map<std::string, std::string>>();
  ConfigNode n(resolved(file, 0, *origin), "", file);
  n.origin_ = std::move(origin);
  return n;
}

const std::string& ConfigNode::file_of(const std::string& key) const {
  if (origin_) {
    const auto it = origin_->find(join(path_, key));
    if (it != origin_->end()) return it->second;
  }
  return file_;
}

std::string ConfigNode::path_beside(const std::string& key, const std::string& relative) const {
  return beside(file_of(key), relative);
}

ConfigNode ConfigNode::load_string(const std::string& text, const std::string& name) {
  if (static_cast<long long>(text.size()) > kMaxConfigBytes)
    throw ConfigError("config " + name + ": " + std::to_string(text.size()) + " bytes; accepted at most " +
                      std::to_string(kMaxConfigBytes) + " (1 MiB)");
  YAML::Node root = parse(text, name);
  if (!root.IsMap()) throw ConfigError("config " + name + ": the top level must be a mapping of keys");
  return ConfigNode(root, "", name);
}

std::string ConfigNode::where(const std::string& key) const {
  return "config " + file_ + ": key '" + join(path_, key) + "'";
}

void ConfigNode::fail(const std::string& key, const std::string& what) const {
  throw ConfigError(where(key) + ": " + what);
}

void ConfigNode::mark(const std::string& key) const { used_->insert(join(path_, key)); }

bool ConfigNode::has(const std::string& key) const { return node_.IsMap() && node_[key].IsDefined(); }

YAML::Node ConfigNode::get(const std::string& key) const {
  if (!has(key)) fail(key, "missing (required)");
  mark(key);
  return node_[key];
}

ConfigNode ConfigNode::child(const std::string& key) const {
  YAML::Node n = get(key);
  if (!n.IsMap()) fail(key, "must be a mapping of keys");
  ConfigNode c(n, join(path_, key), file_);
  c.used_ = used_;
  c.children_ = children_;
  c.origin_ = origin_;
  c.unit_slip_checks_ = unit_slip_checks_;
  children_->push_back(c.path_);
  return c;
}

ConfigNode ConfigNode::child_or_empty(const std::string& key) const {
  if (has(key)) return child(key);
  ConfigNode c(YAML::Node(YAML::NodeType::Map), join(path_, key), file_);
  c.used_ = used_;
  c.children_ = children_;
  c.origin_ = origin_;
  c.unit_slip_checks_ = unit_slip_checks_;
  return c;
}

double ConfigNode::number(const std::string& key, double lo, double hi, const std::string& unit,
                          double scale) const {
  YAML::Node n = get(key);
  double v = 0;
  try {
    if (!n.IsScalar()) throw YAML::Exception(YAML::Mark::null_mark(), "not a scalar");
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    fail(key, "must be a number in " + range_text(lo, hi, unit));
  }
  if (!std::isfinite(v) || v < lo || v > hi) {
    std::ostringstream s;
    s << "value " << v << " is out of range; accepted " << range_text(lo, hi, unit);
    fail(key, s.str());
  }
  return v * scale;
}

double ConfigNode::number_or(const std::string& key, double fallback, double lo, double hi,
                             const std::string& unit, double scale) const {
  return has(key) ? number(key, lo, hi, unit, scale) : fallback * scale;
}

int ConfigNode::integer(const std::string& key, long lo, long hi) const {
  YAML::Node n = get(key);
  long v = 0;
  try {
    v = n.as<long>();
  } catch (const YAML::Exception&) {
    fail(key, "must be an integer in " + range_text(lo, hi, ""));
  }
  if (v < lo || v > hi) {
    fail(key, "value " + std::to_string(v) + " is out of range; accepted " + range_text(lo, hi, ""));
  }
  return static_cast<int>(v);
}

int ConfigNode::integer_or(const std::string& key, int fallback, long lo, long hi) const {
  return has(key) ? integer(key, lo, hi) : fallback;
}

bool ConfigNode::boolean(const std::string& key) const {
  YAML::Node n = get(key);
  try {
    return n.as<bool>();
  } catch (const YAML::Exception&) {
    fail(key, "must be true or false");
  }
}

bool ConfigNode::boolean_or(const std::string& key, bool fallback) const {
  return has(key) ? boolean(key) : fallback;
}

std::string ConfigNode::text(const std::string& key) const {
  YAML::Node n = get(key);
  if (!n.IsScalar()) fail(key, "must be a string");
  return n.as<std::string>();
}

std::string ConfigNode::choice(const std::string& key, const std::vector<std::string>& accepted) const {
  std::string v = text(key);
  for (const auto& a : accepted)
    if (a == v) return v;
  std::string list;
  for (const auto& a : accepted) list += (list.empty() ? "" : ", ") + a;
  fail(key, "value '" + v + "' is not accepted; accepted: " + list);
}

std::string ConfigNode::choice_or(const std::string& key, const std::string& fallback,
                                  const std::vector<std::string>& accepted) const {
  return has(key) ? choice(key, accepted) : fallback;
}

std::vector<double> ConfigNode::numbers(const std::string& key, double lo, double hi,
                                        const std::string& unit, double scale,
                                        int exact_length) const {
  YAML::Node n = get(key);
  if (!n.IsSequence()) fail(key, "must be a list of numbers in " + range_text(lo, hi, unit));
  if (exact_length >= 0 && static_cast<int>(n.size()) != exact_length) {
    fail(key, "must have exactly " + std::to_string(exact_length) + " numbers, has " +
                  std::to_string(n.size()));
  }
  std::vector<double> out;
  for (std::size_t i = 0; i < n.size(); ++i) {
    double v = 0;
    try {
      v = n[i].as<double>();
    } catch (const YAML::Exception&) {
      fail(key, "element " + std::to_string(i) + " is not a number");
    }
    if (!std::isfinite(v) || v < lo || v > hi) {
      std::ostringstream s;
      s << "element " << i << " value " << v << " is out of range; accepted " << range_text(lo, hi, unit);
      fail(key, s.str());
    }
    out.push_back(v * scale);
  }
  return out;
}

Eigen::Vector3d ConfigNode::vector3(const std::string& key, double lo, double hi, const std::string& unit,
                                    double scale) const {
  auto v = numbers(key, lo, hi, unit, scale, 3);
  return {v[0], v[1], v[2]};
}

Eigen::Vector3d ConfigNode::vector3_or(const std::string& key, const Eigen::Vector3d& fallback, double lo,
                                       double hi, const std::string& unit, double scale) const {
  return has(key) ? vector3(key, lo, hi, unit, scale) : fallback;
}

void ConfigNode::finish() const {
  std::vector<std::string> unknown;
  // Walk this mapping and every mapping beneath it that was consumed as a child.
  std::vector<std::pair<YAML::Node, std::string>> todo{{node_, path_}};
  while (!todo.empty()) {
    auto [n, p] = todo.back();
    todo.pop_back();
    if (!n.IsMap()) continue;
    for (const auto& kv : n) {
      std::string full = join(p, kv.first.as<std::string>());
      if (!used_->count(full)) {
        unknown.push_back(full);
      } else if (kv.second.IsMap()) {
        for (const auto& c : *children_)
          if (c == full) todo.push_back({kv.second, full});
      }
    }
  }
  if (!unknown.empty()) {
    std::string list;
    for (const auto& u : unknown) list += (list.empty() ? "" : ", ") + u;
    throw ConfigError("config " + file_ + ": unknown key(s): " + list +
                      " (check the spelling against launch_free_configs/ and README.md)");
  }
}

}  // namespace core
