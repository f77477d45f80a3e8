#pragma once
// Unit-slip tests (issue 22) shared by the coupling and rocks tests: a shipped config's text with one value written
// in the wrong unit, and the check that each refusal names its key and the likely slip.
#include <gtest/gtest.h>

#include <cstddef>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace test_slips {

struct Slip {
  const char* from;  // the config's text
  const char* to;    // the same value in the wrong unit
  const char* key;   // the key path the message must name
  const char* hint;  // the likely slip it must name
};

// The text of a file under the source tree (e.g. "launch_free_configs/bpm_calibrated.yaml").
inline std::string source_text(const std::string& relative) {
  std::ifstream in(std::string(CRUSHER_SOURCE_DIR) + "/" + relative);
  if (!in) throw std::logic_error("no file " + relative);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// `text` (of `name`) with its first `from` replaced by `to`.
inline std::string replaced(std::string text, const std::string& from, const std::string& to, const std::string& name) {
  const auto at = text.find(from);
  if (at == std::string::npos) throw std::logic_error(name + " has no '" + from + "'");
  return text.replace(at, from.size(), to);
}

// Each slip's error, error_with(from, to) ("" when it loads), names its key and its hint.
template <std::size_t N, class ErrorWith>
void expect_slips_named(const Slip (&slips)[N], ErrorWith error_with) {
  for (const Slip& s : slips) {
    const std::string e = error_with(s.from, s.to);
    EXPECT_NE(e.find(s.key), std::string::npos) << s.to << ": " << e;
    EXPECT_NE(e.find(s.hint), std::string::npos) << s.to << ": " << e;
  }
}

}  // namespace test_slips
