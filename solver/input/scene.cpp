#include "scene.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <limits>
#include <sstream>

#include "atomic_file.hpp"
#include "error.hpp"
#include "input_file.hpp"
#include "particle_file.hpp"
#include "units.hpp"

namespace pd::solver {
namespace {

bool is_control(char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }

// A control character as TOML escapes it: \n, \t, \r, else \u0000 and the like.
std::string escaped(char c) {
  if (c == '\n') return "\\n";
  if (c == '\t') return "\\t";
  if (c == '\r') return "\\r";
  char code[8];
  std::snprintf(code, sizeof code, "\\u%04X", static_cast<unsigned char>(c));
  return code;
}

// A string in a message, quoted as TOML writes it: 'right', or with escapes
// where it holds a quote or a control character ("a\u0000b", "a\nb"), never
// over several lines (a message is one line).
std::string in_quotes(const std::string& text) {
  if (std::none_of(text.begin(), text.end(), [](char c) { return c == '\'' || is_control(c); }))
    return "'" + text + "'";
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += std::string("\\") + c;
    else if (is_control(c)) out += escaped(c);
    else out += c;
  }
  return out + "\"";
}

// For a path or a name holding a control character: " (here \u0000, its
// character 8)", else "". The system reads a path up to a NUL (c3a.pdp\u0000x
// opened c3a.pdp), and names head CSV columns and appear in messages.
std::string control_character_note(const std::string& text) {
  const auto at = std::find_if(text.begin(), text.end(), is_control);
  if (at == text.end()) return "";
  return " (here " + escaped(*at) + ", its character " + std::to_string(at - text.begin() + 1) + ")";
}

// A key of a table in a message: bare where TOML allows it, else quoted.
std::string key_text(const std::string& key) {
  const bool bare = !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
  return bare ? key : in_quotes(key);
}

// A value in a message, on one line: a table inline ({damage = 0.35, set =
// 'right'}; toml++ prints one as lines of "key = value"), a float as written.
std::string node_text(const toml::node& node) {
  // A float as the user wrote it (1.19, not 1.1899999999999999): the
  // shortest form from 6 significant digits on that reads back to the same double.
  if (node.is_floating_point()) {
    std::string shortest = shortest_text(*node.value<double>());
    if (shortest.find_first_of(".eni") == std::string::npos) shortest += ".0";  // a float stays one: 0.0, not 0
    return shortest;
  }
  // An array element by element, so that its floats read as written too.
  if (const toml::array* array = node.as_array()) {
    std::string out = "[";
    for (std::size_t k = 0; k < array->size(); ++k) out += (k ? ", " : "") + node_text(*array->get(k));
    return out + "]";
  }
  if (const toml::table* table = node.as_table()) {
    std::string out;
    for (const auto& [key, value] : *table)
      out += (out.empty() ? "{" : ", ") + key_text(std::string(key.str())) + " = " + node_text(value);
    return out.empty() ? "{}" : out + "}";
  }
  if (const auto text = node.value_exact<std::string>()) return in_quotes(*text);
  std::ostringstream out;
  node.visit([&](const auto& n) { out << n; });
  return out.str();
}

// Edit distance of two keys (insertions, deletions, substitutions).
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// For a missing key: " (line 4 has 'youngs_modulos': misspelt?)" when the
// table holds a key a few letters from it, else "".
std::string misspelt_hint(const toml::table& table, const std::string& key) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, key.size() / 4) + 1;
  for (const auto& [k, node] : table) {
    const std::string name(k.str());
    const std::size_t d = edit_distance(name, key);
    if (d > 0 && d < best_distance) best = name, best_distance = d;
  }
  if (best.empty()) return "";
  const toml::node* n = table.get(best);
  const std::string where =
      n && n->source().begin.line > 0 ? "line " + std::to_string(n->source().begin.line) + " has" : "it has";
  return " (" + where + " " + in_quotes(best) + ": misspelt?)";
}

// Reads the keys of one TOML table, remembering which were used so that
// unknown (misspelt) keys are reported at the end.
// A key written with the value its default has ("energy_interval = 100") is
// noted in `written_defaults` (its full name): the restart key leaves it out,
// so that a scene that writes a default and one that leaves it out restart
// each other's checkpoints.
class TableReader {
public:
  TableReader(const toml::table& table, std::string prefix, const std::string& file,
              std::vector<std::string>* written_defaults = nullptr)
      : table_(table), prefix_(std::move(prefix)), file_(file), written_defaults_(written_defaults) {}
  // A reader of a table inside this one, noting defaults in the same list.
  TableReader sub(const toml::table& table, std::string prefix) const {
    return TableReader(table, std::move(prefix), file_, written_defaults_);
  }

  std::string full(const std::string& key) const { return prefix_.empty() ? key : prefix_ + "." + key; }
  const std::string& file() const { return file_; }

  // "FILE:LINE: key 'section.key' = VALUE", the start of every message about a key.
  std::string described(const std::string& key) const {
    const toml::node* n = table_.get(key);
    return location(key) + ": key '" + clipped(full(key)) + "'" + (n ? " = " + clipped(node_text(*n)) : "");
  }
  // "FILE:LINE" for a value of the file, "FILE, --set" for one that --set put
  // there (it has no line), "FILE" for a key that is not there.
  std::string location(const std::string& key) const {
    const toml::node* n = table_.get(key);
    if (!n) return file_;
    return file_ + (n->source().begin.line > 0 ? ":" + std::to_string(n->source().begin.line) : std::string(", --set"));
  }
  [[noreturn]] void fail(const std::string& key, const std::string& message) const {
    throw Error(described(key) + ": " + message);
  }

  const toml::node* find(const std::string& key) {
    used_.insert(key);
    return table_.get(key);
  }
  bool has(const std::string& key) { return find(key) != nullptr; }

  // "FILE" for a table of the file, "FILE, --set" for one that --set made
  // (stop.damage=0.5 on a scene without [stop]; loads=[{...}]), whose line is 0:
  // where a key missing from it is to be given.
  std::string source() const {
    return file_ + (!prefix_.empty() && table_.source().begin.line == 0 ? ", --set" : "");
  }

  const toml::node& require(const std::string& key) {
    const toml::node* n = find(key);
    // (A table that --set wrote, such as loads.0.y={value=0.3}, is blamed on --set.)
    if (!n) throw Error(source() + ": missing required key '" + full(key) + "'" + misspelt_hint(table_, key));
    return *n;
  }

