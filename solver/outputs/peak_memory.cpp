#include "peak_memory.hpp"

#include <sys/resource.h>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <fstream>
#include <limits>
#include <string>

namespace pd::solver {

std::uint64_t peak_memory_bytes() {
  // VmHWM follows a reset; getrusage's maximum does not (it is the fallback).
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmHWM:", 0) == 0) return std::stoull(line.substr(6)) * 1024;  // "VmHWM:  N kB"
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<std::uint64_t>(usage.ru_maxrss) * 1024;  // Linux reports kB
}

void return_large_blocks_when_freed() {
#if defined(__GLIBC__)
  // A fixed threshold also turns off glibc's dynamic one (mallopt(3)).
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
#endif
}

void keep_freed_blocks_for_reuse() {
#if defined(__GLIBC__)
  // No block gets pages of its own (mmap), whatever its size, and the heap's
  // free top is never given back (mallopt(3)). Blocks mapped before stay
  // mapped until freed.
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max());
#endif
}

void reset_peak_memory() {
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";  // 5: reset the peak resident set size (proc(5))
}

}  // namespace pd::solver
