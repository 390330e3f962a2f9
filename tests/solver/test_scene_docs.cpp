// docs/scenes.md lists exactly the keys the scene reader accepts: a key the
// reader takes that the guide does not name cannot be found by a user, and a
// key the guide names that the reader does not take is refused as unknown.
//
// The reader's keys come from the reader itself: an unknown key in a table is
// refused with the keys it looked up there ("(known here: a, b, ...)",
// TableReader::reject_unknown_keys in solver/input/scene.cpp). The guide's
// keys are the first cells of the key tables under each section heading.
// The test's scenes reach every key the reader's source names, so that a key
// read only in one branch (one kind of load, one model) is compared too.
//
// The defaults the guide states are the reader's: a key written with the
// value its "default" cell gives is one the reader notes as written with its
// default (Scene::written_defaults, which the restart key leaves out).
//
// So are the words a key takes (`"pmb"`, `"osb"`): the reader's come from its
// refusal of a word it does not take ("expected one of ..."), each of which
// it then takes; the guide's from the key's row.
#include <catch2/catch.hpp>
#include <toml++/toml.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "error.hpp"
#include "scene.hpp"

namespace {

using Keys = std::set<std::string>;

// A dynamic scene that touches every table a dynamic run reads (OSB with dual
// horizons, so that [refinement] and model.osb_failure are accepted; the
// automatic step, so that time.safety is), with a traction load and velocity
// loads whose components vary in both forms.
const char* dynamic_scene = R"(
particles = "plate.pdp"
[model]
type = "osb"
dual_horizon = true
[material]
youngs_modulus = 3.24e9
density = 1190
fracture_energy = 200
poisson_ratio = 0.35
[effects]
damage = true
[time]
step = "auto"
end = 1e-5
[stop]
set = "right"
[refinement]
levels = 1
[[loads]]
set = "top"
type = "traction"
y = 1e6
[[loads]]
set = "bottom"
type = "velocity"
x = { value = 0, gradient = [1, 0] }
[[loads]]
set = "left"
type = "velocity"
y = { from = [0, 0], to = [1, 0], values = [0, 1] }
[[precracks]]
from = [0, 0.0125]
to = [0.002, 0.0125]
[output]
energy_interval = 100
)";

const char* quasi_static_scene = R"(
particles = "plate.pdp"
[material]
youngs_modulus = 3.24e9
fracture_energy = 200
[quasi_static]
load_factors = [1]
[[loads]]
set = "left"
type = "displacement"
x = 1e-6
)";

// The keys the reader looked up in the table `where` ("" for the top level,
// "material", "loads[0]", "loads[1].x"), from the refusal of an unknown key
// added there with --set (the key is chosen so that no table has it).
Keys reader_keys(const std::string& scene, const std::string& where, const std::string& set_prefix) {
  const std::string unknown = "key_no_table_has";
  std::string message;
  try {
    pd::solver::parse_scene(scene, "dir/scene.toml", {set_prefix + unknown + "=1"});
  } catch (const pd::Error& e) {
    message = e.what();
  }
  INFO(message);
  const std::string expected = "unknown key '" + (where.empty() ? "" : where + ".") + unknown + "'";
  REQUIRE(message.find(expected) != std::string::npos);
  const std::string marker = "(known here: ";
  const auto from = message.find(marker);
  REQUIRE(from != std::string::npos);
  const auto to = message.find(')', from);
  REQUIRE(to != std::string::npos);
  Keys keys;
  std::istringstream list(message.substr(from + marker.size(), to - from - marker.size()));
  for (std::string key; std::getline(list, key, ',');) keys.insert(key.substr(key.find_first_not_of(' ')));
  return keys;
}

std::vector<std::string> cells_of(const std::string& line) {
  std::vector<std::string> cells;
  std::istringstream row(line.substr(line.find('|') + 1));
  for (std::string cell; std::getline(row, cell, '|');) {
    const auto first = cell.find_first_not_of(' '), last = cell.find_last_not_of(' ');
    cells.push_back(first == std::string::npos ? "" : cell.substr(first, last - first + 1));
  }
  return cells;
}

