#include "solver_summary.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "error.hpp"
#include "units.hpp"
#include "results_format.hpp"
#include "run_lock.hpp"

namespace pd::post {
namespace {

// An object's members: string values unescaped, the others as their JSON
// text; `texts` names the members whose value is a string, so that "958"
// is told from 958.
struct JsonObject {
  std::map<std::string, std::string> members;
  std::set<std::string> texts;
};

// A small JSON reader (RFC 8259 syntax) that keeps the values of the
// top-level object's members and checks, then skips, everything else.
class JsonScanner {
public:
  JsonScanner(const std::string& text, const std::string& path) : s_(text), path_(path) {}

  JsonObject object() {
    JsonObject object;
    std::map<std::string, std::string>& out = object.members;
    space();
    expect('{');
    space();
    if (peek() == '}') return ++pos_, finish(object);
    for (;;) {
      space();
      const std::size_t key_at = pos_;
      const std::string key = string();
      // pd-solve writes each key once: a second one (an edited file, or two
      // joined) would silently stand for the first (before 7 December 2026
      // the last of them was read, exit 0).
      if (out.count(key))
        throw file_error(path_, "the key \"" + key + "\" is given twice (again at byte " + std::to_string(key_at) +
                                    "): pd-solve writes each key once (an edited file, or two joined); give the "
                                    "summary.json that pd-solve wrote");
      space();
      expect(':');
      space();
      if (peek() == '"') {
        out[key] = string();
        object.texts.insert(key);
      } else {
        // Other values as their JSON text (a number as written; objects and arrays whole).
        const std::size_t start = pos_;
        value();
        out[key] = s_.substr(start, pos_ - start);
      }
      space();
      if (peek() == ',') { ++pos_; continue; }
      expect('}');
      return finish(object);
    }
  }

private:
  JsonObject finish(JsonObject& object) {
    space();
    if (pos_ != s_.size()) fail("text after the end of the object");
    return object;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw file_error(path_, "not valid JSON at byte " + std::to_string(pos_) + ": " + what);
  }
  char peek() const { return pos_ < s_.size() ? s_[pos_] : '\0'; }
  void expect(char c) {
    if (peek() != c) fail(std::string("expected '") + c + "'");
    ++pos_;
  }
  void space() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  std::string string() {
    expect('"');
    std::string out;
    for (;;) {
      if (pos_ >= s_.size()) fail("unterminated string");
      const char c = s_[pos_++];
      if (c == '"') return out;
      if (static_cast<unsigned char>(c) < 0x20) fail("control character in a string");
      if (c != '\\') { out += c; continue; }
      const char e = peek();
      ++pos_;
      switch (e) {
        case '"': case '\\': case '/': out += e; break;
        case 'n': out += '\n'; break;
        case 't': out += '\t'; break;
        case 'r': out += '\r'; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'u': {
          // UTF-8 of the code point (before 7 December 2026 every \u
          // escape read as '?': a quasi-static run's stop reason reached
          // pd-post's summary.json with its characters lost). A surrogate
          // pair is one code point; a surrogate alone is U+FFFD, as
          // json_string writes a byte that begins no character.
          unsigned code = hex4();
          if (code >= 0xD800 && code <= 0xDBFF && s_.compare(pos_, 2, "\\u") == 0) {
            const std::size_t at = pos_;
            pos_ += 2;
            const unsigned low = hex4();
            if (low >= 0xDC00 && low <= 0xDFFF) code = 0x10000 + ((code - 0xD800) << 10) + (low - 0xDC00);
            else pos_ = at;  // not its pair: read on its own
          }
          if (code >= 0xD800 && code <= 0xDFFF) code = 0xFFFD;
          append_utf8(out, code);
          break;
        }
        default: fail("bad escape");
      }
    }
  }
  // The four hex digits of a \u escape.
  unsigned hex4() {
    unsigned code = 0;
    for (int k = 0; k < 4; ++k) {
      const char h = peek();
      if (!std::isxdigit(static_cast<unsigned char>(h))) fail("bad \\u escape");
      code = code * 16 + static_cast<unsigned>(std::isdigit(static_cast<unsigned char>(h)) ? h - '0'
                                                   : std::tolower(static_cast<unsigned char>(h)) - 'a' + 10);
      ++pos_;
    }
    return code;
  }
  static void append_utf8(std::string& out, unsigned code) {
    if (code < 0x80) {
      out += static_cast<char>(code);
    } else if (code < 0x800) {
      out += static_cast<char>(0xC0 | (code >> 6));
      out += static_cast<char>(0x80 | (code & 0x3F));
    } else if (code < 0x10000) {
      out += static_cast<char>(0xE0 | (code >> 12));
      out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (code & 0x3F));
    } else {
      out += static_cast<char>(0xF0 | (code >> 18));
      out += static_cast<char>(0x80 | ((code >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (code & 0x3F));
    }
  }
  void value() {
    const char c = peek();
    if (c == '"') { string(); return; }
    if (c == '{' || c == '[') {
      const char close = c == '{' ? '}' : ']';
      ++pos_;
      space();
      if (peek() == close) { ++pos_; return; }
      for (;;) {
        space();
        if (close == '}') { string(); space(); expect(':'); space(); }
        value();
        space();
        if (peek() == ',') { ++pos_; continue; }
        expect(close);
        return;
      }
    }
    for (const char* word : {"true", "false", "null"})
      if (s_.compare(pos_, std::char_traits<char>::length(word), word) == 0) {
        pos_ += std::char_traits<char>::length(word);
        return;
      }
    number();
  }
  void number() {
    const std::size_t start = pos_;
    if (peek() == '-') ++pos_;
    if (!std::isdigit(static_cast<unsigned char>(peek()))) fail("expected a value");
    while (std::isdigit(static_cast<unsigned char>(peek()))) ++pos_;
    if (peek() == '.') {
      ++pos_;
      if (!std::isdigit(static_cast<unsigned char>(peek()))) fail("bad number");
      while (std::isdigit(static_cast<unsigned char>(peek()))) ++pos_;
    }
    if (peek() == 'e' || peek() == 'E') {
      ++pos_;
      if (peek() == '+' || peek() == '-') ++pos_;
      if (!std::isdigit(static_cast<unsigned char>(peek()))) fail("bad number");
      while (std::isdigit(static_cast<unsigned char>(peek()))) ++pos_;
    }
    if (pos_ == start) fail("expected a value");
  }

  const std::string& s_;
  const std::string& path_;
  std::size_t pos_ = 0;
};

// pd-solve writes every member as one JSON type: a value of another type
// (a number given as a string, an object as a number) is an edited file.
// Before 7 December 2026 "steps": "958" was read as the number, and a
// "counts" or "material" that was no object, or an "effects.damage" that was
// no true or false, was passed over: the checks against arrival.vtp and
// the damage-off note skipped without a word.
[[noreturn]] void wrong_type(const std::string& path, const std::string& shown_key, const std::string& value,
                             bool is_text, const std::string& expected) {
  const std::string shown = is_text ? "the string \"" + clipped(value) + "\"" : clipped(value);
  throw file_error(path, "\"" + shown_key + "\" is " + shown + ", expected " + expected +
                             ": pd-solve writes it so (an edited file); give the summary.json that pd-solve wrote");
}

// A member's JSON number; NaN if the member is absent. A value that is no
// number is the file's fault, named with its key.
double member_number(const JsonObject& object, const std::string& key, const std::string& shown_key,
                     const std::string& path) {
  const auto& members = object.members;
  const auto it = members.find(key);
  if (it == members.end()) return std::nan("");
  if (object.texts.count(key)) wrong_type(path, shown_key, it->second, true, "a number");
  char* end = nullptr;
  const double value = std::strtod(it->second.c_str(), &end);
  if (it->second.empty() || end != it->second.c_str() + it->second.size() || !std::isfinite(value))
    throw file_error(path, "\"" + shown_key + "\" is " + it->second + ", expected a number");
  return value;
}

// The members of an object member ("counts", "material"); none if absent.
JsonObject member_object(const JsonObject& object, const std::string& key, const std::string& path) {
  const auto it = object.members.find(key);
  if (it == object.members.end()) return {};
  if (object.texts.count(key) || it->second.empty() || it->second.front() != '{')
    wrong_type(path, key, it->second, object.texts.count(key) > 0, "an object ({...})");
  return JsonScanner(it->second, path).object();
}

}  // namespace

RunKind detect_run_kind(const std::string& outdir, const SolverSummary& summary) {
  namespace fs = std::filesystem;
  if (summary.mode == "quasi_static") return RunKind::quasi_static;
  const fs::path dir(outdir);
  if (fs::exists(dir / results::arrival_file)) return RunKind::dynamic;
  if (fs::exists(dir / results::load_steps_file) || fs::exists(dir / results::final_state_file))
    return RunKind::quasi_static;
  return RunKind::dynamic;
}

std::string unfinished_run_state(const RunLockStatus& lock) {
  // The run's lock tells the two apart (before 7 December 2026 "the solver
  // was killed or is still running" for both): the kernel releases it when
  // pd-solve ends, however it ends.
  switch (lock.state) {
    case RunLockStatus::State::held:
      return "the run is still running (pd-solve holds " + lock.path +
             (lock.pid.empty() ? std::string() : ", PID " + lock.pid) + ")";
    case RunLockStatus::State::absent:
    case RunLockStatus::State::free: return "the run stopped before its end (killed, or failed)";
    case RunLockStatus::State::unknown: break;
  }
  return "the solver was killed or is still running";
}

std::string incomplete_run_warning(const std::string& outdir, const std::string& covers) {
  return "incomplete run: " + (std::filesystem::path(outdir) / results::summary_file).string() +
         " does not exist (pd-solve writes it when a run ends; " + unfinished_run_state(run_lock_status(outdir)) +
         "); " + covers;
}

SolverSummary read_solver_summary(const std::string& outdir) {
  SolverSummary s;
  s.path = (std::filesystem::path(outdir) / results::summary_file).string();
  if (!std::filesystem::exists(s.path)) return s;
  std::ifstream in(s.path, std::ios::binary);
  if (!in) throw file_error(s.path, "cannot open for reading");
  std::stringstream text;
  text << in.rdbuf();
  const JsonObject summary = JsonScanner(text.str(), s.path).object();
  const auto& strings = summary.members;
  s.present = true;
  auto get = [&](const char* key) {
    const auto it = strings.find(key);
    return it == strings.end() ? std::string() : it->second;
  };
  for (const char* key : {"mode", "model", "plane", "stop_reason", "run_id"})
    if (strings.count(key) && !summary.texts.count(key)) wrong_type(s.path, key, get(key), false, "a string");
  s.mode = get("mode");
  s.model = get("model");
  s.plane = get("plane");
  s.stop_reason = get("stop_reason");
  s.run_id = get("run_id");
  if (!s.plane.empty() && s.plane != "stress" && s.plane != "strain")
    throw file_error(s.path, "\"plane\" is '" + s.plane + "', expected \"stress\" or \"strain\"");
  if (!s.mode.empty() && s.mode != "dynamic" && s.mode != "quasi_static")
    throw file_error(s.path, "\"mode\" is '" + s.mode + "', expected \"dynamic\" or \"quasi_static\"");
  // The effects are an object of their own: its members read the same way.
  const JsonObject effects = member_object(summary, "effects", s.path);
  if (const auto damage = effects.members.find("damage"); damage != effects.members.end()) {
    if (effects.texts.count("damage") || (damage->second != "true" && damage->second != "false"))
      wrong_type(s.path, "effects.damage", damage->second, effects.texts.count("damage") > 0, "true or false");
    s.damage_off = damage->second == "false";
  }
  if (summary.texts.count("load_steps")) wrong_type(s.path, "load_steps", get("load_steps"), true, "a count");
  if (const std::string steps = get("load_steps"); !steps.empty()) {
    char* end = nullptr;
    const long value = std::strtol(steps.c_str(), &end, 10);
    if (end != steps.c_str() + steps.size() || value < 0)
      throw file_error(s.path, "\"load_steps\" is " + steps + ", expected a count");
    s.load_steps = value;
  }
  const double steps = member_number(summary, "steps", "steps", s.path);
  if (std::isfinite(steps)) {
    if (!(steps >= 0 && steps < 9e15 && steps == std::floor(steps)))
      throw file_error(s.path, "\"steps\" is " + get("steps") + ", expected a count");
    s.steps = static_cast<long>(steps);
  }
  s.end_time = member_number(summary, "end_time_s", "end_time_s", s.path);
  const double particles =
      member_number(member_object(summary, "counts", s.path), "particles", "counts.particles", s.path);
  if (std::isfinite(particles)) {
    // (Cast unchecked before 7 December 2026: 2.5 was compared as 2, and 1e30 was out of a long's range.)
    if (!(particles >= 0 && particles < 9e15 && particles == std::floor(particles)))
      throw file_error(s.path, "\"counts.particles\" is " +
                                   member_object(summary, "counts", s.path).members.at("particles") +
                                   ", expected a count");
    s.particles = static_cast<long>(particles);
  }
  const auto material = member_object(summary, "material", s.path);
  s.youngs_modulus = member_number(material, "youngs_modulus_Pa", "material.youngs_modulus_Pa", s.path);
  s.density = member_number(material, "density_kg_m3", "material.density_kg_m3", s.path);
  // pd-solve names itself in every summary.json it writes ("tool": "pd-solve
  // 0.1.0"; a fresh run checks that before it replaces one): another tool's
  // file, or one written by hand, would pass for a finished run's.
  if (const std::string tool = get("tool"); tool.rfind("pd-solve", 0) != 0)
    throw file_error(s.path, (tool.empty() ? std::string("has no \"tool\"") : "its \"tool\" is '" + tool + "'") +
                                 ": not a summary.json that pd-solve wrote (it writes one naming itself when a run "
                                 "ends); move it away to read the run as incomplete, or give the folder that "
                                 "pd-solve -o wrote");
  return s;
}

void check_same_run(const SolverSummary& summary, const ArrivalData& arrival) {
  if (!summary.present) return;
  const auto differ = recorded_values_differ;
  std::string what;
  if (summary.steps >= 0 && arrival.end_step >= 0 && summary.steps != arrival.end_step)
    what = "the run ended at step " + std::to_string(summary.steps) + " (\"steps\"), and " + arrival.path +
           " is from step " + std::to_string(arrival.end_step);
  else if (differ(summary.end_time, arrival.end_time))
    what = "the run ended at t = " + shortest_text(summary.end_time) + " s (\"end_time_s\"), and " + arrival.path +
           " is from t = " + shortest_text(arrival.end_time) + " s";
  else if (summary.particles >= 0 && static_cast<std::size_t>(summary.particles) != arrival.size())
    what = "the run had " + std::to_string(summary.particles) + " particles (\"counts\"), and " + arrival.path +
           " has " + std::to_string(arrival.size());
  else if (differ(summary.youngs_modulus, arrival.youngs_modulus) || differ(summary.density, arrival.density))
    what = "the run's material has E = " + shortest_text(summary.youngs_modulus) + " Pa, rho = " +
           shortest_text(summary.density) + " kg/m^3 (\"material\"), and " + arrival.path + "'s E = " +
           shortest_text(arrival.youngs_modulus) + " Pa, rho = " + shortest_text(arrival.density) + " kg/m^3";
  if (!what.empty()) throw mixed_runs_error(summary.path, what);
  // The identifier last: the values above say what differs, where they do.
  check_same_run_id(summary.path, summary.run_id, "\"run_id\"", arrival.path, arrival.run_id);
}

}  // namespace pd::post