  // A plain number; with `unit`, a key whose number is in that fixed SI unit
  // (docs/scenes.md, "Units": only the material's values and the times take
  // a unit), whose refusal of a value written with one says how to write it.
  double number(const std::string& key, const toml::node& n, std::optional<Quantity> unit = {},
                const char* example = "") const {
    if (!n.is_number()) fail(key, "expected a number" + (unit && n.is_string() ? no_unit(key, n, *unit, example) : ""));
    const double v = *n.value<double>();
    if (!std::isfinite(v)) fail(key, "expected a finite number");
    return v;
  }
  // Why a key in a fixed unit refuses the value `n` written with a unit: its
  // unit, and the value as the key takes it where each number's unit is
  // known ("write progress_interval = 10" for "10 s"), else `example`.
  std::string no_unit(const std::string& key, const toml::node& n, Quantity unit, const char* example) const {
    const auto in_si = [&](const toml::node& e, std::string& out) {
      if (e.is_number()) return out = shortest_text(*e.value<double>()), true;
      if (!e.is_string()) return false;
      try {
        return out = shortest_text(parse_quantity(*e.value<std::string>(), unit, key)), true;
      } catch (const Error&) {
        return false;
      }
    };
    std::string written;
    if (const toml::array* a = n.as_array()) {
      for (const auto& e : *a) {
        std::string value;
        if (!in_si(e, value)) {
          written.clear();
          break;
        }
        written += (written.empty() ? "[" : ", ") + value;
      }
      if (!written.empty()) written += "]";
    } else if (!in_si(n, written)) {
      written.clear();
    }
    const std::string head = ": this key is in " + std::string(si_unit(unit)) +
                             (n.is_array() ? " and takes plain numbers, no units" : " and takes a plain number, no unit");
    return written.empty() ? head + " (e.g. " + key + " = " + example + ")" : head + "; write " + key + " = " + written;
  }
  double positive(const std::string& key) {
    const double v = number(key, require(key));
    if (!(v > 0)) fail(key, "expected a positive number");
    return v;
  }
  double positive_or(const std::string& key, double fallback) {
    return has(key) ? noted(key, positive(key), fallback) : fallback;
  }
  // A positive physical quantity (docs/scenes.md, "Units"): a plain number in
  // SI units, or a string with its unit ("3.24 GPa"), taken as written. A plain
  // number far outside what solids have (plausible_range) is refused: 3.24 for
  // a Young's modulus is far more likely GPa than a material of 3.24 Pa.
  double quantity(const std::string& key, Quantity kind) {
    const toml::node& n = require(key);
    if (n.is_string()) {
      const double v = parse_quantity(*n.value<std::string>(), kind, described(key));
      if (!(v > 0)) fail(key, "expected a positive value");
      return v;
    }
    const double v = positive(key);
    const PlausibleRange range = plausible_range(kind);
    if (v < range.low || v > range.high) {
      const std::string si = si_unit(kind), hint = unit_hint(v, kind);
      std::ostringstream m;
      m << v << " " << si << " is outside " << range.what << " (" << range.low << " to " << range.high << " " << si
        << "); a plain number is read in " << si << ". ";
      if (!hint.empty()) m << "If it is in " << hint << ", write \"" << v << " " << hint << "\"";
      else m << "If it is meant, write it with its unit, \"" << v << " " << si << "\"";
      m << " (a value written with its unit is taken as given)";
      fail(key, m.str());
    }
    return v;
  }
  double quantity_or(const std::string& key, Quantity kind, double fallback) {
    return has(key) ? noted(key, quantity(key, kind), fallback) : fallback;
  }
  double real_or(const std::string& key, double fallback, std::optional<Quantity> unit = {}, const char* example = "") {
    const toml::node* n = find(key);
    return n ? noted(key, number(key, *n, unit, example), fallback) : fallback;
  }
  long count_or(const std::string& key, long fallback) {
    const toml::node* n = find(key);
    if (!n) return fallback;
    if (!n->is_integer()) fail(key, "expected a whole number of steps");
    const long v = static_cast<long>(*n->value<std::int64_t>());
    if (v < 0) fail(key, "expected a number of steps >= 0");
    return noted(key, v, fallback);
  }
  // A whole number of `what` (e.g. "halvings") from `lowest` to `highest`
  // (no upper bound: LONG_MAX), or the fallback; the message states the range.
  long whole_or(const std::string& key, long fallback, const std::string& what, long lowest = 0,
                long highest = std::numeric_limits<long>::max()) {
    const toml::node* n = find(key);
    if (!n) return fallback;
    if (!n->is_integer()) fail(key, "expected a whole number of " + what);
    const long v = static_cast<long>(*n->value<std::int64_t>());
    if (v < lowest || v > highest)
      fail(key, "expected a number of " + what +
                    (highest == std::numeric_limits<long>::max()
                         ? " >= " + std::to_string(lowest)
                         : " from " + std::to_string(lowest) + " to " + std::to_string(highest)));
    return noted(key, v, fallback);
  }
  bool boolean_or(const std::string& key, bool fallback) {
    const toml::node* n = find(key);
    if (!n) return fallback;
    if (!n->is_boolean()) fail(key, "expected true or false");
    return noted(key, *n->value<bool>(), fallback);
  }
  std::string string(const std::string& key) {
    const toml::node& n = require(key);
    if (!n.is_string()) fail(key, "expected a string");
    return *n.value<std::string>();
  }
  std::string string_or(const std::string& key, const std::string& fallback) {
    return has(key) ? noted(key, string(key), fallback) : fallback;
  }
  // With `unit`, numbers in that fixed SI unit, as number() takes one.
  std::vector<double> numbers(const std::string& key, std::size_t expected_size, std::optional<Quantity> unit = {},
                              const char* example = "") {
    const toml::node& n = require(key);
    const toml::array* a = n.as_array();
    if (!a) fail(key, "expected an array of numbers");
    if (expected_size && a->size() != expected_size)
      fail(key, "expected " + std::to_string(expected_size) + " numbers");
    std::vector<double> out;
    for (const auto& e : *a) {
      if (!e.is_number())
        fail(key, "expected an array of numbers" + (unit && e.is_string() ? no_unit(key, n, *unit, example) : ""));
      const double v = *e.value<double>();
      if (!std::isfinite(v)) fail(key, "expected finite numbers");
      out.push_back(v);
    }
    return out;
  }
  const toml::table* subtable(const std::string& key) {
    const toml::node* n = find(key);
    if (!n) return nullptr;
    if (!n->is_table()) fail(key, "expected a table [" + full(key) + "]");
    return n->as_table();
  }

  // Every key not read is an error: a misspelt key must not silently fall back to a default.
  void reject_unknown_keys() const {
    for (const auto& [key, value] : table_) {
      const std::string k(key.str());
      if (used_.count(k)) continue;
      std::string known;
      for (const auto& u : used_) known += (known.empty() ? "" : ", ") + u;
      // A key of the file has its line; one that --set put there has none (as in described()).
      const std::string where = file_ + (value.source().begin.line > 0 ? ":" + std::to_string(value.source().begin.line)
                                                                       : std::string(", --set"));
      throw Error(where + ": unknown key '" + clipped(full(key_text(k))) + "' = " + clipped(node_text(value)) + " (known here: " + known + ")");
    }
  }

  // `value` as read; its key noted when it is the default.
  template <typename T>
  T noted(const std::string& key, T value, const T& fallback) {
    if (written_defaults_ && value == fallback) written_defaults_->push_back(full(key));
    return value;
  }

private:

  const toml::table& table_;
  std::string prefix_;
  const std::string& file_;
  std::vector<std::string>* written_defaults_;
  std::set<std::string> used_;
};

RegionSpec read_region(TableReader& r, bool allow_missing) {
  RegionSpec region;
  const bool has_set = r.has("set"), has_box = r.has("box"), has_nearest = r.has("nearest");
  region.where = r.location(has_nearest ? "nearest" : has_box ? "box" : "set");
  if (has_set + has_box + has_nearest > 1)
    r.fail(has_nearest ? "nearest" : "box", "give one of 'set', 'box' and 'nearest', not several");
  if (has_nearest) {
    const auto point = r.numbers("nearest", 2, Quantity::length, "[0.01, 0.02]");
    region.has_nearest = true;
    region.nearest = {point[0], point[1]};
  } else if (has_set) {
    region.set = r.string("set");
    if (region.set.empty()) r.fail("set", "expected a set name");
    if (const std::string note = control_character_note(region.set); !note.empty())
      r.fail("set", "a set name must not hold a control character" + note +
                        "; the particle file's sets are named without them");
  } else if (has_box) {
    const auto b = r.numbers("box", 4, Quantity::length, "[0, 0, 0.01, 0.001]");
    if (!(b[2] >= b[0] && b[3] >= b[1])) r.fail("box", "expected [xmin, ymin, xmax, ymax] with xmin <= xmax, ymin <= ymax");
    region.has_box = true;
    std::copy(b.begin(), b.end(), region.box.begin());
  } else if (!allow_missing) {
    throw Error(r.source() + ": missing key '" + r.full("set") +
                "': give 'set' (a boundary set name or \"all\"), 'box' or 'nearest'");
  }
  return region;
}

TimeFunction read_time_function(TableReader& r, TimeFunction::Kind fallback_kind) {
  TimeFunction f;
  f.kind = fallback_kind;
  if (r.has("ramp_time") && r.has("table")) r.fail("table", "give either 'ramp_time' or 'table', not both");
  if (r.has("ramp_time")) {
    f.kind = TimeFunction::Kind::ramp;
    f.ramp_time = r.quantity("ramp_time", Quantity::time);
  } else if (r.has("table")) {
    f.kind = TimeFunction::Kind::table;
    const toml::array* rows = r.require("table").as_array();
    if (!rows || rows->empty()) r.fail("table", "expected [[t0, f0], [t1, f1], ...] with t in s");
    double last_t = -INFINITY;
    for (const auto& row : *rows) {
      const toml::array* pair = row.as_array();
      if (!pair || pair->size() != 2 || !(*pair)[0].is_number() || !(*pair)[1].is_number())
        r.fail("table", "expected [[t0, f0], [t1, f1], ...] with t in s");
      const double t = *(*pair)[0].value<double>(), v = *(*pair)[1].value<double>();
      if (!std::isfinite(t) || !std::isfinite(v)) r.fail("table", "expected finite values");
      if (!(t > last_t)) r.fail("table", "times must increase strictly");
      last_t = t;
      f.table.emplace_back(t, v);
    }
  }
  return f;
}

