#pragma once
// JSON text pieces shared by the diagnosis's writers: a string escaped, a number (null when not finite: JSON has no
// inf or nan).
#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

namespace analysis::json {

inline std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    if (c == '\n') { o += "\\n"; continue; }
    o += c;
  }
  return o;
}

inline std::string num(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream o;
  o << std::setprecision(8) << v;
  return o.str();
}

}  // namespace analysis::json
