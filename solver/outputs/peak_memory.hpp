#pragma once
// Peak resident memory of this process, as pd-solve reports it (summary.json,
// the "done" line). A switching scene resets it between its two parts, so
// each part reports its own peak.
#include <cstdint>

namespace pd::solver {

// The largest resident memory since the process started or the last reset [bytes].
std::uint64_t peak_memory_bytes();

// Starts a new peak where the system allows it (Linux: /proc/self/clear_refs);
// elsewhere the peak stays that of the whole process.
void reset_peak_memory();

}  // namespace pd::solver
