#pragma once
// OpenMP threads that wait for work sleep instead of spinning, unless the user chose otherwise with
// OMP_WAIT_POLICY. On a shared machine a spinning team holds the cores another run needs (issue 22: two coupled
// runs at once on 2 cores took 20x longer each; with passive waiting, about twice as long). libgomp reads the
// variable once, when it is loaded (before main), so a program that must set it re-executes itself with it set.
#include <string>

namespace core {

// Call first thing in main(). With OMP_WAIT_POLICY unset: sets it to passive (and CRUSHER_OMP_WAIT_DEFAULT=passive,
// so the log can say whose choice it is) and re-executes the program (/proc/self/exe, same arguments, same process
// id); returns when the variable was already set or the re-execution failed (said on stderr: waiting stays active).
void prefer_passive_openmp_wait(char** argv);

// The policy in effect for the log: "passive (the default; OMP_WAIT_POLICY=active to spin)",
// "active (OMP_WAIT_POLICY)", or "unset (libgomp's default: spin a while, then sleep)".
std::string openmp_wait_policy();

}  // namespace core
