#pragma once
// Peak resident memory of this process, as pd-solve reports it (summary.json,
// the "done" line). A switching scene resets it between its two parts, so
// each part reports its own peak.
#include <cstdint>

namespace pd::solver {

// The largest resident memory since the process started or the last reset [bytes].
std::uint64_t peak_memory_bytes();

// Makes the process's peak memory that of its live arrays, not of the
// allocator's history (call once, first thing in main): large blocks (1 MiB
// and more) get pages of their own, which go back to the system when freed.
// By default glibc raises that threshold after each such free, up to 32 MiB,
// and later blocks below it come from the heap, whose freed middle stays
// resident: a set-up's or an output's temporary arrays then add to the time
// loop's (docs/performance.md, "Peak memory"). Elsewhere it does nothing.
void return_large_blocks_when_freed();

// The opposite, for runs that free and allocate tables of the same sizes
// again and again (adaptive refinement builds a new simulation at each event,
// docs/refinement.md, "Wall time and the allocator"): every block comes from
// the heap and freed memory stays with the process for the next event,
// instead of going back to the system and being zeroed page by page by the
// kernel when touched again. The peak then includes freed blocks that no
// later one fitted into. Elsewhere it does nothing.
void keep_freed_blocks_for_reuse();

// Starts a new peak where the system allows it (Linux: /proc/self/clear_refs);
// elsewhere the peak stays that of the whole process.
void reset_peak_memory();

}  // namespace pd::solver
