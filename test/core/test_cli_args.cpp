// Numbers given as text (command-line flags, ROS parameters) are checked in one place: the whole text a finite
// number in range, else a message naming the flag, the value and what is accepted (issue 22: `crusher run
// --duration -1|0|abc|nan` was ignored and 1e9 passed).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/cli_args.hpp"
#include "core/run_config.hpp"

namespace {
std::string number_error(const std::string& v, double lo = 0.001, double hi = 3600) {
  try {
    core::parse_number("--duration", v, lo, hi, "s");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(ParseNumber, AcceptsWholeNumbersInRange) {
  EXPECT_DOUBLE_EQ(core::parse_number("--x", "2.5", 0, 10), 2.5);
  EXPECT_DOUBLE_EQ(core::parse_number("--x", "1e-3", 1e-3, 10), 1e-3);
  EXPECT_DOUBLE_EQ(core::parse_number("--x", "10", 0, 10), 10);
  EXPECT_EQ(core::parse_integer("--n", "42", 1, 100), 42);
}

TEST(ParseNumber, RefusesNamingFlagValueAndRange) {
  for (const char* bad : {"-1", "0", "abc", "nan", "inf", "", "1e9", "5x"}) {
    const std::string m = number_error(bad);
    ASSERT_FALSE(m.empty()) << "'" << bad << "' was accepted";
    EXPECT_EQ(m.rfind("--duration ", 0), 0u) << m;
    EXPECT_NE(m.find(std::string(bad).empty() ? "''" : bad), std::string::npos) << m;
    EXPECT_NE(m.find("accepted a number in [0.001, 3600] s"), std::string::npos) << m;
  }
}

TEST(ParseNumber, IntegersRefuseFractionsTextAndOverflow) {
  for (const char* bad : {"1.5", "abc", "", "0", "101", "99999999999999999999999"}) {
    try {
      core::parse_integer("--steps", bad, 1, 100);
      ADD_FAILURE() << "'" << bad << "' was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("--steps"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("accepted a whole number in [1, 100]"), std::string::npos) << e.what();
    }
  }
}

// The nodes' ~duration (and `crusher run --duration`, through config_tool --keys) take run.duration_s's range.
TEST(ParseNumber, DurationOverrideTakesTheSchemaRange) {
  EXPECT_DOUBLE_EQ(core::checked_duration("parameter ~duration", "5"), 5.0);
  try {
    core::checked_duration("parameter ~duration", "1e9");
    ADD_FAILURE() << "1e9 s was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("parameter ~duration 1e9: accepted a number in [0.001, 3600] s (run.duration_s)"),
              std::string::npos) << e.what();
  }
}
