#pragma once
// What the solver's summary.json says about a run, as far as pd-post needs it.
// pd-solve writes summary.json once, at the end of a run: an output directory
// without it belongs to a run that stopped before its end or is still running
// (its lock says which).
#include <cmath>
#include <string>

#include "arrival_data.hpp"
#include "run_lock.hpp"

namespace pd::post {

struct SolverSummary {
  bool present = false;     // OUTDIR/summary.json exists
  std::string path;         // OUTDIR/summary.json
  std::string mode;         // "quasi_static"; empty for dynamic runs (the key is not written)
  std::string model;        // "pmb", ...; empty if absent
  std::string plane;        // "stress", "strain"; empty if absent (older outputs)
  std::string stop_reason;  // empty if absent
  long load_steps = -1;     // a quasi-static run's load steps in all; -1 if absent
  bool damage_off = false;  // "effects": {"damage": false} (the scene's effects.damage)
  // A dynamic run's end and what it ran on, for telling its arrival.vtp from
  // another run's; -1 or NaN if absent.
  long steps = -1;                 // "steps": the step the run ended at
  double end_time = std::nan("");  // "end_time_s" [s]
  long particles = -1;             // "counts": {"particles"} (the final set's)
  double youngs_modulus = std::nan("");  // "material": {"youngs_modulus_Pa"} [Pa]
  double density = std::nan("");         // "material": {"density_kg_m3"} [kg/m^3]
  std::string run_id;  // "run_id" (docs/formats.md, "Run identifier"); empty if absent
};

// What OUTDIR holds: a quasi-static run if summary.json says so, or if it has
// load_steps.csv or final_state.vtp and no arrival.vtp; a dynamic run otherwise.
RunKind detect_run_kind(const std::string& outdir, const SolverSummary& summary);

// Why a run's folder has no summary.json, as the run's lock (common/run_lock)
// says: "the run is still running (pd-solve holds OUTDIR/.pd-solve.lock, PID
// N)" where a live pd-solve holds it, "the run stopped before its end
// (killed, or failed)" where nobody does, and, where the lock cannot be
// looked at, "the solver was killed or is still running".
std::string unfinished_run_state(const RunLockStatus& lock);

// The warning for an output directory without summary.json; `covers` says
// how far the files that exist go (e.g. "arrival.vtp is from t = 12 us").
std::string incomplete_run_warning(const std::string& outdir, const std::string& covers);

// Reads OUTDIR/summary.json if it exists. Only the values above are kept
// (top-level ones, and "effects"' member "damage"; "mode" must be "dynamic"
// or "quasi_static", "plane" "stress" or "strain"); the whole file must be
// valid JSON, else pd::Error names the file and the byte where it stops
// being JSON; and its "tool" must be pd-solve's ("pd-solve 0.1.0").
SolverSummary read_solver_summary(const std::string& outdir);

// pd::Error naming both files unless the run's summary.json and its
// arrival.vtp are of one run: the end step and time, the particle count, the
// material and the run identifier, where both give them (a folder mixed by copying files of two
// runs would otherwise be read as one run).
void check_same_run(const SolverSummary& summary, const ArrivalData& arrival);

}  // namespace pd::post
