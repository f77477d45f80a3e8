#pragma once
// One description per config key: name, kind, unit, SI scale, range, default and meaning, bound to the struct
// member it fills. The description drives loading and validation (through ConfigNode, so messages name the key
// path, the accepted range and the unit), writing back (write: a YAML mapping, load -> write -> load is the
// identity) and the key reference (`crusher config --keys`). The default is the struct's own member initialiser;
// a default outside the key's range means "not set" (printed as "unset", not written back). Cross-key checks stay
// code: a key's `then` hook runs after it is read, with the node, to fail by name.
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <functional>
#include <map>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/config.hpp"

namespace core {

enum class KeyKind { Number, Integer, Boolean, Choice, Text, Numbers };

// The slip hint of a mm key's plausible band (Schema::plausible): a size typed in metres.
inline constexpr const char* kMetresForMm = "metres given for mm?";

struct KeyInfo {
  std::string name;                  // path inside the section: "pressure.modulus_MPa"
  KeyKind kind = KeyKind::Number;
  std::string unit;                  // the file's unit ("" dimensionless)
  double scale = 1.0;                // file unit -> SI
  double lo = 0, hi = 0;             // accepted range, in the file's unit (numbers, lists, integers)
  bool required = false;
  std::vector<std::string> choices;  // Choice
  int length = -1;                   // Numbers: exact length, -1 free
  std::string meaning;
  std::string default_text;          // the default as the reference prints it ("required", "unset", a value)
  bool written = true;               // false: read only (e.g. a file whose values are written as keys)
  std::string applies_to;            // non-empty: the key exists only then (e.g. "law: hysteretic only ...")
  // Plausibility (numbers, lists): a value inside [lo, hi] whose magnitude lies outside [plausible_lo,
  // plausible_hi] (0 is accepted) is refused as a likely unit slip; slip_small / slip_large name the slip of a value
  // ~1000x below / above the band ("metres given for mm?"). plausible_hi 0: no band.
  double plausible_lo = 0, plausible_hi = 0;
  std::string slip_small, slip_large;
};

// Refuses (ConfigError through `node`) a value of `key` outside the plausible band of `k`, naming the likely slip.
void check_plausible(const ConfigNode& node, const std::string& key, const KeyInfo& k);
// Called in a handler of the ConfigError that refused `key`'s value as out of its range: rethrows it, with the likely
// slip named when 1000x (or 1/1000 of) an out-of-range value lies in the plausible band of `k` (metres in a mm key
// whose range starts above 1/1000 of the band: `sieves_mm: [0.001, ...]`, `rock_density_kg_m3: 2.65`).
[[noreturn]] void rethrow_naming_slip(const ConfigNode& node, const std::string& key, const KeyInfo& k);

// A copy of `over` laid over a copy of `base`: mappings merge key by key (recursively), anything else replaces
// (how a config's keys are laid over its `base:` file; config.cpp).
YAML::Node merged(const YAML::Node& base, const YAML::Node& over);
// Formatting shared by writing and the reference: 12 significant digits.
std::string format_number(double v);
// The reference lines of `keys` under `section`: name, unit, range, default, meaning (one line each).
std::string key_reference(const std::string& section, const std::vector<KeyInfo>& keys);
// `node` with a mapping at the dotted path `name` (created as needed) given the value `v`.
void set_path(YAML::Node& node, const std::string& name, const YAML::Node& v);

template <class T>
class Schema {
 public:
  using Hook = std::function<void(const ConfigNode& node, const std::string& key, T& out)>;
  // A value in SI (lists: each element), got from and set into T; integers as long.
  struct Entry {
    KeyInfo info;
    std::function<double(const T&)> get_num;
    std::function<void(T&, double)> set_num;
    std::function<long(const T&)> get_int;
    std::function<void(T&, long)> set_int;
    std::function<bool(const T&)> get_flag;
    std::function<void(T&, bool)> set_flag;
    std::function<std::string(const T&)> get_str;
    std::function<void(T&, const std::string&)> set_str;
    std::function<std::vector<double>(const T&)> get_list;
    std::function<void(T&, const std::vector<double>&)> set_list;
    Hook then;
    std::function<double(const T&)> scale_of;  // a scale that depends on other keys (read after them)
    std::function<bool(const T&)> applies;      // the key exists only when this holds (else refused, not written)
    std::string applies_text;                   // what the refusal says
  };
  template <class V>
  using Ref = std::function<V&(T&)>;

