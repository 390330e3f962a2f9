#pragma once
// What a plan may ask of the machine, the same for every kind of run
// (docs/scenes.md, "[time]" and "[output]"): steps no machine could finish
// are refused and steps that would run for days warned about; snapshots
// that would not fit on the output folder's disk are refused and more than
// 10,000 snapshot files warned about. A dynamic run counts time steps, a
// quasi-static one load steps; each says what it counted and what to change.
#include <string>

#include "run_context.hpp"

namespace pd::solver {

// A duration for the plan: "40 s", "3.2 min", "1.5 h", "2.1 days".
std::string duration_text(double seconds);

// How much work a run's steps are.
struct RunLength {
  double steps = 0;             // time steps or load steps
  double bond_evaluations = 0;  // the directed bond evaluations they take (at the least)
  double seconds = 0;           // at the rate measured at set-up
  std::string description;      // the count and its estimate, for the messages ("time.end = ... about 3 days")
  std::string advice;           // what to change, for the refusal ("shorten time.end, ...")
};

// pd::Error "`where`: DESCRIPTION (N days even at 1e10 directed bond
// evaluations per second); refused (ADVICE)" when the steps cannot be counted
// exactly (more than 2^53) or their bond evaluations would take more than a
// year even at 1e10 per second (several times what one machine reaches: a
// refusal that does not depend on the machine's load). Returns the
// description as a warning when they would run for more than a day at the
// measured rate (only an estimate), else "".
std::string check_run_length(const RunLength& length, const std::string& where);

// What a run's snapshots and its checkpoint would take on disk.
struct SnapshotVolume {
  double snapshots = 0;         // the files the run writes
  double particles = 0;         // in each (about 40 bytes each on disk)
  double checkpoint_bytes = 0;  // 0 without checkpoints
  std::string span;             // the steps they cover: "from step 0 to 1000"
  std::string advice;           // what to change besides the interval and the disk: "shorten time.end (in s)"
};

// Snapshots are taken at about 40 bytes per particle (the compressed .vtp of
// a cracked C3-A plate: 37; a quasi-static one of C1: 36). pd::Error
// "SOURCE: key 'output.snapshot_interval' = N: S snapshots of about X MB each
// (TOTAL) SPAN [and a checkpoint of about C] would not fit in the F free under
// OUTDIR; raise the interval, ADVICE or free disk space" when they and the
// checkpoint cannot fit under the output folder; returns a warning ending in
// "that many files" beyond 10,000 snapshot files (else nothing): a time.end
// in the wrong unit, or a million tiny load steps, with snapshots on would
// otherwise write for days until the disk is full.
std::string check_snapshot_volume(const RunContext& run, const SnapshotVolume& volume);

}  // namespace pd::solver
