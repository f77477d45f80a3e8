#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <unistd.h>

#include "core/run_program.hpp"

namespace fs = std::filesystem;

// A file name that a shell would split and run: it must reach the program as one argument, and nothing runs.
TEST(RunProgram, HostileNameIsOneArgumentAndNeverACommand) {
  const fs::path dir = fs::temp_directory_path() / ("run_program_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string name = (dir / "a b';touch PWNED;'$(touch PWNED2)\"").string();
  EXPECT_EQ(core::run_program({"touch", name}), 0);
  EXPECT_TRUE(fs::exists(name));
  EXPECT_FALSE(fs::exists("PWNED") || fs::exists("PWNED2"));  // a shell would have run them in this folder
  fs::remove_all(dir);
}

TEST(RunProgram, ReportsExitStatusSignalAndMissingProgram) {
  EXPECT_EQ(core::run_program({"/bin/sh", "-c", "exit 3"}), 3);
  EXPECT_EQ(core::run_program({"/bin/sh", "-c", "kill -TERM $$"}), 128 + 15);
  EXPECT_EQ(core::run_program({"/nonexistent/program"}), -1);
  EXPECT_EQ(core::run_program({}), -1);
}

TEST(RunProgram, FindsTheToolsScripts) {
  EXPECT_FALSE(core::tool_script("plot_diagnosis.py").empty());
  EXPECT_TRUE(core::tool_script("no_such_script.py").empty());
}