  Schema& number(const std::string& name, const std::string& unit, double scale, double lo, double hi,
                 Ref<double> ref, const std::string& meaning, bool required = false, Hook then = {}) {
    Entry e = make(name, KeyKind::Number, unit, scale, lo, hi, meaning, required, then);
    e.get_num = [ref](const T& t) { return ref(const_cast<T&>(t)); };
    e.set_num = [ref](T& t, double v) { ref(t) = v; };
    return add(std::move(e));
  }
  template <class F>  // ref: I&(T&) for any integer member type I (int, unsigned long long, ...)
  Schema& integer(const std::string& name, long lo, long hi, F ref, const std::string& meaning,
                  bool required = false) {
    using I = std::remove_reference_t<decltype(ref(std::declval<T&>()))>;
    Entry e = make(name, KeyKind::Integer, "", 1.0, lo, hi, meaning, required, {});
    e.get_int = [ref](const T& t) { return static_cast<long>(ref(const_cast<T&>(t))); };
    e.set_int = [ref](T& t, long v) { ref(t) = static_cast<I>(v); };
    return add(std::move(e));
  }
  Schema& boolean(const std::string& name, Ref<bool> ref, const std::string& meaning, bool required = false) {
    Entry e = make(name, KeyKind::Boolean, "", 1.0, 0, 1, meaning, required, {});
    e.get_flag = [ref](const T& t) { return ref(const_cast<T&>(t)); };
    e.set_flag = [ref](T& t, bool v) { ref(t) = v; };
    return add(std::move(e));
  }
  // A choice stored as anything (an enum, a flag): get gives the accepted word, set takes it.
  Schema& choice(const std::string& name, std::vector<std::string> choices, std::function<std::string(const T&)> get,
                 std::function<void(T&, const std::string&)> set, const std::string& meaning, bool required = false) {
    Entry e = make(name, KeyKind::Choice, "", 1.0, 0, 0, meaning, required, {});
    e.info.choices = std::move(choices);
    e.get_str = std::move(get);
    e.set_str = std::move(set);
    return add(std::move(e));
  }
  Schema& choice(const std::string& name, std::vector<std::string> choices, Ref<std::string> ref,
                 const std::string& meaning, bool required = false) {
    return choice(
        name, std::move(choices), [ref](const T& t) { return ref(const_cast<T&>(t)); },
        [ref](T& t, const std::string& v) { ref(t) = v; }, meaning, required);
  }
  Schema& text(const std::string& name, Ref<std::string> ref, const std::string& meaning, bool required = false,
               Hook then = {}) {
    Entry e = make(name, KeyKind::Text, "", 1.0, 0, 0, meaning, required, then);
    e.get_str = [ref](const T& t) { return ref(const_cast<T&>(t)); };
    e.set_str = [ref](T& t, const std::string& v) { ref(t) = v; };
    return add(std::move(e));
  }
  Schema& numbers(const std::string& name, const std::string& unit, double scale, double lo, double hi,
                  Ref<std::vector<double>> ref, const std::string& meaning, bool required = false, Hook then = {}) {
    Entry e = make(name, KeyKind::Numbers, unit, scale, lo, hi, meaning, required, then);
    e.get_list = [ref](const T& t) { return ref(const_cast<T&>(t)); };
    e.set_list = [ref](T& t, const std::vector<double>& v) { ref(t) = v; };
    return add(std::move(e));
  }
  Schema& vector3(const std::string& name, const std::string& unit, double scale, double lo, double hi,
                  Ref<Eigen::Vector3d> ref, const std::string& meaning, bool required = false) {
    Entry e = make(name, KeyKind::Numbers, unit, scale, lo, hi, meaning, required, {});
    e.info.length = 3;
    e.get_list = [ref](const T& t) {
      const Eigen::Vector3d& v = ref(const_cast<T&>(t));
      return std::vector<double>{v[0], v[1], v[2]};
    };
    e.set_list = [ref](T& t, const std::vector<double>& v) { ref(t) = Eigen::Vector3d(v[0], v[1], v[2]); };
    return add(std::move(e));
  }
  // A number whose SI scale depends on other keys (e.g. a power-law stiffness: 1000^exponent); read after them.
  Schema& number_scaled(const std::string& name, const std::string& unit, std::function<double(const T&)> scale_of,
                        double lo, double hi, Ref<double> ref, const std::string& meaning, bool required = false) {
    Entry e = make(name, KeyKind::Number, unit, 1.0, lo, hi, meaning, required, {});
    e.get_num = [ref](const T& t) { return ref(const_cast<T&>(t)); };
    e.set_num = [ref](T& t, double v) { ref(t) = v; };
    e.scale_of = std::move(scale_of);
    return add(std::move(e));
  }
  // The last key added exists only when `pred` holds on what was read before it (`when`, for the reference); given
  // otherwise, it is refused with "applies to `what`". Required, it is required only then.
  Schema& applies_if(std::function<bool(const T&)> pred, const std::string& what, const std::string& when) {
    auto& e = entries_.back();
    e.applies = std::move(pred);
    e.applies_text = what;
    e.info.applies_to = what;
    if (e.info.required) e.info.default_text = "required if " + when;
    return *this;
  }
  // The last key added (a number or a list): magnitudes outside [lo, hi] but inside its range are refused as a
  // likely unit slip (0 is accepted); `small` / `large` name the slip of a value ~1000x below / above the band.
  Schema& plausible(double lo, double hi, const std::string& small, const std::string& large) {
    auto& i = entries_.back().info;
    i.plausible_lo = lo;
    i.plausible_hi = hi;
    i.slip_small = small;
    i.slip_large = large;
    return *this;
  }
  // The mapping at `path` is written in flow style ({a: 1, b: 2}).
  Schema& flow_style(const std::string& path) {
    flow_maps_.push_back(path);
    return *this;
  }
  // The last key added is read but not written back.
  Schema& load_only() {
    entries_.back().info.written = false;
    return *this;
  }
  // Every key of `sub` under `prefix`, filling the member `part` of T.
  template <class S>
  Schema& include(const std::string& prefix, const Schema<S>& sub, std::function<S&(T&)> part) {
    auto in = [part](const T& t) -> const S& { return part(const_cast<T&>(t)); };
    for (const auto& s : sub.entries()) {
      Entry e;
      e.info = s.info;
      e.info.name = prefix + "." + s.info.name;
      if (s.get_num) e.get_num = [f = s.get_num, in](const T& t) { return f(in(t)); };
      if (s.set_num) e.set_num = [f = s.set_num, part](T& t, double v) { f(part(t), v); };
      if (s.get_int) e.get_int = [f = s.get_int, in](const T& t) { return f(in(t)); };
      if (s.set_int) e.set_int = [f = s.set_int, part](T& t, long v) { f(part(t), v); };
      if (s.get_flag) e.get_flag = [f = s.get_flag, in](const T& t) { return f(in(t)); };
      if (s.set_flag) e.set_flag = [f = s.set_flag, part](T& t, bool v) { f(part(t), v); };
      if (s.get_str) e.get_str = [f = s.get_str, in](const T& t) { return f(in(t)); };
      if (s.set_str) e.set_str = [f = s.set_str, part](T& t, const std::string& v) { f(part(t), v); };
      if (s.get_list) e.get_list = [f = s.get_list, in](const T& t) { return f(in(t)); };
      if (s.set_list) e.set_list = [f = s.set_list, part](T& t, const std::vector<double>& v) { f(part(t), v); };
      if (s.then)
        e.then = [f = s.then, part](const ConfigNode& n, const std::string& k, T& t) { f(n, k, part(t)); };
      if (s.scale_of) e.scale_of = [f = s.scale_of, in](const T& t) { return f(in(t)); };
      if (s.applies) e.applies = [f = s.applies, in](const T& t) { return f(in(t)); };
      e.applies_text = s.applies_text;
      entries_.push_back(std::move(e));
    }
    return *this;
  }

