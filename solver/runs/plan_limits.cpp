#include "plan_limits.hpp"

#include <cstdio>
#include <filesystem>
#include <sstream>

#include "error.hpp"
#include "units.hpp"

namespace pd::solver {

std::string duration_text(double seconds) {
  char text[32];
  if (seconds < 120) std::snprintf(text, sizeof text, "%.2g s", seconds);
  else if (seconds < 7200) std::snprintf(text, sizeof text, "%.2g min", seconds / 60);
  else if (seconds < 172800) std::snprintf(text, sizeof text, "%.2g h", seconds / 3600);
  else std::snprintf(text, sizeof text, "%.3g days", seconds / 86400);
  return text;
}

std::string check_run_length(const RunLength& length, const std::string& where) {
  constexpr double fastest_evaluations_per_second = 1e10;
  constexpr double countable = 9007199254740992.0;  // 2^53: every step number exact
  constexpr double year = 365.0 * 86400.0;
  if (!(length.steps <= countable) || !(length.bond_evaluations <= fastest_evaluations_per_second * year)) {
    std::ostringstream m;
    m << where << ": " << length.description << " ("
      << length.bond_evaluations / fastest_evaluations_per_second / 86400.0
      << " days even at 1e10 directed bond evaluations per second); refused (" << length.advice << ")";
    throw Error(m.str());
  }
  return length.seconds > 86400.0 ? length.description : std::string();
}

std::string check_snapshot_volume(const RunContext& run, const SnapshotVolume& volume) {
  const long interval = run.scene.output.snapshot_interval;
  constexpr double bytes_per_particle = 40;
  const double snapshot_bytes = volume.snapshots * bytes_per_particle * volume.particles;
  const double bytes = snapshot_bytes + volume.checkpoint_bytes;
  std::error_code error;
  const auto space = std::filesystem::space(run.output_dir(), error);
  std::ostringstream m;
  m << run.scene.source_of("output.snapshot_interval") << ": key 'output.snapshot_interval' = " << interval << ": "
    << static_cast<long long>(volume.snapshots) << " snapshots of about " << bytes_per_particle * volume.particles / 1e6
    << " MB each (" << format_bytes(snapshot_bytes) << ") " << volume.span;
  if (!error && bytes > static_cast<double>(space.available))
    throw Error(m.str() +
                (volume.checkpoint_bytes > 0 ? " and a checkpoint of about " + format_bytes(volume.checkpoint_bytes)
                                             : std::string()) +
                " would not fit in the " + format_bytes(static_cast<double>(space.available)) + " free under " +
                run.output_dir() + "; raise the interval, " + volume.advice + " or free disk space");
  return volume.snapshots > 10000 ? m.str() + ": that many files" : std::string();
}

}  // namespace pd::solver
