#pragma once
// The common frame of the three command-line tools: one positional argument
// plus options (Boost.Program_options), --help and --version, and every
// failure as one line on stderr ("pd-mesh: error: ...") with exit status 1,
// a report on stdout that could not be written (a full disk) included.
#include <boost/program_options.hpp>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "error.hpp"
#include "pd/version.hpp"

namespace pd {

// Whether everything written to stdout reached it (flushed now: stdio
// keeps a failed write's error, e.g. of a full disk, until asked). Says why
// not on stderr.
inline bool standard_output_written(const char* tool) {
  errno = 0;
  std::cout.flush();
  const bool flushed = std::fflush(stdout) == 0;
  const int error = errno;
  if (flushed && !std::ferror(stdout) && std::cout) return true;
  std::cerr << tool << ": error: cannot write to standard output"
            << (error != 0 ? std::string(": ") + std::strerror(error) : std::string(" (disk full?)"))
            << "; the report printed there is lost\n";
  return false;
}

template <class Body>
int run_tool(const char* tool, Body&& body) {
  int status = 1;
  try {
    status = body();
  } catch (const Error& e) {
    std::cerr << tool << ": error: " << e.what() << "\n";
  } catch (const std::exception& e) {
    std::cerr << tool << ": error: " << e.what() << "\n";
  }
  // (Not left to exit(), which drops a failed flush without a word and exits
  // 0. A tool that failed has said why already, which may be this.)
  if (status == 0 && !standard_output_written(tool)) status = 1;
  return status;
}

// The number of letters to add, leave out, change or swap with the next
// (optimal string alignment) to turn `a` into `b`.
inline std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

// What an option typed that no tool option is gets for an answer: its name
// as typed (up to any '='), and the options of `visible` that begin with it
// or with its lower-case form (`--gri`, `-gri`, `--Grid`: --grid), else the
// nearest within two edits (`--spaceing`: --spacing).
inline std::string unknown_option_message(const std::string& typed, const char* tool,
                                          const boost::program_options::options_description& visible) {
  const std::string name = clipped(typed.substr(0, typed.find('=')));
  std::string word = name.substr(std::min(name.find_first_not_of('-'), name.size()));
  for (char& c : word) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  std::vector<std::string> candidates;
  if (!word.empty())
    for (const auto& option : visible.options()) {
      const std::string& full = option->long_name();
      if (!full.empty() && full.compare(0, word.size(), word) == 0) candidates.push_back("--" + full);
    }
  // Else a misspelling: the options one or two edits away (a letter
  // added, left out, changed or two swapped: `--spaceing`, `--thresold`),
  // the nearest; one edit only for a word of four letters or fewer. Before 7
  // December 2026 a misspelt option got the --help pointer alone.
  if (candidates.empty() && word.size() <= 64) {
    std::size_t nearest = word.size() <= 4 ? 1 : 2;
    for (const auto& option : visible.options()) {
      const std::string& full = option->long_name();
      if (full.empty() || full.size() > 64) continue;
      const std::size_t distance = edit_distance(word, full);
      if (distance > nearest) continue;
      if (distance < nearest) candidates.clear(), nearest = distance;
      candidates.push_back("--" + full);
    }
  }
  if (candidates.empty())
    return name + ": no such option (" + tool + " --help lists them)";
  std::string list;
  for (std::size_t k = 0; k < candidates.size(); ++k)
    list += (k == 0 ? "" : k + 1 == candidates.size() ? " or " : ", ") + candidates[k];
  return name + ": no such option; did you mean " + list + "?";
}

// The items of a comma-separated option value (`--times 1us, 2us`), each
// without the blanks (spaces, tabs) around it, so that an item reads the
// same whether or not a blank follows the comma; an empty item (`1,,2`, a
// comma at the end) is kept, for the caller to refuse by its place. The one
// splitter of the tools' list options: pd-post's, pd-mesh's and the
// validation tools' (before 7 December 2026 each split its lists its own
// way: pd-post refused `--times '1e-6, 2e-6'` while it read `--times '1us,
// 2us'`, and pd-mesh dropped a trailing comma of `--refine-region`).
inline std::vector<std::string> comma_items(const std::string& list) {
  std::vector<std::string> items;
  for (std::size_t begin = 0;;) {
    const std::size_t comma = std::min(list.find(',', begin), list.size());
    const std::size_t first = list.find_first_not_of(" \t", begin);
    const std::size_t last = list.find_last_not_of(" \t", comma == 0 ? std::string::npos : comma - 1);
    items.push_back(first < comma && last != std::string::npos && last >= first
                        ? list.substr(first, last - first + 1)
                        : std::string());
    if (comma == list.size()) break;
    begin = comma + 1;
  }
  if (list.empty()) items.clear();
  return items;
}

// A file or folder whose name begins with '-' (`pd-post -run`) reads as an
// option: where an argument that begins as the unknown option `name` names
// one that exists, the hint to write it as ./NAME (before 7 December 2026
// only "no such option").
inline std::string path_hint(int argc, char** argv, const std::string& name) {
  for (int k = 1; k < argc; ++k) {
    const std::string token = argv[k];
    std::error_code error;
    if (token.size() > 1 && token[0] == '-' && token.compare(0, name.size(), name) == 0 &&
        std::filesystem::symlink_status(token, error).type() != std::filesystem::file_type::not_found && !error)
      return "; for the " + std::string(std::filesystem::is_directory(token, error) ? "folder " : "file ") +
             clipped(token) + " write ./" + clipped(token) + " (a name that begins with '-' reads as an option)";
  }
  return "";
}

// What an option given an empty value (`--vtk ''`, `--vtk=`) gets.
inline std::string empty_value_message(const std::string& key) {
  return "--" + key + ": the value is empty (''; an unset shell variable?): give one, or leave --" + key + " out";
}

// What an option given without its value gets (`name` as typed: -o, --vtk).
// `next`: the option that followed it, taken for its value ("" for none).
inline std::string missing_value_message(const std::string& name, const char* tool, const std::string& next = "") {
  return name + ": no value after it" + (next.empty() ? "" : " ('" + clipped(next) + "', the word after it, is an option)") +
         ": give one (" + name + " VALUE, " + tool + " --help says what it takes), or "
         "leave " + name + " out";
}

// What an option given twice (or more) gets for an answer: every time it was
// given, as typed, and to give it once. `name` is Boost's ("--spacing"); the
// positional argument given also as its long option (`pd-solve scene.toml
// --scene other.toml`) is named as the usage names it (SCENE). Boost's own
// "option '--spacing' cannot be specified more than once" named neither the
// values nor what to do (before 7 December 2026). `fallback`: Boost's text,
// should no occurrence be found.
inline std::string given_twice_message(const boost::program_options::parsed_options& parsed,
                                       const std::string& name, const std::string& positional,
                                       const std::string& fallback) {
  const std::string key = name.substr(std::min(name.find_first_not_of('-'), name.size()));
  std::vector<std::string> times;
  for (const auto& option : parsed.options)
    if (option.string_key == key) {
      std::string typed;
      for (const std::string& token : option.original_tokens) typed += (typed.empty() ? "" : " ") + token;
      times.push_back("'" + clipped(typed) + "'");
    }
  if (times.size() < 2) return fallback;
  std::string list;
  for (std::size_t k = 0; k < times.size(); ++k)
    list += (k == 0 ? "" : k + 1 == times.size() ? ", then " : ", ") + times[k];
  const std::string count = times.size() == 2 ? "twice" : std::to_string(times.size()) + " times";
  if (key == positional) {
    std::string usage = key;
    for (char& c : usage) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return usage + " given " + count + " (" + list +
           "): give it once, as the command's first argument (--" + key + " is another name for it)";
  }
  return "--" + key + " given " + count + " (" + list +
         "): give it once, with the value you mean";
}

// Parses the command line into `vm`: the `visible` options (which must
// include "help" and "version") and one positional argument stored under
// `positional` as a string. Prints the help (with `help_footer`) or the
// version to `out` and returns false if asked for; returns true to go on.
// An option given an empty value is a pd::Error naming the option, and so is
// a second positional argument, naming it, and an option no tool option is
// (an abbreviation included), naming the options that begin with it or lie
// within two edits of it (and, where it names a file, how to give that), an
// option given twice, naming each time (given_twice_message), a short option
// joined to its value by '=' (`-o=x`), and an option left without its value
// (`--vtk=`, `--vtk` at the end, `-o --restart`), and a short option whose
// word with its dash names a long option or an existing file or folder
// (`-output`, `-out` where a folder -out exists).
// (A tool started on several MPI processes passes a silent stream to all
// but one, so that the text appears once.)
inline bool parse_command_line(int argc, char** argv, const char* tool,
                               const boost::program_options::options_description& visible,
                               const char* positional, boost::program_options::variables_map& vm,
                               const std::string& help_footer = "", std::ostream& out = std::cout) {
  namespace po = boost::program_options;
  // Positional arguments after the first are collected, not left to Boost,
  // whose "too many positional options" named neither them nor their most
  // likely cause: a value typed with a space before its unit (`--spacing 0.5
  // mm`, `--set time.end = 1e-5`).
  const char* const extra_positional = "pd-extra-positional";
  po::options_description hidden;
  hidden.add_options()(positional, po::value<std::string>())(extra_positional,
                                                             po::value<std::vector<std::string>>());
  po::options_description all;
  all.add(visible).add(hidden);
  po::positional_options_description positionals;
  positionals.add(positional, 1).add(extra_positional, -1);
  // Boost's default style also takes the start of an option for the whole
  // (`--gri` for --grid): undocumented, and an option added later that
  // begins the same way would change what an abbreviation means without a
  // word. Off: an abbreviation is an unknown option, the full one suggested.
  const int style = po::command_line_style::default_style & ~po::command_line_style::allow_guessing;
  const po::parsed_options parsed = [&] {
    try {
      return po::command_line_parser(argc, argv).options(all).positional(positionals).style(style).run();
    } catch (const po::invalid_command_line_syntax& e) {
      // `--spacing=` is an empty value like `--spacing ''`, and an option
      // with nothing after it a value left out; Boost's "the argument for
      // option '--spacing' should follow immediately after the equal sign"
      // and "the required argument for option '--vtk' is missing" said
      // neither (before 7 December 2026).
      const std::string name = e.get_option_name();
      if (e.kind() == po::invalid_syntax::empty_adjacent_parameter)
        throw Error(empty_value_message(name.substr(std::min(name.find_first_not_of('-'), name.size()))));
      if (e.kind() == po::invalid_syntax::missing_parameter) throw Error(missing_value_message(name, tool));
      throw;
    } catch (const po::unknown_option& e) {
      throw Error(unknown_option_message(e.get_option_name(), tool, visible) + path_hint(argc, argv, e.get_option_name()));
    }
  }();
  // A short option joined to its value by '=' (`-o=plate.pdp`) takes '=' as
  // part of the value: pd-mesh wrote a file named "=plate.pdp", exit 0
  // (before 7 December 2026). Only the long form takes '='.
  for (const auto& option : parsed.options) {
    if (option.original_tokens.size() != 1 || option.value.size() != 1) continue;
    const std::string& token = option.original_tokens[0];
    if (token.size() > 3 && token[0] == '-' && token[1] != '-' && token[2] == '=' && option.value[0] == token.substr(2))
      throw Error(clipped(token) + ": a short option takes its value after a space, " + token.substr(0, 2) + " " +
                  clipped(token.substr(3)) + " (or --" + option.string_key + "=" + clipped(token.substr(3)) +
                  "); joined to it, '=' would be part of the value");
  }
  // A short option takes the rest of its word for its value (`-out`: -o ut).
  // Where the word with its dash names a long option (`-output`) or a file
  // or folder that exists (`pd-post -out`, a folder "-out"), that is what was
  // meant: before 7 December 2026 pd-post read -o ut and ended in "missing
  // OUTDIR", pd-mesh wrote its particle file as "utput".
  for (const auto& option : parsed.options) {
    if (option.original_tokens.size() != 1 || option.value.size() != 1) continue;
    const std::string& token = option.original_tokens[0];
    if (token.size() < 3 || token[0] != '-' || token[1] == '-' || option.value[0] != token.substr(2)) continue;
    const std::string read_as = clipped(token) + ": read as " + token.substr(0, 2) + " " + clipped(token.substr(2)) +
                                " (a short option takes the rest of its word for its value)";
    const std::string word = token.substr(1, token.find('=') == std::string::npos ? std::string::npos : token.find('=') - 1);
    for (const auto& known : visible.options())
      if (!known->long_name().empty() && known->long_name() == word)
        throw Error(read_as + "; a long option takes two dashes: --" + clipped(token.substr(1)));
    std::error_code error;
    if (std::filesystem::symlink_status(token, error).type() != std::filesystem::file_type::not_found && !error)
      throw Error(read_as + "; for the " + (std::filesystem::is_directory(token, error) ? "folder " : "file ") +
                  clipped(token) + " write ./" + clipped(token) + " (a name that begins with '-' reads as an option)");
  }
  // An option whose value was left out takes the next word, another option,
  // for it (`-o --restart`: a run into a folder "--restart", exit 0, before
  // 7 December 2026): refused as a value left out.
  for (const auto& option : parsed.options) {
    if (option.original_tokens.size() != 2 || option.value.size() != 1) continue;
    const std::string& value = option.value[0];
    const std::string word = value.substr(0, value.find('='));
    if (word.size() < 2 || word[0] != '-') continue;
    for (const auto& known : all.options()) {
      const std::string short_name = known->canonical_display_name(po::command_line_style::allow_dash_for_short);
      if (word == "--" + known->long_name() || (short_name.size() == 2 && word == short_name))
        throw Error(missing_value_message(option.original_tokens[0], tool, value));
    }
  }
  // An option given an empty value (`--vtk ""`, an unset shell variable)
  // would read as the option left out: the tools take an empty text for
  // "not given", and the command ran without it and without a word.
  for (const auto& option : parsed.options)
    for (const std::string& value : option.value)
      if (option.string_key != positional && option.string_key != extra_positional && value.empty())
        throw Error(empty_value_message(option.string_key));
  try {
    po::store(parsed, vm);
  } catch (const po::multiple_occurrences& e) {
    throw Error(given_twice_message(parsed, e.get_option_name(), positional, e.what()));
  }
  if (vm.count("help")) {
    out << visible << "\n" << help_footer;
    return false;
  }
  if (vm.count("version")) {
    out << tool << " " << version_string << "\n";
    return false;
  }
  if (vm.count(extra_positional)) {
    const auto& values = vm[extra_positional].as<std::vector<std::string>>();
    std::string extras;
    for (const std::string& value : values) extras += (extras.empty() ? "'" : ", '") + clipped(value) + "'";
    throw Error(std::string("unexpected argument") + (values.size() == 1 ? " " : "s ") + extras +
                " after '" + clipped(vm[positional].as<std::string>()) + "', the one argument " + tool +
                " takes besides its options: an option's value is one word, with no space before its unit "
                "(0.5mm, 80us) or around '=', and in quotes where it holds spaces");
  }
  po::notify(vm);
  return true;
}

}  // namespace pd
