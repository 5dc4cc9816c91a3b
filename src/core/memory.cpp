#include "core/memory.hpp"

#include <malloc.h>

#include <mutex>

namespace rbpart {

void keep_freed_memory() {
  static std::once_flag once;
  std::call_once(once, [] {
    // Blocks up to glibc's largest mmap threshold (32 MiB on 64-bit) come from the heap; the heap
    // is trimmed only when 1 GiB at its top is free.
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
  });
}

}  // namespace rbpart
