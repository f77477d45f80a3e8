// core::keep_freed_heap (heap_policy.hpp): a large buffer freed and allocated again is not faulted in again. Without
// the policy glibc maps a 64 MiB block afresh each time (16,384 minor page faults on 4 KiB pages for the second use).
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cstdio>
#include <cstdlib>

#include "core/heap_policy.hpp"

namespace {

long minor_faults() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_minflt;
}

// Allocates n bytes, writes every page, frees them; returns the page faults it took.
long use_buffer(std::size_t n) {
  const long f0 = minor_faults();
  volatile char* p = static_cast<volatile char*>(std::malloc(n));
  if (!p) return -1;
  for (std::size_t i = 0; i < n; i += 4096) p[i] = 1;
  std::free(const_cast<char*>(p));
  return minor_faults() - f0;
}

TEST(HeapPolicy, AFreedLargeBufferIsNotFaultedInAgain) {
  ASSERT_TRUE(core::keep_freed_heap());
  const std::size_t n = std::size_t(64) << 20;
  const long first = use_buffer(n), second = use_buffer(n);
  ASSERT_GE(first, 0) << "malloc of 64 MiB failed";
  ASSERT_GE(second, 0) << "malloc of 64 MiB failed";
  std::printf("64 MiB buffer: %ld page faults at its first use, %ld at its second\n", first, second);
  EXPECT_LT(second, 1000);
}

}  // namespace
