#include "core/heap_policy.hpp"

#include <malloc.h>

namespace core {

bool keep_freed_heap() {
  const bool no_mmap = mallopt(M_MMAP_MAX, 0) == 1;            // large blocks from the heap, not fresh mappings
  const bool keep = mallopt(M_TRIM_THRESHOLD, 1 << 30) == 1;  // and what is freed stays for the next ones
  return no_mmap && keep;
}

}  // namespace core