// The name a load without a `name` goes by: its set, else load<k>.
std::string unnamed_load_name(const toml::table& load, std::size_t index) {
  if (const auto set = load["set"].value<std::string>()) return *set;
  return "load" + std::to_string(index);
}

// The name a load goes by (docs/scenes.md): its `name`, else unnamed_load_name.
std::string load_name(const toml::table& load, std::size_t index) {
  if (const auto name = load["name"].value<std::string>()) return *name;
  return unnamed_load_name(load, index);
}

// A load component: a number (uniform), or an inline table for a value that
// varies linearly with position, { value = v, gradient = [gx, gy], at = [x, y] }
// (at defaults to [0, 0]) or { from = [x0, y0], to = [x1, y1], values = [v0, v1] }
// (v0 at `from`, v1 at `to`, linear along the line through them, constant across it).
void read_component(TableReader& r, const std::string& key, bool may_vary, double& value,
                    LinearVariation& variation) {
  const toml::node& n = r.require(key);
  if (n.is_number()) {
    value = r.number(key, n);
    return;
  }
  const toml::table* t = n.as_table();
  if (!t)
    r.fail(key, "expected a number, or for a value that varies linearly with position "
                "{ value = ..., gradient = [d/dx, d/dy], at = [x, y] } or "
                "{ from = [x0, y0], to = [x1, y1], values = [v0, v1] }");
  if (!may_vary) r.fail(key, "a value that varies with position is available for velocity, displacement and "
                             "initial_velocity loads only");
  TableReader c = r.sub(*t, r.full(key));
  const bool two_points = c.has("from") || c.has("to") || c.has("values");
  if (two_points && (c.has("value") || c.has("gradient") || c.has("at")))
    r.fail(key, "give either { value, gradient, at } or { from, to, values }, not a mix");
  if (two_points) {
    const auto from = c.numbers("from", 2, Quantity::length, "[0, 0]"), to = c.numbers("to", 2, Quantity::length, "[0.01, 0]"),
               values = c.numbers("values", 2);
    const Vec2 start{from[0], from[1]}, direction = Vec2{to[0], to[1]} - start;
    const double length_squared = dot(direction, direction);
    if (!(length_squared > 0)) c.fail("to", "expected a point different from 'from'");
    value = values[0];
    variation.origin = start;
    variation.gradient = ((values[1] - values[0]) / length_squared) * direction;
    variation.written_points = {{c.full("from"), start}, {c.full("to"), Vec2{to[0], to[1]}}};
  } else {
    value = c.number("value", c.require("value"));
    const auto gradient = c.numbers("gradient", 2);
    variation.gradient = {gradient[0], gradient[1]};
    if (c.has("at")) {
      const auto at = c.numbers("at", 2, Quantity::length, "[0.025, 0.01]");
      variation.origin = {at[0], at[1]};
      variation.written_points = {{c.full("at"), variation.origin}};
    }
  }
  c.reject_unknown_keys();
}

LoadSpec read_load(const TableReader& top, const toml::table& t, std::size_t index, bool switching) {
  TableReader r = top.sub(t, "loads[" + std::to_string(index) + "]");
  LoadSpec load;
  load.file_index = static_cast<long>(index);
  // In a scene that switches from quasi-static to dynamic every load says which part it belongs to.
  if (r.has("phase")) {
    if (!switching)
      r.fail("phase", "only in a scene that switches from quasi-static to dynamic (quasi_static.then = \"dynamic\")");
    const std::string phase = r.string("phase");
    if (phase == "quasi_static") load.phase = LoadPhase::quasi_static;
    else if (phase == "dynamic") load.phase = LoadPhase::dynamic;
    else r.fail("phase", "expected \"quasi_static\" or \"dynamic\"");
  } else if (switching) {
    throw Error(r.source() + ": missing key 'loads[" + std::to_string(index) +
                "].phase': quasi_static.then = \"dynamic\" needs \"quasi_static\" or \"dynamic\" on every load");
  }
  const std::string type = r.string("type");
  if (type == "velocity") load.kind = LoadKind::velocity;
  else if (type == "displacement") load.kind = LoadKind::displacement;
  else if (type == "fixed") load.kind = LoadKind::fixed;
  else if (type == "traction") load.kind = LoadKind::traction;
  else if (type == "initial_velocity") load.kind = LoadKind::initial_velocity;
  else r.fail("type", "expected one of \"velocity\", \"displacement\", \"fixed\", \"traction\", \"initial_velocity\"");
  load.region = read_region(r, false);
  // A name is the restart key's (it heads energy.csv's columns, whose rows
  // before a checkpoint were written under it); one equal to the name the
  // load has without it is that load's default, and left out.
  load.name = r.string_or("name", unnamed_load_name(t, index));
  // The name heads CSV columns (energy.csv: reaction_x_<name>_N; load_steps.csv: <name>_reaction_x_N).
  if (load.name.empty() || load.name.find_first_of(",\"") != std::string::npos ||
      std::any_of(load.name.begin(), load.name.end(), is_control)) {
    const std::string from = r.has("name") ? "name" : "set";
    r.fail(from, "a load's name heads the reaction columns of the CSV files: it must not be empty nor hold a comma, "
                 "quote or control character (tab, line break, NUL, ...)" + control_character_note(load.name) +
                     std::string(from == "set" ? " (give the load a 'name' of its own)" : ""));
  }
  if (load.kind == LoadKind::fixed) {
    load.has_x = load.has_y = true;  // both components held at zero displacement
  } else {
    load.has_x = r.has("x");
    load.has_y = r.has("y");
    const bool may_vary = load.kind != LoadKind::traction;
    if (load.has_x) read_component(r, "x", may_vary, load.x, load.x_variation);
    if (load.has_y) read_component(r, "y", may_vary, load.y, load.y_variation);
    if (!load.has_x && !load.has_y)
      throw Error(r.source() + ": loads[" + std::to_string(index) + "] (" + type + "): give at least one of 'x', 'y'");
  }
  if (load.kind == LoadKind::velocity || load.kind == LoadKind::displacement || load.kind == LoadKind::traction)
    load.time_function = read_time_function(r, TimeFunction::Kind::constant);
  if (load.kind == LoadKind::traction) load.edge_length = r.positive_or("edge_length", 0);
  r.reject_unknown_keys();
  return load;
}

