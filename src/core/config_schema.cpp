#include "core/config_schema.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace core {

std::string format_number(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.12g", v);
  return b;
}

void set_path(YAML::Node& node, const std::string& name, const YAML::Node& v) {
  const auto dot = name.find('.');
  if (dot == std::string::npos) {
    node[name] = v;
    return;
  }
  const std::string head = name.substr(0, dot);
  YAML::Node child = node[head];
  if (!child.IsMap()) child = YAML::Node(YAML::NodeType::Map);
  set_path(child, name.substr(dot + 1), v);
  node[head] = child;
}

namespace {
bool has_band(const KeyInfo& k) {
  return k.plausible_hi > 0 && (k.kind == KeyKind::Number || k.kind == KeyKind::Numbers);
}

// The value of a number key, or each element of a list (YAML::Exception when one is not a number).
std::vector<double> numbers_at(const ConfigNode& node, const std::string& key) {
  const YAML::Node y = node.raw()[key];
  std::vector<double> v;
  if (y.IsSequence())
    for (const auto& e : y) v.push_back(e.as<double>());
  else
    v.push_back(y.as<double>());
  return v;
}

// "; 1000x that (..) would fit: HINT" when 1000x x fits, the same for 1/1000 of it, else "". need_hint: only where
// the key names the slip (a non-empty hint).
template <class Fits>
std::string slip_hint(double x, const KeyInfo& k, Fits fits, bool need_hint) {
  std::ostringstream s;
  if (fits(x * 1e3) && (!need_hint || !k.slip_small.empty()))
    s << "; 1000x that (" << format_number(x * 1e3) << ") would fit: " << k.slip_small;
  else if (fits(x * 1e-3) && (!need_hint || !k.slip_large.empty()))
    s << "; 1/1000 of it (" << format_number(x * 1e-3) << ") would fit: " << k.slip_large;
  return s.str();
}
}  // namespace

void check_plausible(const ConfigNode& node, const std::string& key, const KeyInfo& k) {
  if (!node.unit_slip_checks() || !has_band(k)) return;
  const std::vector<double> v = numbers_at(node, key);
  const double lo = k.plausible_lo, hi = k.plausible_hi;
  auto inside = [&](double a) { return std::abs(a) >= lo && std::abs(a) <= hi; };
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (v[i] == 0 || inside(v[i])) continue;
    std::ostringstream s;
    s << (v.size() > 1 ? "element " + std::to_string(i) + " value " : "value ") << format_number(v[i])
      << " is implausible: magnitudes of " << format_number(lo) << " to " << format_number(hi) << " " << k.unit
      << " are expected (or 0)" << slip_hint(v[i], k, inside, false) << " (refused as a likely unit slip)";
    node.fail(key, s.str());
  }
}

void rethrow_naming_slip(const ConfigNode& node, const std::string& key, const KeyInfo& k) {
  if (!has_band(k)) throw;
  std::vector<double> v;
  bool numbers = true;
  try {
    v = numbers_at(node, key);
  } catch (const YAML::Exception&) {
    numbers = false;
  }
  if (!numbers) throw;  // refused as no number: as it was (the ConfigError being handled)
  auto fits = [&](double x) {
    return std::abs(x) >= k.plausible_lo && std::abs(x) <= k.plausible_hi && x >= k.lo && x <= k.hi;
  };
  std::string hint;
  for (double x : v)  // the first value out of range is the one refused
    if (!(std::isfinite(x) && x >= k.lo && x <= k.hi)) {
      hint = slip_hint(x, k, fits, true);
      break;
    }
  if (hint.empty()) throw;
  try {
    throw;
  } catch (const ConfigError& e) {
    throw ConfigError(e.what() + hint + " (refused as a likely unit slip)");
  }
}

namespace {
std::string range_of(const KeyInfo& k) {
  switch (k.kind) {
    case KeyKind::Boolean: return "true|false";
    case KeyKind::Text: return "text";
    case KeyKind::Choice: {
      std::string s;
      for (const auto& c : k.choices) s += (s.empty() ? "" : "|") + c;
      return s;
    }
    default: break;
  }
  std::string s = "[" + format_number(k.lo) + ", " + format_number(k.hi) + "]";
  if (k.kind == KeyKind::Numbers) s = (k.length > 0 ? std::to_string(k.length) + " x " : "list ") + s;
  return s;
}
std::string pad(const std::string& s, std::size_t w) { return s.size() >= w ? s + " " : s + std::string(w - s.size(), ' '); }
}  // namespace

std::string key_reference(const std::string& section, const std::vector<KeyInfo>& keys) {
  std::ostringstream o;
  for (const auto& k : keys) {
    o << pad(section + "." + k.name, 44) << pad(k.unit.empty() ? "-" : k.unit, 10) << pad(range_of(k), 24)
      << pad(k.default_text, 14) << k.meaning << "\n";
  }
  return o.str();
}

}  // namespace core