  const std::vector<Entry>& entries() const { return entries_; }
  std::vector<KeyInfo> keys() const {
    std::vector<KeyInfo> out;
    for (const auto& e : entries_) out.push_back(e.info);
    return out;
  }

  // Reads every key given in `section` into `out` (keys not given keep out's values; a required one missing
  // fails by name). The caller runs finish() on the root for unknown keys.
  // A T with its member defaults, the section's keys read into it.
  T read(const ConfigNode& section) const {
    T out;
    read(section, out);
    return out;
  }
  void read(const ConfigNode& section, T& out) const {
    std::map<std::string, ConfigNode> maps{{"", section}};
    for (int pass = 0; pass < 2; ++pass)  // keys with a scale that depends on others last
      for (const auto& e : entries_)
        if (static_cast<bool>(e.scale_of) == (pass == 1)) read_one(maps, e, out);
  }

  // The section as a YAML mapping in the file's units; values that are not set (outside their range) are left out.
  YAML::Node write(const T& v) const {
    YAML::Node root(YAML::NodeType::Map);
    for (const auto& e : entries_) {
      YAML::Node y;
      if (!e.info.written || (e.applies && !e.applies(v)) || !value_node(e, v, y)) continue;
      set_path(root, e.info.name, y);
    }
    for (const auto& path : flow_maps_) {
      YAML::Node n = root;
      std::string rest = path;
      for (auto dot = rest.find('.'); n && dot != std::string::npos; dot = rest.find('.')) {
        n.reset(n[rest.substr(0, dot)]);
        rest = rest.substr(dot + 1);
      }
      if (n && n[rest]) n[rest].SetStyle(YAML::EmitterStyle::Flow);
    }
    return root;
  }