// [quasi_static]: the load steps as an explicit list of cumulative load
// factors (`load_factors`) or as runs of equal increments (`increments`,
// [[count, increment], ...] starting from 0), and the minimiser's settings.
QuasiStaticSpec read_quasi_static(const TableReader& top, const toml::table& t) {
  const std::string& path = top.file();
  TableReader r = top.sub(t, "quasi_static");
  QuasiStaticSpec q;
  q.enabled = true;
  const bool has_list = r.has("load_factors"), has_increments = r.has("increments");
  if (has_list == has_increments) {
    std::string both;
    // Both given, one by --set: a --set adds a key and cannot remove the
    // scene's other one (before 7 December 2026 the refusal did not say
    // where each came from).
    if (has_list) {
      const bool list_set = r.location("load_factors") == path + ", --set";
      const bool increments_set = r.location("increments") == path + ", --set";
      const auto where = [&](const std::string& key, bool set) { return set ? "by --set" : "at " + r.location(key); };
      both = ": both are given, 'load_factors' " + where("load_factors", list_set) + " and 'increments' " +
             where("increments", increments_set);
      if (list_set != increments_set)
        both += "; --set cannot remove the scene's key: give the load steps with it (--set 'quasi_static." +
                std::string(list_set ? "increments" : "load_factors") + "=...'), or edit the scene";
    }
    throw Error(path + ": [quasi_static]: give exactly one of 'load_factors' (a list of load factors) or "
                "'increments' ([[count, increment], ...])" + both);
  }
  q.load_steps_key = has_list ? "load_factors" : "increments";
  if (has_list) {
    q.load_factors = r.numbers("load_factors", 0);
    if (q.load_factors.empty()) r.fail("load_factors", "expected at least one load factor");
  } else {
    const toml::array* rows = r.require("increments").as_array();
    if (!rows || rows->empty()) r.fail("increments", "expected [[count, increment], ...]");
    double row_start = 0;  // the factor the row before ended at
    std::size_t row_number = 0;
    for (const auto& row : *rows) {
      ++row_number;
      const toml::array* pair = row.as_array();
      if (!pair || pair->size() != 2 || !(*pair)[0].is_integer() || !(*pair)[1].is_number())
        r.fail("increments", "expected [[count, increment], ...] with a whole count");
      const auto count = *(*pair)[0].value<std::int64_t>();
      const double increment = *(*pair)[1].value<double>();
      if (count < 1 || count > 10000000) r.fail("increments", "expected counts between 1 and 1e7");
      if (!std::isfinite(increment) || increment == 0) r.fail("increments", "expected finite, non-zero increments");
      // The rows together, as one row is: each load step's factor is kept
      // before the plan's limits are checked, and a hundred rows of 1e7 took
      // 8 GB first (before 7 December 2026).
      if (static_cast<std::int64_t>(q.load_factors.size()) + count > 10000000)
        r.fail("increments", "the rows add up to more than 1e7 load steps (" +
                                 std::to_string(static_cast<std::int64_t>(q.load_factors.size()) + count) +
                                 " by row " + std::to_string(row_number) + "); expected at most 1e7 in all");
      // Each factor from its row's start and its place in the row, not by
      // summing: 20000 increments of 1e-6 end at 0.02, as written, where a
      // running sum ended at 0.019999999999999348 (before 7 December 2026).
      for (std::int64_t k = 1; k <= count; ++k)
        q.load_factors.push_back(row_start + static_cast<double>(k) * increment);
      row_start = q.load_factors.back();
    }
  }
  for (double f : q.load_factors)
    if (!std::isfinite(f)) r.fail(has_list ? "load_factors" : "increments", "expected finite load factors");
  // Loads times 0 at every step: the run would compute the unloaded plate
  // and end as a success (before 7 December 2026).
  if (std::all_of(q.load_factors.begin(), q.load_factors.end(), [](double f) { return f == 0; }))
    r.fail("load_factors", "every load factor is 0: the loads would never act, and the run would compute the "
                           "unloaded plate; give the factors that scale the loads, e.g. [0.5, 1.0]");
  q.tolerance = r.positive_or("tolerance", 1e-6);
  if (q.tolerance >= 1) r.fail("tolerance", "expected a relative residual below 1");
  // The residual is a sum of forces rounded at about 1e-16 of them: below
  // that no minimisation converges, and each ran to max_iterations (before 7
  // December 2026, the message then advising more).
  if (q.tolerance < std::numeric_limits<double>::epsilon())
    r.fail("tolerance", "below the round-off of double arithmetic (2.2e-16), which no minimisation can reach; "
                        "expected a relative residual from 2.2e-16 to below 1, e.g. 1e-10");
  // (A count below 1 was told "a number of steps >= 0", though 0 is refused
  // too and these are iterations and rounds; before 7 December 2026.)
  q.max_iterations = r.whole_or("max_iterations", 20000, "iterations", 1);
  const std::string on_failure = r.string_or("on_nonconvergence", "error");
  if (on_failure == "warn") q.warn_on_nonconvergence = true;
  else if (on_failure != "error") r.fail("on_nonconvergence", "expected \"error\" or \"warn\"");
  q.max_breaking_rounds = r.whole_or("max_breaking_rounds", 1000, "rounds", 1);
  q.stop_reaction_fraction = r.real_or("stop_reaction_fraction", 0);
  if (!(q.stop_reaction_fraction >= 0 && q.stop_reaction_fraction < 1))
    r.fail("stop_reaction_fraction", "expected a fraction in [0, 1)");
  if (r.has("then")) {
    if (r.string("then") != "dynamic") r.fail("then", "expected \"dynamic\" (continue with [time] from the last equilibrium)");
    q.then_dynamic = true;
  }
  const std::string kernels = r.string_or("kernels", "lists");
  if (kernels == "lattice") q.lattice_kernels = true;
  else if (kernels != "lists") r.fail("kernels", "expected \"lists\" or \"lattice\"");
  if (q.lattice_kernels && q.then_dynamic)
    r.fail("kernels", "\"lattice\" does not hand its bond states to a dynamic part yet: use \"lists\" with then = \"dynamic\"");
  q.coarse_correction = r.boolean_or("coarse_correction", true);
  q.damped_rounds = r.boolean_or("damped_rounds", true);
  q.progress_interval = r.real_or("progress_interval", 10, Quantity::time, "10");
  if (!(q.progress_interval >= 0)) r.fail("progress_interval", "expected seconds >= 0");
  r.reject_unknown_keys();
  return q;
}

// Keys of [quasi_static] that the scene's other choices leave without
// effect, given all the same (before 7 December 2026 taken without a word):
// the lattice kernels' settings on the energy table, the re-equilibrations
// after bond breaking without damage. The plan's warnings, one per key.
std::vector<std::string> inert_quasi_static_keys(const TableReader& top, const toml::table& t,
                                                 const QuasiStaticSpec& q, bool damage) {
  TableReader r = top.sub(t, "quasi_static");
  std::vector<std::string> warnings;
  const std::pair<const char*, const char*> lattice_only[] = {
      {"coarse_correction", "the coarse-space correction of the lattice kernels' preconditioner"},
      {"damped_rounds", "the lattice kernels' damped Newton rounds after a dropped round"}};
  if (!q.lattice_kernels)
    for (const auto& [key, what] : lattice_only)
      if (r.has(key))
        warnings.push_back(r.described(key) + " has no effect with quasi_static.kernels = \"lists\": it sets " +
                           what + "; leave it out, or set kernels = \"lattice\"");
  if (!damage && r.has("max_breaking_rounds"))
    warnings.push_back(r.described("max_breaking_rounds") +
                       " has no effect with effects.damage = false: no bond breaks, so no load step "
                       "re-equilibrates; leave it out, or turn damage on");
  return warnings;
}

// Quasi-static loads are multiplied by the load factor: only displacements,
// fixed supports and tractions have a meaning there, without a time function.
void check_quasi_static_load(const LoadSpec& load, const toml::table& t, std::size_t index, const std::string& path) {
  TableReader r(t, "loads[" + std::to_string(index) + "]", path);
  if (load.kind == LoadKind::velocity || load.kind == LoadKind::initial_velocity)
    r.fail("type", "not available in quasi-static mode (use \"displacement\", \"fixed\" or \"traction\")");
  if (r.has("ramp_time")) r.fail("ramp_time", "not available in quasi-static mode: the load steps scale the load");
  if (r.has("table")) r.fail("table", "not available in quasi-static mode: the load steps scale the load");
}

