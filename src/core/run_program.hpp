#pragma once
// Helper programs (the plot scripts) started with an argument vector, never through a shell: a file name with
// quotes, spaces, `;` or `$()` reaches the program as one argument and is never run as a command.
#include <string>
#include <vector>

namespace core {

// Runs argv[0] (a path, or a name looked up on PATH) with the arguments argv[1..] and waits for it.
// Returns its exit status, 128 + the signal that ended it, or -1 when it could not be started.
int run_program(const std::vector<std::string>& argv);

// The path of a file given relative to the repository (from the working folder, else from the source tree), "" when
// neither exists: e.g. launch_free_configs/bpm_calibrated.yaml.
std::string source_file(const std::string& rel);
// The path of src/tools/NAME (source_file).
std::string tool_script(const std::string& name);

// Runs `/usr/bin/python3 src/tools/SCRIPT DIR`; on failure warns on stderr as `TOOL: ...` and returns false.
bool run_plot_script(const std::string& tool, const std::string& script, const std::string& dir);

}  // namespace core
