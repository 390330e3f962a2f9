#include "checkpoint.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstdint>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "atomic_file.hpp"
#include "binary_codec.hpp"
#include "checksum.hpp"
#include "error.hpp"
#include "units.hpp"

namespace pd::solver {
namespace {
constexpr char magic[8] = {'P', 'D', 'C', 'H', 'K', '0', '0', '3'};
constexpr char quasi_static_magic[8] = {'P', 'D', 'Q', 'S', 'C', '0', '0', '2'};

// write_keyed_payload, atomically.
void write_envelope(const std::string& path, const char* file_magic, const std::string& key,
                    const std::function<void(BinaryWriter&)>& write_payload) {
  write_atomically(path, [&](std::ofstream& out) { write_keyed_payload(out, file_magic, key, write_payload); });
}

// A checkpoint file opened and checked (magic, key, the checksum over its
// payload), positioned at the payload's first byte. The file is streamed
// through the checksum in pieces, never held whole: a large run's restart
// holds its state once.
// The key's lines, each named with its table: "material.density = 1190",
// "loads[1].y = 0.3" (the n-th [[loads]] entry), "particles HASH".
// The key's lines after the scene's text (checkpoint_key).
constexpr const char* particles_line = "particles ";
constexpr const char* several_processes_line = "bond states family by family";

// `key` without the line that says its bond states are family by family
// (checkpoint_key), and whether it had it: the line tells the layout of the
// bond states, not another run, so that a checkpoint of any process count
// restarts on any other (Simulation::State::bond_states_by_family).
bool without_layout_line(std::string& key) {
  const std::string line = std::string("\n") + several_processes_line;
  if (key.size() < line.size() || key.compare(key.size() - line.size(), line.size(), line) != 0) return false;
  key.erase(key.size() - line.size());
  return true;
}

std::vector<std::string> qualified_lines(const std::string& key) {
  std::vector<std::string> lines;
  std::map<std::string, int> entries;
  std::string table;
  std::istringstream in(key);
  for (std::string line; std::getline(in, line);) {
    line.erase(0, line.find_first_not_of(" \t"));
    if (line.empty()) continue;
    if (line.rfind("[[", 0) == 0) {
      const std::string name = line.substr(2, line.find("]]") - 2);
      table = name + "[" + std::to_string(entries[name]++) + "]";
    } else if (line[0] == '[') {
      table = line.substr(1, line.find(']') - 1);
      // The table itself: [refinement], [stop] and [quasi_static] ask for
      // their effect by being there, with every key at its default too.
      lines.push_back("[" + table + "]");
    } else if (line.rfind(particles_line, 0) == 0 && line.find(" = ") == std::string::npos) {
      lines.push_back(line);  // the run's own lines, in no table of the scene
    } else {
      lines.push_back(table.empty() ? line : table + "." + line);
    }
  }
  return lines;
}

// A number of a key as text: a whole number below 1e15 as its digits (a
// count of 1000000 reads as one, not as 1e+06), any other as the shortest
// text of its double (shortest_text). Equal doubles give equal texts.
std::string number_text(double value) {
  if (std::fabs(value) < 1e15 && value == std::floor(value)) return std::to_string(static_cast<long long>(value));
  return shortest_text(value);
}

// One number of a key as number_text writes its double,
// or as written when it is not a number TOML writes. A whole number that no
// double holds (beyond 2^53, odd) keeps its digits.
std::string canonical_number(std::string token) {
  token.erase(std::remove(token.begin(), token.end(), '_'), token.end());
  const bool sign = token[0] == '+' || token[0] == '-';
  const std::size_t digits = sign ? 1 : 0;
  int base = 10;
  if (token.size() > digits + 2 && token[digits] == '0' && std::strchr("xob", token[digits + 1]))
    base = token[digits + 1] == 'x' ? 16 : token[digits + 1] == 'o' ? 8 : 2;
  const std::string integer = base == 10 ? token.substr(digits) : token.substr(digits + 2);
  if (!integer.empty() &&
      std::all_of(integer.begin(), integer.end(), [&](char c) { return std::isxdigit(static_cast<unsigned char>(c)); }) &&
      (base == 16 || std::all_of(integer.begin(), integer.end(), [](char c) { return c >= '0' && c <= '9'; }))) {
    errno = 0;
    const unsigned long long magnitude = std::strtoull(integer.c_str(), nullptr, base);
    if (errno != 0) return token;
    const double value = static_cast<double>(magnitude);
    if (!(value < 18446744073709551616.0) || static_cast<unsigned long long>(value) != magnitude)
      return (token[0] == '-' ? "-" : "") + std::to_string(magnitude);
    return number_text(token[0] == '-' ? -value : value);
  }
  char* end = nullptr;
  const double value = std::strtod(token.c_str(), &end);
  return end == token.c_str() + token.size() ? number_text(value) : token;
}

// A key's text with every number outside its strings written as
// number_text writes its double: 1190, 1190.0 and 0x4a6 are "1190",
// 0.34999999999999998 (17 digits, as toml++ writes 0.35) is "0.35",
// 100000000000000000 and 1e+17 are "1e+17". A value the scene reads as a
// number is that double however it was spelt (a whole number, a decimal,
// "1190 kg/m^3" kept as its SI number, a --set); counts take whole numbers
// only, so no count is mistaken for a decimal. Strings keep their text (a
// load's name 'edge 1' is not 'edge 1.0'), and so do keys and the run's own
// lines: a number starts a value, after '=', '[' or ','. Two keys are one
// scene when these texts are equal; the refusal's message quotes them.
std::string canonical_numbers(const std::string& text) {
  std::string out;
  out.reserve(text.size() + text.size() / 8);
  char previous = '\n';  // the last character outside strings that is not a space
  for (std::size_t i = 0; i < text.size();) {
    const char c = text[i];
    if (c == '"' || c == '\'') {
      // A string as toml++ writes one: "..." (with escapes), '...', or either tripled.
      const std::string quote(text.compare(i, 3, std::string(3, c)) == 0 ? 3 : 1, c);
      std::size_t end = i + quote.size();
      while (end < text.size() && text.compare(end, quote.size(), quote) != 0)
        end += c == '"' && text[end] == '\\' ? 2 : 1;
      end = std::min(text.size(), end + quote.size());
      out.append(text, i, end - i);
      i = end;
      previous = c;
      continue;
    }
    const auto digit = [&](std::size_t k) {
      return k < text.size() && std::isdigit(static_cast<unsigned char>(text[k]));
    };
    if ((previous == '=' || previous == '[' || previous == ',') &&
        (digit(i) || ((c == '+' || c == '-') && digit(i + 1)))) {
      std::size_t end = i + 1;
      for (; end < text.size(); ++end) {
        const char d = text[end];
        const bool exponent_sign = (d == '+' || d == '-') && (text[end - 1] == 'e' || text[end - 1] == 'E') &&
                                   text.compare(i, 2, "0x") != 0;
        if (!std::isalnum(static_cast<unsigned char>(d)) && d != '.' && d != '_' && !exponent_sign) break;
      }
      out += canonical_number(text.substr(i, end - i));
      i = end;
      previous = '0';
      continue;
    }
    out += c;
    if (!std::isspace(static_cast<unsigned char>(c))) previous = c;
    ++i;
  }
  return out;
}

// Why a key that changes no result is still part of the checkpoint's key
// (docs/solver.md, "Safety"), for the refusal's message; empty for the others.
std::string why_kept(const std::string& line) {
  const std::string name = line.substr(0, line.find(" = "));
  if (name == "output.energy_interval")
    return "; the energy interval cannot change on a restart: the run checks its energy and keeps the state an "
           "unstable run rolls back to at each energy row, so another interval can change where such a run stops, "
           "and energy.csv would change its spacing midway";
  if (name == "output.snapshot_interval")
    return "; the snapshot interval cannot change on a restart: the series of snapshots (snapshots.pvd) and the "
           "restart's check of those written so far follow one interval";
  if (name == "output.damage_thresholds")
    return "; the damage thresholds cannot change on a restart: the checkpoint holds the arrival times of its "
           "thresholds";
  return {};
}

// Why a checkpoint's key is not this run's, for the refusal's message:
// the first key of the scene the checkpoint has with another value or not at
// all, else the first key only this run has, else the particle file's content.
// (The process count is no mismatch: without_layout_line.)
std::string key_mismatch(const std::string& stored, const std::string& now) {
  std::vector<std::string> a = qualified_lines(canonical_numbers(stored)), b = qualified_lines(canonical_numbers(now));
  const std::set<std::string> in_a(a.begin(), a.end()), in_b(b.begin(), b.end());
  // A key is named before its table ('model.dual_horizon = true', not
  // '[model]', which is left out with its last key): a table's line alone
  // differs only for a table that asks for its effect by being there.
  for (auto* lines : {&a, &b})
    std::stable_partition(lines->begin(), lines->end(), [](const std::string& line) { return line[0] != '['; });
  std::string line_a, line_b;
  for (const auto& line : a)
    if (line.rfind(particles_line, 0) == 0 && line.find(" = ") == std::string::npos) line_a = line;
  for (const auto& line : b)
    if (line.rfind(particles_line, 0) == 0 && line.find(" = ") == std::string::npos) line_b = line;
  std::string difference = "the keys differ";
  for (const auto& line : a) {
    if (in_b.count(line) || line == line_a) continue;
    const auto name_end = line.find(" = ");
    const std::string name = name_end != std::string::npos ? line.substr(0, name_end + 3) : line;
    // (A key at its default is left out of the key, written or not: scene.cpp.)
    difference = "first difference: '" + line + "' in the checkpoint; left out now (or its default)";
    for (const auto& other : b)
      if (other.rfind(name, 0) == 0) {
        difference = "first difference: '" + line + "' in the checkpoint, '" + other + "' now";
        break;
      }
    difference += why_kept(line);
    break;
  }
  if (difference == "the keys differ")
    for (const auto& line : b)
      if (!in_a.count(line) && line != line_b) {
        difference = "first difference: '" + line + "' now; the checkpoint's run left it out (or had its "
                     "default)" + why_kept(line);
        break;
      }
  if (difference == "the keys differ" && line_a != line_b)
    return "checkpoint belongs to another particle file (its content changed since the checkpoint was written: " +
           line_a.substr(std::string(particles_line).size()) + " then, " + line_b.substr(std::string(particles_line).size()) +
           " now)";
  return "checkpoint belongs to a different scene or particle file (settings changed since it was written; " +
         difference + ")";
}

// A dynamic checkpoint's state and energy rows. With `in_place` the arrays
// of `s` have the run's sizes already and are overwritten (a file of other
// sizes is refused); without, they take the file's sizes.
void read_state(BinaryReader& r, Simulation::State& s, EnergyRecords& energy, bool in_place) {
  const auto read = [&](auto& v, const char* what) {
    const auto count = r.scalar<std::uint64_t>(what);
    if (in_place && count != v.size())
      throw file_error(r.path(), std::string("checkpoint does not fit this particle set and scene (") + what + ": " +
                                     std::to_string(count) + " values, the run has " + std::to_string(v.size()) + ")");
    r.values(v, count, what);
  };
  s.step = static_cast<long>(r.scalar<std::int64_t>("step"));
  s.time = r.scalar<double>("time");
  s.external_work = r.scalar<double>("external work");
  energy.check.energy_beyond_work = r.scalar<double>("energy beyond the work at the start");
  energy.check.largest_supplied = r.scalar<double>("largest energy supplied");
  energy.check.broken_at_start = r.scalar<std::uint64_t>("bonds broken at the start");
  const auto gain_warning = r.counted_strings("energy gain warning");
  if (gain_warning.size() > 1) throw file_error(r.path(), "checkpoint is corrupt (energy gain warning)");
  energy.check.gain_warning = gain_warning.empty() ? std::string() : gain_warning.front();
  const std::pair<std::vector<double>*, const char*> arrays[] = {
      {&s.kinematics.ux, "ux"}, {&s.kinematics.uy, "uy"}, {&s.kinematics.vx, "vx"}, {&s.kinematics.vy, "vy"},
      {&s.kinematics.fx, "fx"}, {&s.kinematics.fy, "fy"}, {&s.damage, "damage"},    {&s.arrival, "arrival times"}};
  for (const auto& [v, what] : arrays) read(*v, what);
  read(s.bond_states, "bond states");
  energy.rows = r.counted_strings("energy rows");
}

// A dynamic checkpoint's payload, whole.
void read_dynamic_payload(BinaryReader& r, Checkpoint& c) {
  read_state(r, c.state, c.energy, false);
  if (r.remaining() != 0) {
    const auto steps = r.counted<std::int64_t>("refinement steps");
    const auto times = r.counted<double>("refinement times");
    const auto counts = r.counted<std::uint64_t>("refinement parent counts");
    const auto parents = r.counted<std::uint32_t>("refinement parents");
    std::uint64_t total = 0;
    for (auto n : counts) total += n;
    if (times.size() != steps.size() || counts.size() != steps.size() || total != parents.size())
      throw file_error(r.path(), "checkpoint is corrupt (refinement events)");
    std::size_t at = 0;
    for (std::size_t e = 0; e < steps.size(); ++e) {
      SplitEvent event{static_cast<long>(steps[e]), times[e], {}};
      event.parents.assign(parents.begin() + static_cast<std::ptrdiff_t>(at),
                           parents.begin() + static_cast<std::ptrdiff_t>(at + counts[e]));
      at += counts[e];
      c.refinements.push_back(std::move(event));
    }
  }
  if (r.remaining() != 0) throw file_error(r.path(), "checkpoint has trailing data");
}

// A quasi-static checkpoint's payload, whole.
void read_quasi_static_payload(BinaryReader& r, QuasiStaticCheckpoint& c) {
  auto& s = c.state;
  s.load_factors_done = r.counted<double>("load factors");
  s.u = r.counted<double>("displacements");
  s.damage_load_factor = r.counted<double>("damage load factors");
  s.largest_reaction_norm = r.scalar<double>("largest reaction");
  s.largest_axial_reaction = r.scalar<double>("largest axial reaction");
  const auto stop_reason = r.counted_strings("stop reason");
  if (stop_reason.size() != 1) throw file_error(r.path(), "checkpoint is corrupt (stop reason)");
  s.stop_reason = stop_reason.front();
  c.bond_states = r.counted<std::uint8_t>("bond states");
  c.load_step_rows = r.counted_strings("load step rows");
  const auto factors = r.counted<double>("snapshot load factors");
  const auto names = r.counted_strings("snapshot names");
  if (factors.size() != names.size()) throw file_error(r.path(), "checkpoint is corrupt (snapshot list)");
  for (std::size_t k = 0; k < factors.size(); ++k) c.snapshots.emplace_back(factors[k], names[k]);
  // The predictor's increment (load_steps.hpp); absent from older checkpoints,
  // which resume with the scaled predictor.
  if (r.remaining() != 0) s.last_increment = r.counted<double>("last increment");
  if (r.remaining() != 0) throw file_error(r.path(), "checkpoint has trailing data");
}

struct CheckedPayload {
  std::ifstream in;
  std::uint64_t size = 0;  // payload bytes
  bool bond_states_by_family = false;  // written on several processes (its key's last line)
};

void open_checked_payload(const std::string& path, const char* file_magic, const std::string& run_key,
                          CheckedPayload& payload) {
  std::ifstream& in = payload.in;
  in.open(path, std::ios::binary);
  if (!in) throw file_error(path, "cannot open checkpoint (run without --restart first)");
  in.seekg(0, std::ios::end);
  const auto file_size = static_cast<std::uint64_t>(std::max<std::streamoff>(in.tellg(), 0));
  in.seekg(0);
  char head[16] = {};
  in.read(head, static_cast<std::streamsize>(std::min<std::uint64_t>(file_size, 16)));
  if (!in) throw file_error(path, "cannot read checkpoint");
  if (file_size >= 8 && file_size < 24 && std::memcmp(head, file_magic, 8) == 0)
    throw file_error(path, "checkpoint is truncated (" + std::to_string(file_size) + " bytes)");
  if (file_size < 24 || std::memcmp(head, file_magic, 8) != 0) {
    const bool dynamic_run = std::memcmp(file_magic, magic, 8) == 0;
    const char* other_magic = dynamic_run ? quasi_static_magic : magic;
    const bool other = file_size >= 8 && std::memcmp(head, other_magic, 8) == 0;
    // Same kind (first five bytes), other format version (last three).
    const bool older = file_size >= 8 && std::memcmp(head, file_magic, 5) == 0;
    const std::string this_mode = dynamic_run ? "dynamic" : "quasi-static";
    const std::string other_mode = dynamic_run ? "quasi-static" : "dynamic";
    throw file_error(path, other   ? "a " + other_mode + " run's checkpoint (" + std::string(head, 8) + "), and this run is " +
                                         this_mode + ": --restart continues the run that wrote it, with its scene; run "
                                         "without --restart to start over"
                           : older ? "checkpoint format " + std::string(head, 8) + " of another pd-solve version (this one reads " +
                                         std::string(file_magic, 8) + "); run again without --restart"
                                   : "not a pd-solve checkpoint");
  }
  const auto key_size = BinaryReader(head + 8, 8, path).scalar<std::uint64_t>("key length");
  if (key_size > file_size - 24)
    throw file_error(path, "checkpoint is truncated: " + std::to_string(file_size) + " bytes, and its header's key of " +
                               std::to_string(key_size) + " bytes needs at least " +
                               std::to_string(std::min(key_size, std::numeric_limits<std::uint64_t>::max() - 24) + 24) +
                               " (pd-solve writes it whole or not at all: a copy cut short, or a disk that filled during "
                               "one); run without --restart to start over");
  std::string stored_key(static_cast<std::size_t>(key_size), '\0');
  in.read(stored_key.data(), static_cast<std::streamsize>(key_size));
  if (!in) throw file_error(path, "cannot read checkpoint");
  // The keys compared without the layout's line: a checkpoint of one process
  // restarts on several and the other way round (the bond states are
  // converted, dynamic_run.cpp), since 8 December 2026.
  payload.bond_states_by_family = without_layout_line(stored_key);
  std::string key = run_key;
  without_layout_line(key);
  if (stored_key != key && canonical_numbers(stored_key) != canonical_numbers(key))
    throw file_error(path, key_mismatch(stored_key, key));
  const std::uint64_t payload_begin = 16 + key_size;
  payload.size = file_size - 8 - payload_begin;
  Checksum sum;
  std::vector<char> piece(std::size_t{1} << 20);
  for (std::uint64_t left = payload.size; left > 0;) {
    const auto n = static_cast<std::size_t>(std::min<std::uint64_t>(left, piece.size()));
    in.read(piece.data(), static_cast<std::streamsize>(n));
    if (!in) throw file_error(path, "cannot read checkpoint");
    sum.update(piece.data(), n);
    left -= n;
  }
  char stored[8];
  in.read(stored, 8);
  if (!in) throw file_error(path, "cannot read checkpoint");
  if (sum.value() != BinaryReader(stored, 8, path).scalar<std::uint64_t>("checksum")) {
    // A file cut short (a copy interrupted, a full disk) has no checksum at
    // its end either: its own arrays' counts show how far it should reach.
    in.clear();
    in.seekg(static_cast<std::streamoff>(payload_begin));
    BinaryReader r(in, payload.size, path);
    try {
      if (std::memcmp(file_magic, magic, 8) == 0) {
        Checkpoint whole;
        read_dynamic_payload(r, whole);
      } else {
        QuasiStaticCheckpoint whole;
        read_quasi_static_payload(r, whole);
      }
    } catch (const Error&) {
      if (r.short_read().end > r.position()) {
        const std::uint64_t most = std::numeric_limits<std::uint64_t>::max();
        const std::uint64_t needed = r.short_read().end > most - payload_begin - 8 ? most
                                                                                  : payload_begin + r.short_read().end + 8;
        throw file_error(path, "checkpoint is truncated: " + std::to_string(file_size) +
                                   " bytes, where the counts of its arrays need at least " + std::to_string(needed) +
                                   " (it ends within '" + r.short_read().what +
                                   "'; pd-solve writes it whole or not at all: a copy cut short, or a disk that filled "
                                   "during one); run without --restart to start over");
      }
    }
    throw file_error(path, "checkpoint checksum mismatch (file corrupted): its " + std::to_string(file_size) +
                               " bytes hold every array its counts give, with other values than were written; run "
                               "without --restart to start over");
  }
  in.seekg(static_cast<std::streamoff>(payload_begin));
}

}  // namespace

std::string checkpoint_key(const std::string& scene_key_text, const std::string& particle_hash, int processes) {
  std::string key = scene_key_text + "\n" + particles_line + particle_hash;
  if (processes > 1) key += std::string("\n") + several_processes_line;
  return key;
}

std::string run_identifier(const std::string& scene_key_text, const std::string& particle_hash) {
  // canonical_numbers: the keys open_checked_payload takes as one are one
  // text here, so a restart it accepts has its checkpoint's identifier.
  const std::string key = canonical_numbers(checkpoint_key(scene_key_text, particle_hash, 1));
  // 64 bits of FNV-1a (pd::Checksum, not cryptographic): the identifier only
  // tells apart runs whose files were mixed in one folder, of which two that
  // differ share it with a chance of about 2^-64.
  Checksum hash;
  hash.update(key.data(), key.size());
  // FNV's last multiply carries a change into the higher bits only: SplitMix64's
  // finaliser spreads it over all 16 digits, so that two identifiers differ in
  // their look, not only in their first digits.
  std::uint64_t h = hash.value();
  h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ULL;
  h = (h ^ (h >> 27)) * 0x94d049bb133111ebULL;
  h ^= h >> 31;
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
  return text;
}

void write_checkpoint(const std::string& path, const std::string& key, const Simulation::StateView& s,
                      const EnergyRecords& energy, const std::vector<SplitEvent>& refinements) {
  write_envelope(path, magic, key, [&](BinaryWriter& w) {
    w.scalar<std::int64_t>(s.step);
    w.scalar(s.time);
    w.scalar(s.external_work);
    w.scalar(energy.check.energy_beyond_work);
    w.scalar(energy.check.largest_supplied);
    w.scalar<std::uint64_t>(energy.check.broken_at_start);
    w.counted_strings(energy.check.gain_warning.empty() ? std::vector<std::string>{}
                                                        : std::vector<std::string>{energy.check.gain_warning});
    const Kinematics& k = *s.kinematics;
    for (const auto* v : {&k.ux, &k.uy, &k.vx, &k.vy, &k.fx, &k.fy, s.damage, s.arrival}) w.counted(*v);
    w.counted(*s.bond_states);
    w.counted_strings(energy.rows);
    if (!refinements.empty()) {
      std::vector<std::int64_t> steps;
      std::vector<double> times;
      std::vector<std::uint64_t> counts;
      std::vector<std::uint32_t> parents;
      for (const auto& e : refinements) {
        steps.push_back(e.step);
        times.push_back(e.time);
        counts.push_back(e.parents.size());
        parents.insert(parents.end(), e.parents.begin(), e.parents.end());
      }
      w.counted(steps);
      w.counted(times);
      w.counted(counts);
      w.counted(parents);
    }
  });
}

Checkpoint read_checkpoint(const std::string& path, const std::string& key) {
  CheckedPayload payload;
  open_checked_payload(path, magic, key, payload);
  BinaryReader r(payload.in, payload.size, path);
  Checkpoint c;
  read_dynamic_payload(r, c);
  c.state.bond_states_by_family = payload.bond_states_by_family;
  return c;
}

bool check_checkpoint(const std::string& path, const std::string& key) {
  CheckedPayload payload;
  open_checked_payload(path, magic, key, payload);
  return payload.bond_states_by_family;
}

EnergyRecords read_checkpoint_in_place(const std::string& path, const std::string& key, Simulation::State& state) {
  CheckedPayload payload;
  open_checked_payload(path, magic, key, payload);
  if (payload.bond_states_by_family)  // (the caller asks check_checkpoint first)
    throw file_error(path, "a checkpoint of several processes is read whole (read_checkpoint), not in place");
  BinaryReader r(payload.in, payload.size, path);
  EnergyRecords energy;
  read_state(r, state, energy, true);
  if (r.remaining() != 0)  // refinement events: read_checkpoint's
    throw file_error(path, "the checkpoint holds a refined particle set, but the scene has no [refinement]");
  return energy;
}

void write_checkpoint(const std::string& path, const std::string& key, const QuasiStaticCheckpoint& c) {
  write_envelope(path, quasi_static_magic, key, [&](BinaryWriter& w) {
    const auto& s = c.state;
    for (const auto* v : {&s.load_factors_done, &s.u, &s.damage_load_factor}) w.counted(*v);
    w.scalar(s.largest_reaction_norm);
    w.scalar(s.largest_axial_reaction);
    w.counted_strings({s.stop_reason});
    w.counted(c.bond_states);
    w.counted_strings(c.load_step_rows);
    std::vector<double> factors;
    std::vector<std::string> names;
    for (const auto& [factor, name] : c.snapshots) factors.push_back(factor), names.push_back(name);
    w.counted(factors);
    w.counted_strings(names);
    w.counted(s.last_increment);  // last: a checkpoint written without it still reads
  });
}

QuasiStaticCheckpoint read_quasi_static_checkpoint(const std::string& path, const std::string& key) {
  CheckedPayload payload;
  open_checked_payload(path, quasi_static_magic, key, payload);
  BinaryReader r(payload.in, payload.size, path);
  QuasiStaticCheckpoint c;
  read_quasi_static_payload(r, c);
  return c;
}

}  // namespace pd::solver