// The entry of an array of tables ([[loads]], [[precracks]]) that one part of
// a --set key selects: an index, or for loads a name (the load's name, else a
// load whose set it is). The error lists what exists.
toml::table& select_entry(toml::array& entries, const std::string& array_key, const std::string& selector,
                          const std::string& assignment, const std::string& file) {
  const bool named = array_key == "loads";
  std::vector<std::size_t> matches;
  if (!selector.empty() && std::all_of(selector.begin(), selector.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    const std::size_t index = selector.size() > 9 ? entries.size() : std::stoul(selector);
    if (index < entries.size()) matches.push_back(index);
  } else if (named) {
    for (std::size_t k = 0; k < entries.size(); ++k)
      if (const toml::table* t = entries[k].as_table(); t && load_name(*t, k) == selector) matches.push_back(k);
    if (matches.empty())
      for (std::size_t k = 0; k < entries.size(); ++k)
        if (const toml::table* t = entries[k].as_table(); t && (*t)["set"].value<std::string>() == selector)
          matches.push_back(k);
  }
  std::string known;
  for (std::size_t k = 0; k < entries.size(); ++k) {
    known += (known.empty() ? "" : ", ") + std::to_string(k);
    const toml::table* t = entries[k].as_table();
    if (named && t) known += " (" + in_quotes(load_name(*t, k)) + ")";
  }
  const std::string prefix = file + ": --set '" + assignment + "': ";
  if (matches.size() > 1) {
    std::string which;
    for (auto k : matches) {
      which += (which.empty() ? "" : " and ") + std::to_string(k);
      // What tells them apart: the type, and the phase of a switching scene.
      if (const toml::table* t = entries[k].as_table(); named && t) {
        const auto type = (*t)["type"].value<std::string>();
        const auto phase = (*t)["phase"].value<std::string>();
        if (type || phase)
          which += " (" + type.value_or("") + (type && phase ? ", " : "") + (phase ? "phase " + *phase : "") + ")";
      }
    }
    throw Error(prefix + "'" + selector + "' names more than one entry of [[" + array_key + "]] (" + which +
                "); address one by index (" + array_key + "." + std::to_string(matches.front()) + ".KEY)");
  }
  if (matches.empty())
    throw Error(prefix + "no entry '" + selector + "' in [[" + array_key + "]] (" +
                (entries.empty() ? std::string("the scene has none")
                                 : std::string("the scene has ") + (entries.size() == 1 ? "entry " : "entries ") + known) +
                "); address one by " +
                (named ? "index or name (" + array_key + ".0.KEY, " + array_key + ".NAME.KEY)"
                       : "index (" + array_key + ".0.KEY)"));
  toml::table* entry = entries[matches.front()].as_table();
  if (!entry) throw Error(prefix + "'" + array_key + "' is not an array of tables [[" + array_key + "]]");
  return *entry;
}

// Loads that act together (all, or one part of a switching scene) need
// different names: each names its columns of energy.csv.
void check_load_names(const std::vector<LoadSpec>& loads, const std::string& path) {
  for (std::size_t a = 0; a < loads.size(); ++a)
    for (std::size_t b = a + 1; b < loads.size(); ++b)
      if (loads[a].name == loads[b].name && loads[a].phase == loads[b].phase)
        throw Error(path + ": loads[" + std::to_string(a) + "] and loads[" + std::to_string(b) + "] are both named '" +
                    loads[a].name + "' (a load's name labels its energy.csv columns and its reactions): give one "
                    "of them another 'name'");
}

// The key an override wrote, as written ("loads.top.y") and as the value it
// reaches ("loads[0].y", an entry of an array of tables by its index).
struct OverrideKey {
  std::string written;
  std::string reached;
};

// Puts "a.b.c = value" into the table, creating tables on the way; a part
// after the name of an array of tables selects one entry (select_entry).
OverrideKey apply_override(toml::table& root, const std::string& assignment, const std::string& file) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw Error(file + ": --set '" + assignment + "': expected section.key=value");
  const std::string key = assignment.substr(0, eq);
  const std::string value = assignment.substr(eq + 1);
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + value);
  } catch (const toml::parse_error&) {
    // Digits alone that TOML cannot read: a whole number beyond 64 bits (not
    // a bare word to take as a string, which then "has no unit").
    const std::string digits = value.substr(value.find_first_not_of("+-") == std::string::npos
                                                ? value.size()
                                                : value.find_first_not_of("+-"));
    if (!digits.empty() && value.find_first_not_of("+-") <= 1 &&
        digits.find_first_not_of("0123456789_") == std::string::npos)
      throw Error(file + ": --set '" + clipped(assignment) + "': " + clipped(value) +
                  " is a whole number beyond the 64 bits TOML reads; write it as a float (with a decimal point or "
                  "an exponent)");
    // A bare word: take it as a string, without the blanks around it, as
    // in a TOML line (--set 'particles = plate.pdp'). A name that holds
    // them is given quoted, as TOML writes it: --set "particles=' plate.pdp'".
    const auto first = value.find_first_not_of(" \t"), last = value.find_last_not_of(" \t");
    parsed = toml::table{};
    parsed.insert("v", first == std::string::npos ? std::string() : value.substr(first, last - first + 1));
  }
  // A line break in the value starts a line of TOML of its own, which the
  // key would drop: "1e-6\nstep=1" set time.end alone (before 7 December 2026).
  if (parsed.size() != 1)
    throw Error(file + ": --set " + in_quotes(clipped(assignment)) + ": the value " + in_quotes(clipped(value)) +
                " holds more than one TOML key-value pair (a line break in it?); give one value per --set");
  const std::string prefix = file + ": --set '" + assignment + "': ";
  // Split at every dot, empty parts kept: ".end", "time..end" and "time." are
  // typing slips to name, not a table '' to make.
  std::vector<std::string> parts(1);
  for (char c : key) {
    if (c == '.') parts.emplace_back();
    else parts.back() += c;
  }
  // Blanks around the parts, as TOML allows around a dotted key's dots and
  // before its '=' ("time.end = 1e-6"; before 7 December 2026 an unknown key
  // 'time.'end '' was made).
  std::string written;
  for (auto& part : parts) {
    const auto first = part.find_first_not_of(" \t"), last = part.find_last_not_of(" \t");
    part = first == std::string::npos ? std::string() : part.substr(first, last - first + 1);
    written += (written.empty() ? "" : ".") + part;
  }
  for (const auto& part : parts)
    if (part.empty())
      throw Error(prefix + "the key '" + key + "' has an empty part (a dot at its start or end, or two dots); "
                  "expected section.key=value, e.g. time.end=1e-6");
  toml::table* t = &root;
  std::string reached;
  for (std::size_t k = 0; k + 1 < parts.size(); ++k) {
    reached += (reached.empty() ? "" : ".") + parts[k];
    toml::node* n = t->get(parts[k]);
    if (!n && t == &root && (parts[k] == "loads" || parts[k] == "precracks"))
      throw Error(prefix + "the scene has no [[" + parts[k] + "]] (give the whole array instead, e.g. --set '" +
                  parts[k] + (parts[k] == "loads" ? "=[{set = \"top\", type = \"velocity\", y = 0.3}]'"
                                                  : "=[{from = [0, 0.0125], to = [0.002, 0.0125]}]'") +
                  ")");
    if (!n) n = &t->insert_or_assign(parts[k], toml::table{}).first->second;
    if (toml::array* entries = n->as_array()) {
      if (k + 2 >= parts.size())
        throw Error(prefix + "name a key of one entry of '" + parts[k] + "', e.g. " + parts[k] + ".0.KEY=value");
      t = &select_entry(*entries, parts[k], parts[k + 1], assignment, file);
      for (std::size_t index = 0; index < entries->size(); ++index)
        if ((*entries)[index].as_table() == t) reached += "[" + std::to_string(index) + "]";
      ++k;  // the selector is used up
      continue;
    }
    if (!n->is_table()) throw Error(prefix + "'" + parts[k] + "' is not a table");
    t = n->as_table();
  }
  parsed.get("v")->visit([&](const auto& node) { t->insert_or_assign(parts.back(), node); });
  return {written, reached + (reached.empty() ? "" : ".") + parts.back()};
}

// Replaces each value of `root` written with a unit (TableReader::quantity;
// already read and checked) by its SI number.
void write_quantities_in_si(toml::table& root) {
  const auto in_si = [](toml::table* table, const char* key, Quantity kind) {
    if (!table) return;
    const toml::node* n = table->get(key);
    if (!n || !n->is_string() || *n->value<std::string>() == "auto") return;
    table->insert_or_assign(key, parse_quantity(*n->value<std::string>(), kind, key));
  };
  toml::table* material = root["material"].as_table();
  in_si(material, "youngs_modulus", Quantity::stress);
  in_si(material, "density", Quantity::density);
  in_si(material, "fracture_energy", Quantity::energy_per_area);
  in_si(material, "thickness", Quantity::length);
  toml::table* time = root["time"].as_table();
  in_si(time, "step", Quantity::time);
  in_si(time, "end", Quantity::time);
  if (toml::array* loads = root["loads"].as_array())
    for (auto& load : *loads) in_si(load.as_table(), "ramp_time", Quantity::time);
}

