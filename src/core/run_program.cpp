#include "core/run_program.hpp"

#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

extern char** environ;

namespace core {

int run_program(const std::vector<std::string>& argv) {
  if (argv.empty()) return -1;
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawnp(&pid, args[0], nullptr, nullptr, args.data(), environ) != 0) return -1;
  int st = 0;
  while (waitpid(pid, &st, 0) < 0)
    if (errno != EINTR) return -1;
  if (WIFEXITED(st)) return WEXITSTATUS(st);
  return WIFSIGNALED(st) ? 128 + WTERMSIG(st) : -1;
}

std::string source_file(const std::string& rel) {
  namespace fs = std::filesystem;
  for (const fs::path& p : {fs::path(rel), fs::path(__FILE__).parent_path().parent_path().parent_path() / rel})
    if (fs::exists(p)) return p.string();
  return "";
}

std::string tool_script(const std::string& name) { return source_file("src/tools/" + name); }

bool run_plot_script(const std::string& tool, const std::string& script, const std::string& dir) {
  const std::string path = tool_script(script);
  if (path.empty()) {
    std::fprintf(stderr, "%s: %s not found: no PNG plots written\n", tool.c_str(), script.c_str());
    return false;
  }
  const int rc = run_program({"/usr/bin/python3", path, dir});
  if (rc != 0) std::fprintf(stderr, "%s: plotting failed (%s exited %d); the results are written\n", tool.c_str(),
                            script.c_str(), rc);
  return rc == 0;
}

}  // namespace core