  // The value of `e` in `v` as a YAML node; false when it is not set (a default outside the key's range).
  static bool value_node(const Entry& e, const T& v, YAML::Node& y) {
    const auto& i = e.info;
    switch (i.kind) {
      case KeyKind::Number: {
        const double x = e.get_num(v) / (e.scale_of ? e.scale_of(v) : i.scale);
        if (!(x >= i.lo && x <= i.hi)) return false;
        y = format_number(x);
        return true;
      }
      case KeyKind::Integer: y = e.get_int(v); return true;
      case KeyKind::Boolean: y = e.get_flag(v) ? "true" : "false"; return true;
      case KeyKind::Choice: y = e.get_str(v); return true;
      case KeyKind::Text:
        if (e.get_str(v).empty()) return false;
        y = e.get_str(v);
        return true;
      case KeyKind::Numbers:
        y = YAML::Node(YAML::NodeType::Sequence);
        y.SetStyle(YAML::EmitterStyle::Flow);
        for (double x : e.get_list(v)) y.push_back(format_number(x / i.scale));
        return true;
    }
    return false;
  }

 private:
  void read_one(std::map<std::string, ConfigNode>& maps, const Entry& e, T& out) const {
    const auto dot = e.info.name.find_last_of('.');
    const std::string parent = dot == std::string::npos ? "" : e.info.name.substr(0, dot);
    const std::string key = e.info.name.substr(dot == std::string::npos ? 0 : dot + 1);
    const bool applies = !e.applies || e.applies(out);
    const ConfigNode* n = mapping(maps, parent, e.info.required && applies);
    if (!n) return;
    if (!applies) {
      if (n->has(key)) n->fail(key, "applies to " + e.applies_text);
      return;
    }
    if (!n->has(key)) {
      if (e.info.required) n->text(key);  // fails: "missing (required)"
      return;
    }
    const auto& i = e.info;
    try {
      switch (i.kind) {
        case KeyKind::Number:
          e.set_num(out, n->number(key, i.lo, i.hi, i.unit, e.scale_of ? e.scale_of(out) : i.scale));
          break;
        case KeyKind::Integer: e.set_int(out, n->integer(key, static_cast<long>(i.lo), static_cast<long>(i.hi))); break;
        case KeyKind::Boolean: e.set_flag(out, n->boolean(key)); break;
        case KeyKind::Choice: e.set_str(out, n->choice(key, i.choices)); break;
        case KeyKind::Text: e.set_str(out, n->text(key)); break;
        case KeyKind::Numbers: e.set_list(out, n->numbers(key, i.lo, i.hi, i.unit, i.scale, i.length)); break;
      }
    } catch (const ConfigError&) {
      rethrow_naming_slip(*n, key, i);
    }
    check_plausible(*n, key, i);
    if (e.then) e.then(*n, key, out);
  }
  Entry make(const std::string& name, KeyKind kind, const std::string& unit, double scale, double lo, double hi,
             const std::string& meaning, bool required, Hook then) const {
    Entry e;
    e.info.name = name;
    e.info.kind = kind;
    e.info.unit = unit;
    e.info.scale = scale;
    e.info.lo = lo;
    e.info.hi = hi;
    e.info.required = required;
    e.info.meaning = meaning;
    e.then = std::move(then);
    return e;
  }
  Schema& add(Entry e) {  // the default printed from a default-constructed T
    if (e.info.required) {
      e.info.default_text = "required";
    } else {
      const T d{};
      YAML::Node y;
      if (!value_node(e, d, y)) {
        e.info.default_text = "unset";
      } else {
        YAML::Emitter out;
        out << YAML::Flow << y;
        e.info.default_text = out.c_str();
      }
    }
    entries_.push_back(std::move(e));
    return *this;
  }
  // The mapping at dotted `path` below maps[""], taken once per read; null when optional and absent.
  static const ConfigNode* mapping(std::map<std::string, ConfigNode>& maps, const std::string& path, bool required) {
    auto it = maps.find(path);
    if (it != maps.end()) return &it->second;
    const auto dot = path.find_last_of('.');
    const std::string parent = dot == std::string::npos ? "" : path.substr(0, dot);
    const std::string key = path.substr(dot == std::string::npos ? 0 : dot + 1);
    const ConfigNode* p = mapping(maps, parent, required);
    if (!p || (!required && !p->has(key))) return nullptr;
    return &maps.emplace(path, p->child(key)).first->second;
  }

  std::vector<Entry> entries_;
  std::vector<std::string> flow_maps_;
};

}  // namespace core