Scene build_scene(toml::table& root, const std::string& path, const std::vector<std::string>& overrides) {
  std::set<std::string> set_keys;  // as written: "time.step", "loads.top.y"
  std::vector<OverrideKey> applied;
  for (const auto& o : overrides) {
    const OverrideKey key = apply_override(root, o, path);
    // The same key set twice: one of the values would be dropped without a
    // word (before the second sitting of 5 December 2026 the last won). Also
    // when written two ways (loads.0.y and loads.top.y, one load), or when a
    // later --set replaces the table or array an earlier one set a key of
    // (before 7 December 2026 the last won there).
    for (const OverrideKey& earlier : applied) {
      if (earlier.reached == key.reached)
        throw Error(path + ", --set: key '" + clipped(key.written) + "' is set twice" +
                    (earlier.written == key.written
                         ? std::string()
                         : " (as '" + clipped(earlier.written) + "' and '" + clipped(key.written) + "', both " +
                               clipped(key.reached) + ")") +
                    "; give it once");
      const std::string& inner = earlier.reached;
      if (inner.size() > key.reached.size() && inner.compare(0, key.reached.size(), key.reached) == 0 &&
          (inner[key.reached.size()] == '.' || inner[key.reached.size()] == '['))
        throw Error(path + ", --set: key '" + clipped(key.written) + "' replaces the whole of '" +
                    clipped(key.reached) + "', dropping the earlier --set of '" + clipped(earlier.written) +
                    "'; give '" + clipped(key.written) + "' first, or that key inside its value");
    }
    applied.push_back(key);
    set_keys.insert(key.written);
  }
  const bool particles_from_command_line = set_keys.count("particles") > 0;
  Scene scene;
  scene.path = path;
  scene.set_keys = std::move(set_keys);
  std::vector<std::string> written_defaults;  // left out of the restart key
  TableReader top(root, "", path, &written_defaults);

  // A relative particle path is relative to the scene file's folder, or, given
  // with --set particles=..., to the working directory (as any command-line path).
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  const std::string particles = top.string("particles");
  if (particles.empty()) top.fail("particles", "expected the particle file's path (written by pd-mesh)");
  if (const std::string note = control_character_note(particles); !note.empty())
    top.fail("particles", "a path must not hold a control character" + note +
                              ": the system reads a path only up to a NUL (another file would be opened), and the "
                              "others are typing slips; write the particle file's path without it");
  const toml::table* quasi_static_table = top.subtable("quasi_static");
  scene.particles_as_written = particles;
  scene.particle_file = std::filesystem::path(particles).is_absolute() || particles_from_command_line
                            ? particles
                            : (folder / particles).string();
  if (quasi_static_table) scene.quasi_static = read_quasi_static(top, *quasi_static_table);
  // A scene that is quasi-static only has no time integration; one that switches has both parts.
  const bool quasi_static_only = quasi_static_table && !scene.quasi_static.then_dynamic;

  // [model] first: the model decides which material keys are required.
  if (const toml::table* t = top.subtable("model")) {
    TableReader r = top.sub(*t, "model");
    const std::string type = r.string_or("type", "pmb");
    std::string known;
    bool found = false;
    for (const auto& m : models) {
      known += std::string(known.empty() ? "" : ", ") + "\"" + m.name + "\"";
      if (type == m.name) scene.model = m.type, found = true;
    }
    if (!found && (type == "lps" || type == "dual_horizon"))
      r.fail("type", "not implemented yet (available: " + known + ")");
    if (!found) r.fail("type", "expected one of " + known);
    const std::string weights = r.string_or("bond_weights", "distance_moment");
    if (weights == "distance_moment") scene.bond_weights = BondWeights::distance_moment;
    else if (weights == "partial_volume") scene.bond_weights = BondWeights::partial_volume;
    else r.fail("bond_weights", "expected \"distance_moment\" or \"partial_volume\"");
    if (r.has("osb_failure")) {
      // What a broken bond leaves in OSB (theory.md Sec. 5.8): a state-based
      // choice, meaningless for a bond-based model.
      if (scene.model != ModelType::osb)
        r.fail("osb_failure", "only for model.type = \"osb\" (a bond-based model has no dilatation)");
      const std::string failure = r.string("osb_failure");
      std::string expected;
      bool known_failure = false;
      for (const auto& f : osb_failures) {
        expected += std::string(expected.empty() ? "" : ", ") + "\"" + f.name + "\"";
        if (failure == f.name) scene.osb_failure = f.failure, known_failure = true;
      }
      if (!known_failure) r.fail("osb_failure", "expected one of " + expected);
      // Written with the default variant, it is the scene that leaves it out
      // (the restart key; before 7 December 2026 such a restart was refused).
      r.noted("osb_failure", scene.osb_failure, Scene{}.osb_failure);
    }
    if (r.has("dual_horizon")) scene.dual_horizon = r.boolean_or("dual_horizon", false);
    r.reject_unknown_keys();
  }
  if (scene.quasi_static.lattice_kernels && scene.model != ModelType::pmb)
    throw Error(path + ": quasi_static.kernels = \"lattice\" is available for model.type = \"pmb\" only "
                "(use kernels = \"lists\")");
  if (const toml::table* t = top.subtable("effects")) {
    TableReader r = top.sub(*t, "effects");
    scene.effects.damage = r.boolean_or("damage", true);
    scene.effects.surface_correction = r.boolean_or("surface_correction", false);
    r.reject_unknown_keys();
  }
  if (quasi_static_table)
    scene.quasi_static.inert_keys =
        inert_quasi_static_keys(top, *quasi_static_table, scene.quasi_static, scene.effects.damage);
  {
    const toml::table* t = top.subtable("material");
    if (!t) throw Error(path + ": missing required table [material]" + misspelt_hint(root, "material"));
    TableReader r = top.sub(*t, "material");
    auto& m = scene.material;
    m.youngs_modulus = r.quantity("youngs_modulus", Quantity::stress);
    // The density only enters the dynamic equation of motion; a quasi-static scene may omit it.
    m.density = quasi_static_only && !r.has("density") ? 0.0 : r.quantity("density", Quantity::density);
    // The fracture energy only decides when bonds break: a scene without damage may omit it.
    m.fracture_energy = !scene.effects.damage && !r.has("fracture_energy")
                            ? 0.0
                            : r.quantity("fracture_energy", Quantity::energy_per_area);
    m.thickness = r.quantity_or("thickness", Quantity::length, 1.0);
    const std::string plane = r.string_or("plane", "stress");
    if (plane == "stress") m.plane = PlaneKind::stress;
    else if (plane == "strain") m.plane = PlaneKind::strain;
    else r.fail("plane", "expected \"stress\" or \"strain\"");
    if (scene.model == ModelType::osb) {
      // The 2D OSB model takes nu from the material (theory.md Sec. 5); its 2D
      // bulk modulus is finite and positive for 0 < nu < 0.5 in plane stress and strain.
      if (!r.has("poisson_ratio"))
        throw Error(path + ": missing key 'material.poisson_ratio': required by model.type = \"osb\" "
                           "(a value in (0, 0.5), plane stress and plane strain)");
      m.poisson_ratio = r.number("poisson_ratio", *r.find("poisson_ratio"));
      if (!(m.poisson_ratio > 0 && m.poisson_ratio < 0.5))
        r.fail("poisson_ratio", "model.type = \"osb\" (2D, plane " + std::string(to_string(m.plane)) +
                                    ") needs a value in (0, 0.5)");
    } else if (r.has("poisson_ratio")) {
      m.poisson_ratio = r.positive("poisson_ratio");
      if (m.poisson_ratio >= 0.5) r.fail("poisson_ratio", "expected a value in (0, 0.5)");
    }
    r.reject_unknown_keys();
  }
  if (quasi_static_only) {
    if (top.has("time"))
      top.fail("time", "a scene is either dynamic ([time]) or quasi-static ([quasi_static]), not both "
                       "(set quasi_static.then = \"dynamic\" to continue a quasi-static run dynamically)");
  } else {
    const toml::table* t = top.subtable("time");
    if (!t)
      throw Error(path + ": missing required table [time]" + misspelt_hint(root, "time") +
                  (quasi_static_table ? std::string(" (quasi_static.then = \"dynamic\" needs the time span of the dynamic part)")
                                      : std::string(" (or [quasi_static] for a quasi-static scene)")));
    TableReader r = top.sub(*t, "time");
    auto& time = scene.time;
    const toml::node& step = r.require("step");
    time.automatic = step.is_string() && *step.value<std::string>() == "auto";
    if (!time.automatic) {
      if (!step.is_number() && !step.is_string())
        r.fail("step", "expected a positive number [s], a time with its unit (\"20 ns\") or \"auto\"");
      try {
        time.step = r.quantity("step", Quantity::time);
      } catch (const Error& e) {
        throw Error(std::string(e.what()) + "; or \"auto\" for the stable step");
      }
    }
    time.safety = r.positive_or("safety", 0.8);
    if (time.safety > 1) r.fail("safety", "expected a fraction of the stable limit in (0, 1]");
    if (!time.automatic && r.has("safety")) r.fail("safety", "only used with step = \"auto\"");
    time.end = r.quantity("end", Quantity::time);
    time.force = r.boolean_or("force", false);
    // (safety with a fixed step is refused above; force with the automatic
    // step, which never exceeds the limit, would as silently do nothing.)
    if (time.automatic && time.force) r.fail("force", "only used with a fixed step above the stable limit, not with "
                                                      "step = \"auto\" (which stays below it)");
    r.reject_unknown_keys();
  }
  if (const toml::table* t = top.subtable("stop")) {
    TableReader r = top.sub(*t, "stop");
    scene.stop.enabled = true;
    scene.stop.region = read_region(r, false);
    scene.stop.damage = r.positive_or("damage", 0.35);
    if (scene.stop.damage > 1) r.fail("damage", "expected a damage in (0, 1]");
    // Without damage no particle ever reaches it: the run would go on to its end unstopped.
    if (!scene.effects.damage)
      r.fail("damage", "no particle is ever damaged with effects.damage = false: the stop condition could never "
                       "act; turn damage on, or leave [stop] out");
    r.reject_unknown_keys();
  }
  if (const toml::table* t = top.subtable("refinement")) {
    TableReader r = top.sub(*t, "refinement");
    auto& f = scene.refinement;
    f.enabled = true;
    if (r.source() != path)
      for (const auto& key : scene.set_keys)
        if (key.rfind("refinement", 0) == 0 && (key.size() == 10 || key[10] == '.'))
          f.made_by_set += (f.made_by_set.empty() ? "" : ", ") + key;
    f.damage_threshold = r.positive_or("damage_threshold", 0.4);
    if (f.damage_threshold >= 1) r.fail("damage_threshold", "expected a damage in (0, 1)");
    const std::string strain = r.string_or("strain", "bond");
    if (strain == "bond") f.strain = RefinementStrain::bond;
    else if (strain == "normal") f.strain = RefinementStrain::normal;
    else r.fail("strain", "expected \"bond\" (largest bond stretch) or \"normal\" (accumulated normal strain)");
    f.strain_fraction = r.positive_or("strain_fraction", default_strain_fraction(f.strain));
    if (f.strain_fraction > 1) r.fail("strain_fraction", "expected a fraction of the critical stretch in (0, 1]");
    f.lead_fraction = r.positive_or("lead_fraction", f.strain_fraction);
    if (f.lead_fraction > f.strain_fraction)
      r.fail("lead_fraction", "expected a fraction of the critical stretch at most strain_fraction (" +
                                  (std::ostringstream() << f.strain_fraction).str() + ")");
    const char* spread_expected =
        "expected \"family\" (the chosen particle's family splits with it), \"none\", or a distance in "
        "horizons in (0, 1] (the family members that near)";
    if (const toml::node* n = r.find("spread"); n && n->is_number()) {
      f.spread = RefinementSpread::within;
      f.spread_horizons = *n->value<double>();
      if (!(f.spread_horizons > 0 && f.spread_horizons <= 1)) r.fail("spread", spread_expected);
    } else if (n && !n->is_string()) {
      r.fail("spread", spread_expected);
    } else {
      const std::string spread = r.string_or("spread", "family");
      if (spread == "family") f.spread = RefinementSpread::family;
      else if (spread == "none") f.spread = RefinementSpread::none;
      else r.fail("spread", spread_expected);
    }
    f.levels = r.whole_or("levels", 1, "halvings", 1, 6);
    if (r.has("region")) {
      const auto b = r.numbers("region", 4, Quantity::length, "[0.045, 0, 0.1, 0.04]");
      if (!(b[2] > b[0] && b[3] > b[1])) r.fail("region", "expected [xmin, ymin, xmax, ymax] [m] with xmin < xmax, ymin < ymax");
      f.has_region = true;
      std::copy(b.begin(), b.end(), f.region.begin());
    }
    f.particle_budget = r.whole_or("particle_budget", 0, "particles");
    f.check_interval_defaulted = !r.has("check_interval");
    f.check_interval = r.whole_or("check_interval", 10, "steps", 1);
    r.reject_unknown_keys();
    // Children have half their parent's horizon: only dual-horizon PD keeps
    // such a set free of ghost forces and conserves momentum (theory.md Sec. 6).
    // Either of the two may come from --set: the message says which.
    if (!scene.dual_horizon.value_or(false)) {
      const std::string& made_by = f.made_by_set;
      const bool dual_from_set = scene.dual_horizon && scene.given_by_set("model.dual_horizon");
      throw Error(path + (made_by.empty() && !dual_from_set ? "" : ", --set") + ": [refinement]" +
                  (made_by.empty() ? "" : " (made by --set " + made_by + "; the scene has none)") +
                  " needs model.dual_horizon = true (children have half their parent's horizon; dual-horizon PD, "
                  "theory.md Sec. 6)" +
                  (scene.dual_horizon ? " (got false" + scene.from_set("model.dual_horizon") + ")"
                                      : std::string(" (not given)")) +
                  (made_by.empty() && !dual_from_set ? std::string() : "; give --set model.dual_horizon=true"));
    }
    if (scene.quasi_static.enabled)
      throw Error(path + ": [refinement] is available in dynamic runs only (found [quasi_static])");
  }
  if (const toml::node* n = top.find("loads")) {
    const toml::array* a = n->as_array();
    if (!a) top.fail("loads", "expected an array of tables [[loads]]");
    for (std::size_t k = 0; k < a->size(); ++k) {
      const toml::table* t = (*a)[k].as_table();
      if (!t) top.fail("loads", "expected an array of tables [[loads]]");
      scene.loads.push_back(read_load(top, *t, k, scene.quasi_static.then_dynamic));
      if (scene.quasi_static.enabled && scene.loads.back().phase != LoadPhase::dynamic)
        check_quasi_static_load(scene.loads.back(), *t, k, path);
    }
    check_load_names(scene.loads, path);
  }
  if (const toml::node* n = top.find("precracks")) {
    const toml::array* a = n->as_array();
    if (!a) top.fail("precracks", "expected an array of tables [[precracks]]");
    if (a->empty()) written_defaults.push_back("precracks");  // (precracks = []: none, as without the key)
    for (std::size_t k = 0; k < a->size(); ++k) {
      const toml::table* t = (*a)[k].as_table();
      if (!t) top.fail("precracks", "expected an array of tables [[precracks]]");
      TableReader r = top.sub(*t, "precracks[" + std::to_string(k) + "]");
      const auto from = r.numbers("from", 2, Quantity::length, "[0, 0.0125]"),
                 to = r.numbers("to", 2, Quantity::length, "[0.002, 0.0125]");
      if (from == to) r.fail("to", "the crack segment has zero length");
      // A crack given twice (or two collinear cracks that overlap) is cut as
      // one longer crack: the shared end points close each tip's gap.
      for (std::size_t j = 0; j < scene.precracks.size(); ++j) {
        const auto& other = scene.precracks[j];
        const double dx = other.to.x - other.from.x, dy = other.to.y - other.from.y, length = std::hypot(dx, dy);
        const auto off_line = [&](double x, double y) {
          return std::fabs(dx * (y - other.from.y) - dy * (x - other.from.x)) / length;  // distance from the line [m]
        };
        const auto along = [&](double x, double y) { return (dx * (x - other.from.x) + dy * (y - other.from.y)) / length; };
        // On its line within 1e-4 of its length (a copy written with a
        // rounded coordinate cuts the same bonds); overlapping by more than round-off.
        if (off_line(from[0], from[1]) > 1e-4 * length || off_line(to[0], to[1]) > 1e-4 * length) continue;
        const double lo = std::max(0.0, std::min(along(from[0], from[1]), along(to[0], to[1])));
        const double hi = std::min(length, std::max(along(from[0], from[1]), along(to[0], to[1])));
        if (hi - lo > 1e-9 * length) {
          std::ostringstream m;
          m << "the crack lies along precracks[" << j << "] over " << hi - lo
            << " m: a crack given twice, or two that overlap, is cut as one longer crack; give each crack once";
          r.fail("from", m.str());
        }
      }
      scene.precracks.push_back({{from[0], from[1]}, {to[0], to[1]}, r.location("from"), r.location("to")});
      r.reject_unknown_keys();
    }
  }
  if (const toml::table* t = top.subtable("output")) {
    TableReader r = top.sub(*t, "output");
    auto& o = scene.output;
    o.snapshot_interval = r.count_or("snapshot_interval", 0);
    if (const toml::node* n = r.find("energy_interval"); n && n->is_integer() && *n->value<std::int64_t>() <= 0)
      r.fail("energy_interval", "expected a positive whole number of steps (energy.csv needs rows)");
    o.energy_interval = r.count_or("energy_interval", 100);
    o.checkpoint_interval = r.count_or("checkpoint_interval", 0);
    if (r.has("damage_thresholds")) {
      o.damage_thresholds = r.noted("damage_thresholds", r.numbers("damage_thresholds", 0), o.damage_thresholds);
      if (o.damage_thresholds.empty()) r.fail("damage_thresholds", "expected at least one threshold");
      for (double d : o.damage_thresholds)
        if (!(d > 0 && d <= 1)) r.fail("damage_thresholds", "expected thresholds in (0, 1]");
      // Each names an array of arrival.vtp of its own (results::arrival_array_name).
      for (std::size_t a = 0; a < o.damage_thresholds.size(); ++a)
        for (std::size_t b = 0; b < a; ++b)
          if (o.damage_thresholds[a] == o.damage_thresholds[b])
            r.fail("damage_thresholds", "threshold " + shortest_text(o.damage_thresholds[a]) +
                                            " is given twice (each threshold is an array of arrival.vtp)");
    }
    r.reject_unknown_keys();
  }
  top.reject_unknown_keys();

  // Values written with a unit are kept as their SI numbers: the scene text
  // in summary.json and the restart key then do not depend on the spelling
  // ("3.24 GPa" and 3.24e9 are one scene).
  write_quantities_in_si(root);
  std::ostringstream canonical;
  canonical << root;
  scene.canonical_text = canonical.str();
  // The checkpoint key: a restart may extend a run, by its end time or (quasi-static only) by more load steps.
  // The particle file enters it by its content's hash (checkpoint_key), not
  // by its name: a file renamed or moved is the same particle set.
  toml::table without_end = root;
  without_end.erase("particles");
  if (toml::table* time = without_end["time"].as_table()) time->erase("end");
  if (toml::table* q = without_end["quasi_static"].as_table(); q && quasi_static_only) {
    q->erase("load_factors");
    q->erase("increments");
    q->erase("progress_interval");  // what the user sees, not what the run computes
  }
  // How often checkpoints are written changes no result (the strain energy a
  // checkpoint's step sums rides on its force evaluation, which it leaves as
  // it is): a restart may write them at another interval, or none. The other
  // output keys stay (docs/solver.md, "Safety"): the energy rows are where
  // the run checks its energy and keeps its roll-back state, the snapshot
  // series follows one interval, and the checkpoint holds the arrival times
  // of its damage thresholds (the energy interval for a dynamic part only).
  if (toml::table* output = without_end["output"].as_table()) {
    output->erase("checkpoint_interval");
    // Only time steps write energy rows: a quasi-static run never reads the
    // energy interval (a static-then-dynamic scene's dynamic part does).
    if (quasi_static_only) output->erase("energy_interval");
  }
  // A key written with its default value computes what its absence does.
  for (const std::string& name : written_defaults) {
    const auto dot = name.rfind('.');
    toml::table* parent = dot == std::string::npos ? &without_end
                                                   : without_end.at_path(name.substr(0, dot)).as_table();
    if (parent) parent->erase(dot == std::string::npos ? name : name.substr(dot + 1));
  }
  // So does a table of these left empty; [refinement], [stop] and
  // [quasi_static] ask for their effect by being there.
  for (const char* section : {"model", "effects", "output"})
    if (const toml::table* t = without_end[section].as_table(); t && t->empty()) without_end.erase(section);
  std::ostringstream key;
  key << without_end;
  scene.restart_key_text = key.str();
  scene.written_defaults = std::move(written_defaults);
  return scene;
}

}  // namespace