// Calls row(table, cells, header) for each row of docs/scenes.md's key
// tables, with its table ("material", "loads", "" for the top level), its
// cells and its table's header cells: the tables under a heading that names
// a table (`[material]`, `[[loads]]`), the top level's and the switching
// scene's (its one table: the loads' `phase`). The other tables (units,
// options, measurements) lie under other headings.
template <class Row>
void for_each_key_row(Row&& row) {
  const std::string path = std::string(PD_DOCS_DIR) + "/scenes.md";
  std::ifstream in(path);
  INFO(path);
  REQUIRE(in);
  const std::regex table_heading(R"(^## `\[\[?([a-z_]+)\]\]?`)");
  std::string section = "-";  // "-" under a heading of no key table (and above the first)
  std::vector<std::string> header;  // empty before a table's header row
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (line.rfind("## ", 0) == 0) {
      header.clear();
      if (std::regex_search(line, m, table_heading)) section = m[1];
      else if (line == "## Top level") section = "";
      else if (line.rfind("## Quasi-static, then dynamic", 0) == 0) section = "loads";
      else section = "-";
      continue;
    }
    const auto bar = line.find_first_not_of(' ');
    if (section == "-" || bar == std::string::npos || line[bar] != '|') {
      header.clear();
      continue;
    }
    const auto cells = cells_of(line.substr(bar));
    if (header.empty()) header = cells;
    else if (cells.empty() || cells[0].find("---") == std::string::npos) row(section, cells, header);
  }
}

// docs/scenes.md's key tables, by the table they describe: every identifier in
// backquotes in the first cell of a row (for_each_key_row; a table is a key
// of the top level); in `{ value = v, ... }` cells, the names before ' ='.
std::map<std::string, Keys> documented_keys() {
  const std::regex quoted(R"(`([^`]*)`)");
  const std::regex identifier(R"(^[a-z_]+$)");
  const std::regex component(R"(([a-z_]+) =)");
  std::map<std::string, Keys> keys;
  for_each_key_row([&](const std::string& section, const std::vector<std::string>& cells,
                       const std::vector<std::string>&) {
    if (!section.empty()) keys[""].insert(section);
    for (auto q = std::sregex_iterator(cells[0].begin(), cells[0].end(), quoted); q != std::sregex_iterator(); ++q) {
      const std::string text = (*q)[1];
      if (std::regex_match(text, identifier)) {
        keys[section].insert(text);
      } else if (text.rfind("{ ", 0) == 0) {
        for (auto c = std::sregex_iterator(text.begin(), text.end(), component); c != std::sregex_iterator(); ++c)
          keys["loads.x"].insert((*c)[1]);
      }
    }
  });
  return keys;
}

// Every key name solver/input/scene.cpp asks a table reader for
// (r.positive_or("damage", ...), c.has("at"), top.subtable("time"), ...),
// in whatever branch: a key read only for one kind of load or model, which
// the scenes above might not reach, is still named here.
Keys keys_named_in_reader_source() {
  const std::string path = std::string(PD_DOCS_DIR) + "/../solver/input/scene.cpp";
  std::ifstream in(path);
  INFO(path);
  REQUIRE(in);
  std::stringstream text;
  text << in.rdbuf();
  const std::string source = text.str();
  const std::regex call(R"re(\b(?:r|c|top)\.(?:has|find|require|positive|positive_or|quantity|quantity_or|)re"
                        R"re(real_or|count_or|whole_or|boolean_or|string|string_or|numbers|subtable)\("([a-z_]+)")re");
  Keys keys;
  for (auto k = std::sregex_iterator(source.begin(), source.end(), call); k != std::sregex_iterator(); ++k)
    keys.insert((*k)[1]);
  return keys;
}

// A default the guide states: its table, its key, and the cell as written.
struct DocumentedDefault {
  std::string table, key, cell;
};

// The "default" cells of docs/scenes.md's key tables (those whose header row
// has a column "default").
std::vector<DocumentedDefault> documented_defaults() {
  const std::regex identifier(R"(^`([a-z_]+)`$)");
  std::vector<DocumentedDefault> out;
  for_each_key_row([&](const std::string& section, const std::vector<std::string>& cells,
                       const std::vector<std::string>& header) {
    const auto at = std::find(header.begin(), header.end(), "default");
    const auto column = static_cast<std::size_t>(at - header.begin());
    std::smatch m;
    if (at != header.end() && cells.size() > column && std::regex_match(cells[0], m, identifier))
      out.push_back({section, m[1], cells[column]});
  });
  return out;
}

// The TOML value a default cell states, or "" for a cell that states none
// ("required", "not set", "`strain_fraction`"): the cell without a remark in
// parentheses after it ("0 (none)") and without its backquotes.
std::string stated_value(std::string cell) {
  static const std::regex remark(R"(^(.*?) \(.*\)$)");
  std::smatch m;
  if (std::regex_match(cell, m, remark)) cell = m[1];
  if (cell.size() > 2 && cell.front() == '`' && cell.back() == '`') cell = cell.substr(1, cell.size() - 2);
  try {
    const toml::table parsed = toml::parse("v = " + cell);
    return parsed.get("v")->is_table() ? "" : cell;
  } catch (const toml::parse_error&) {
    return "";
  }
}

