#include "core/config_schema.hpp"

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