std::string RegionSpec::describe() const {
  std::ostringstream out;
  if (has_nearest) out << "the particle nearest to [" << nearest.x << ", " << nearest.y << "]";
  else if (has_box) out << "box [" << box[0] << ", " << box[1] << ", " << box[2] << ", " << box[3] << "]";
  else out << "set '" << set << "'";
  return out.str();
}

double TimeFunction::operator()(double t) const {
  switch (kind) {
    case Kind::constant: return 1.0;
    case Kind::ramp: return t >= ramp_time ? 1.0 : std::max(t, 0.0) / ramp_time;
    case Kind::table: {
      if (t <= table.front().first) return table.front().second;
      if (t >= table.back().first) return table.back().second;
      const auto upper = std::upper_bound(table.begin(), table.end(), t,
                                          [](double v, const auto& row) { return v < row.first; });
      const auto lower = upper - 1;
      const double w = (t - lower->first) / (upper->first - lower->first);
      return lower->second + w * (upper->second - lower->second);
    }
  }
  return 1.0;
}

const char* to_string(LoadKind kind) {
  switch (kind) {
    case LoadKind::velocity: return "velocity";
    case LoadKind::displacement: return "displacement";
    case LoadKind::fixed: return "fixed";
    case LoadKind::traction: return "traction";
    case LoadKind::initial_velocity: return "initial_velocity";
  }
  return "?";
}