// The words in double quotes in `text` ("expected \"bond\" (...) or
// \"normal\"": bond, normal).
Keys quoted_words(const std::string& text) {
  static const std::regex word("\"([a-z_]+)\"");
  Keys words;
  for (auto w = std::sregex_iterator(text.begin(), text.end(), word); w != std::sregex_iterator(); ++w)
    words.insert((*w)[1]);
  return words;
}

// The words the guide lists for each key ("model.type", "loads.type"): in
// the second cell of its row (`"pmb"`, `"osb"`), at the start of its last
// cell (`"velocity"`, `"displacement"`, ...), and those its last cell defines
// (`"bond"`: ..., at the cell's start or after '. ' or '; ').
std::map<std::string, Keys> documented_words() {
  const std::regex identifier(R"(^`([a-z_]+)`$)");
  const std::regex listed(R"re(`"([a-z_]+)"`)re");
  const std::regex leading(R"re(^(`"[a-z_]+"`(, | / )?)+)re");
  const std::regex defined(R"re((?:^|\. |; )`"([a-z_]+)"`:)re");
  std::map<std::string, Keys> out;
  for_each_key_row([&](const std::string& section, const std::vector<std::string>& cells,
                       const std::vector<std::string>&) {
    std::smatch m;
    if (cells.size() < 3 || !std::regex_match(cells[0], m, identifier)) return;
    Keys words;
    const auto add = [&](const std::string& text, const std::regex& pattern) {
      for (auto w = std::sregex_iterator(text.begin(), text.end(), pattern); w != std::sregex_iterator(); ++w)
        words.merge(quoted_words((*w)[0]));
    };
    add(cells[1], listed);
    add(cells.back(), leading);
    add(cells.back(), defined);
    if (!words.empty()) out[(section.empty() ? "" : section + ".") + std::string(m[1])] = words;
  });
  return out;
}

// The words the reader takes for `key` in `scene` (--set `set_key`, with
// the `others`), none when the key takes no word from a list: those its
// refusal of an unknown word names after "expected", each checked to be taken.
Keys reader_words(const std::string& scene, const std::string& key, const std::string& set_key,
                  const std::vector<std::string>& others = {}) {
  const std::string unknown = "word_no_key_takes";
  const auto with = [&](const std::string& value) {
    std::vector<std::string> overrides = others;
    overrides.push_back(set_key + "=" + value);
    return overrides;
  };
  std::string message;
  try {
    pd::solver::parse_scene(scene, "dir/scene.toml", with(unknown));
  } catch (const pd::Error& e) {
    message = e.what();
  }
  INFO(key << ": " << message);
  const std::string refused = "'" + unknown + "': expected ";
  const auto at = message.find(refused);
  if (at == std::string::npos) return {};
  const Keys words = quoted_words(message.substr(at + refused.size()));
  for (const auto& word : words) {
    std::string taken = "taken";
    try {
      pd::solver::parse_scene(scene, "dir/scene.toml", with(word));
    } catch (const pd::Error& e) {
      taken = e.what();
    }
    INFO("--set " << set_key << "=" << word);
    CHECK(taken.find("'" + word + "': expected ") == std::string::npos);
  }
  return words;
}

}  // namespace

TEST_CASE("docs/scenes.md lists exactly the keys the scene reader accepts, table by table", "[scene][docs]") {
  const auto documented = documented_keys();
  std::map<std::string, Keys> reader;
  reader[""] = reader_keys(dynamic_scene, "", "");
  for (const char* table : {"model", "material", "effects", "time", "stop", "refinement", "output"})
    reader[table] = reader_keys(dynamic_scene, table, std::string(table) + ".");
  reader["quasi_static"] = reader_keys(quasi_static_scene, "quasi_static", "quasi_static.");
  reader["precracks"] = reader_keys(dynamic_scene, "precracks[0]", "precracks.0.");
  // A traction reads every key a load has but the varying components' own.
  reader["loads"] = reader_keys(dynamic_scene, "loads[0]", "loads.0.");
  reader["loads.x"] = reader_keys(dynamic_scene, "loads[1].x", "loads.1.x.");
  const Keys other_form = reader_keys(dynamic_scene, "loads[2].y", "loads.2.y.");
  CHECK(other_form == reader["loads.x"]);

  // The quasi-static scene's top level reads [quasi_static] where the dynamic one reads [time]: both are read.
  REQUIRE(reader[""].count("quasi_static"));
  for (const auto& [table, keys] : reader) {
    INFO("table '" << table << "' (\"\" = the top level)");
    REQUIRE(documented.count(table));
    CHECK(documented.at(table) == keys);
  }
  CHECK(documented.size() == reader.size());

  // Every key the reader's source asks for is one the scenes above reach (so
  // one the comparison above covers): a key read in a branch they miss fails
  // here until they reach it.
  Keys reached;
  for (const auto& [table, keys] : reader) reached.insert(keys.begin(), keys.end());
  const Keys named = keys_named_in_reader_source();
  CHECK(named.size() > 60);  // the pattern still finds the reader's calls
  for (const auto& key : named) {
    INFO("solver/input/scene.cpp reads '" << key << "': no table of this test's scenes reads it");
    CHECK(reached.count(key));
  }
}

