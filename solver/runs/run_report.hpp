#pragma once
// What a run tells the user, the same way for every kind of run: the plan
// printed before it starts (the lines every run shares, then the run's own)
// and summary.json at the end (the fields every run shares, then the run's
// own; docs/formats.md).
#include <cstdint>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "bond_setup.hpp"
#include "loads.hpp"
#include "model_summary.hpp"
#include "run_context.hpp"
#include "units.hpp"  // format_number, used with the plan lines

namespace pd::solver {

// A JSON object written one field per line; nested objects on one line.
class JsonObject {
public:
  JsonObject& number(const std::string& key, double value);  // non-finite values become null
  JsonObject& integer(const std::string& key, std::int64_t value);
  JsonObject& text(const std::string& key, const std::string& value);
  JsonObject& boolean(const std::string& key, bool value);
  JsonObject& object(const std::string& key, const JsonObject& value);
  JsonObject& texts(const std::string& key, const std::vector<std::string>& values);  // an array of strings
  // "{...}" on one line (nested) or one field per line (top level).
  std::string str(bool one_line = false) const;

private:
  std::vector<std::pair<std::string, std::string>> fields_;  // key, JSON value
};

// What the plan and summary need to know of a run's problem.
struct ProblemFacts {
  const ModelSummary& model;
  const SetupFacts& setup;
  const std::vector<ResolvedLoad>& loads;
  // The particles the counts are of: 0 for the particle file's; an adaptive
  // run's summary gives its final set's, with the bonds of that set.
  std::size_t particle_count = 0;
  // Warnings the run found besides those of the scene and set-up (a step
  // count that would run for days), listed after them.
  std::vector<std::string> run_warnings{};
};

// What the plan warns about before the first step (an output folder whose
// name ends in white space, loads, pieces, the critical stretch); also
// summary.json's "warnings". `particle_count`: of the set the loads were
// resolved on; `output_dir`: -o.
std::vector<std::string> plan_warnings(const Scene& scene, const ProblemFacts& problem, std::size_t particle_count,
                                       const std::string& output_dir);

// "pd-solve VERSION (KIND)" and the scene, particles, model, effects and loads
// lines and the warnings (on stderr too when stdout is not a terminal);
// `particles_extra` goes into the particles line.
// The run's plan reached its report (flushed now), else pd::Error: a report
// that cannot be written (stdout to a full disk) stops the run before its
// first step, rather than after hours (the tool would fail at its end).
// Nothing to check on a process that prints nothing (no stream buffer).
void require_plan_written(std::ostream& log);

void print_plan_header(std::ostream& log, const RunContext& run, const ProblemFacts& problem, const std::string& kind,
                       const std::string& particles_extra = "");
// Where a warning goes besides the run's report: stderr when the report goes
// elsewhere (stdout to a file, stderr to the terminal), so that a warning is
// never only in a file unread; null when both are one place (a terminal,
// 2>&1), not to print it twice. Under mpirun the root's streams are the
// launcher's, whatever the user redirected: stderr.
std::ostream* warning_echo(const RunContext& run);

// The threads and output lines, and the stop line if the scene has one.
void print_plan_footer(std::ostream& log, const RunContext& run, const std::string& output_plan);

// The fields every summary.json has, for a run of `mode` ("dynamic",
// "quasi_static"); the caller adds its own and writes it with write_summary.
JsonObject summary_fields(const RunContext& run, const ProblemFacts& problem, const std::string& mode,
                          const std::string& stop_reason, double wall_seconds);
// Adds the peak memory and writes OUTDIR/summary.json atomically.
void write_summary(const RunContext& run, JsonObject summary, std::uint64_t bond_count);

// "<peak> MB (<bytes per bond> bytes per directed bond)" for the final line.
std::string peak_memory_text(std::uint64_t bond_count);

}  // namespace pd::solver