std::string particles_white_space_check(const Scene& scene) {
  // (A --set path is read from the working directory, the file's from its folder.)
  const bool from_set = scene.set_keys.count("particles") > 0;
  return white_space_name_check(
      scene.particles_as_written, from_set ? "" : std::filesystem::path(scene.path).parent_path().string(),
      scene.source_of("particles") + ": key 'particles' = " + in_quotes(clipped(scene.particles_as_written)),
      [from_set](const std::string& name) {
        return from_set ? "--set particles=" + name : "particles = " + in_quotes(name);
      });
}

Scene parse_scene(const std::string& text, const std::string& path, const std::vector<std::string>& overrides) {
  toml::table root;
  try {
    root = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw Error(path + ":" + std::to_string(e.source().begin.line) + ": TOML syntax error: " +
                std::string(e.description()));
  }
  return build_scene(root, path, overrides);
}

Scene read_scene(const std::string& path, const std::vector<std::string>& overrides) {
  if (std::filesystem::is_directory(path)) throw Error(path + ": is a folder, not a scene file (.toml)");
  require_regular_input(path, "the scene");
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open scene file");
  // The other files of the pipeline, given where the scene goes, read as TOML syntax errors.
  if (begins_as_particle_file(path))
    throw Error(path + ": a particle file (written by pd-mesh), not a scene: a scene (.toml) names it with "
                       "particles = \"...\" (docs/scenes.md; geometries/*.toml are examples)");
  if (std::filesystem::path(path).extension() == ".geo")
    throw Error(path + ": a gmsh geometry, not a scene: mesh it with pd-mesh into a particle file, and name that "
                       "file in a scene (.toml) with particles = \"...\" (docs/mesher.md, docs/scenes.md)");
  std::stringstream text;
  text << in.rdbuf();
  return parse_scene(text.str(), path, overrides);
}

}  // namespace pd::solver