TEST_CASE("docs/scenes.md states the defaults the scene reader takes", "[scene][docs]") {
  const auto defaults = documented_defaults();
  std::set<std::string> checked;
  for (const auto& d : defaults) {
    const std::string value = stated_value(d.cell);
    if (value.empty()) continue;  // "required", "not set", a default named by another key
    const std::string key = d.table + "." + d.key;
    INFO("docs/scenes.md: [" << d.table << "] '" << d.key << "' default '" << d.cell << "', --set " << key << "="
                             << value);
    const std::string& scene = d.table == "quasi_static" ? quasi_static_scene : dynamic_scene;
    pd::solver::Scene parsed;
    REQUIRE_NOTHROW(parsed = pd::solver::parse_scene(scene, "dir/scene.toml", {key + "=" + value}));
    const auto& noted = parsed.written_defaults;
    CHECK(std::find(noted.begin(), noted.end(), key) != noted.end());
    checked.insert(key);
  }
  // The defaults of every table that has a default column, as the guide gives them on 7 December 2026.
  CHECK(checked == std::set<std::string>{
                       "model.type", "model.bond_weights", "model.osb_failure", "material.thickness",
                       "material.plane", "effects.damage", "effects.surface_correction", "time.safety", "time.force",
                       "stop.damage", "refinement.damage_threshold", "refinement.strain_fraction",
                       "refinement.strain", "refinement.spread", "refinement.levels", "refinement.particle_budget",
                       "refinement.check_interval", "quasi_static.tolerance", "quasi_static.max_iterations",
                       "quasi_static.on_nonconvergence", "quasi_static.max_breaking_rounds",
                       "quasi_static.stop_reaction_fraction", "quasi_static.kernels",
                       "quasi_static.coarse_correction", "quasi_static.damped_rounds",
                       "quasi_static.progress_interval", "output.snapshot_interval", "output.energy_interval",
                       "output.checkpoint_interval", "output.damage_thresholds"});
}

TEST_CASE("docs/scenes.md lists the words each key takes as the scene reader takes them", "[scene][docs]") {
  std::map<std::string, Keys> reader;
  const auto probe = [&](const std::string& scene, const std::string& table, const std::string& set_prefix,
                         const std::vector<std::string>& others = {}) {
    for (const auto& key : reader_keys(scene, table, set_prefix)) {
      const std::string name = table.substr(0, table.find('[')) + "." + key;
      const Keys words = reader_words(scene, name, set_prefix + key, others);
      if (!words.empty()) reader[name] = words;
    }
  };
  for (const char* table : {"model", "material", "effects", "time", "stop", "refinement", "output"})
    probe(dynamic_scene, table, std::string(table) + ".");
  probe(quasi_static_scene, "quasi_static", "quasi_static.");
  probe(dynamic_scene, "loads[0]", "loads.0.");
  probe(dynamic_scene, "precracks[0]", "precracks.0.");
  // The loads' phase is read in a scene that switches only.
  const std::string switching = std::string(quasi_static_scene) + "[time]\nstep = \"auto\"\nend = 1e-6\n";
  const Keys phases = reader_words(switching, "loads.phase", "loads.0.phase",
                                   {"quasi_static.then=dynamic", "material.density=1190"});
  if (!phases.empty()) reader["loads.phase"] = phases;
  // The keys that take words, as the reader has them on 7 December 2026 (the
  // probes above still find them).
  Keys with_words;
  for (const auto& [key, words] : reader) with_words.insert(key);
  CHECK(with_words == Keys{"loads.phase", "loads.type", "material.plane", "model.bond_weights", "model.osb_failure",
                           "model.type", "quasi_static.kernels", "quasi_static.on_nonconvergence",
                           "quasi_static.then", "refinement.spread", "refinement.strain"});
  const auto documented = documented_words();
  for (const auto& [key, words] : reader) {
    INFO("docs/scenes.md: the words of '" << key << "'");
    REQUIRE(documented.count(key));
    CHECK(documented.at(key) == words);
  }
}
