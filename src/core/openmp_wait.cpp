#include "core/openmp_wait.hpp"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <unistd.h>

namespace core {

void prefer_passive_openmp_wait(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY")) return;
  ::setenv("OMP_WAIT_POLICY", "passive", 1);
  ::setenv("CRUSHER_OMP_WAIT_DEFAULT", "passive", 1);
  ::execv("/proc/self/exe", argv);
  std::fprintf(stderr, "%s: cannot re-execute itself with OMP_WAIT_POLICY=passive (%s); OpenMP threads spin while "
                       "they wait\n", argv[0], std::strerror(errno));
  ::unsetenv("OMP_WAIT_POLICY");
}

std::string openmp_wait_policy() {
  const char* p = std::getenv("OMP_WAIT_POLICY");
  if (!p) return "unset (libgomp's default: spin a while, then sleep)";
  const char* d = std::getenv("CRUSHER_OMP_WAIT_DEFAULT");
  if (d && std::strcmp(d, p) == 0)  // set by us (or the wrapper), not changed since
    return std::string(p) + " (the default; OMP_WAIT_POLICY=active to spin)";
  return std::string(p) + " (OMP_WAIT_POLICY)";
}

}  // namespace core
