#include "number_table.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "error.hpp"
#include "input_file.hpp"
#include "particle_file.hpp"

namespace pd::post {

std::vector<NumberRow> read_number_table(const std::string& path, std::size_t columns, const std::string& what,
                                         const std::string& expected) {
  require_regular_input(path, what);
  // Another file given by mistake (a particle file, a scene, a geometry) is
  // named as not this one; before 7 December 2026 one whose lines all began
  // with letters was read as a header and a table without rows ("lists no
  // pore").
  const std::string not_this = ", not " + what + ": expected a text file of lines " + expected + ", one per line";
  if (begins_as_particle_file(path)) throw file_error(path, "a particle file" + not_this);
  std::ifstream in(path);
  if (!in) throw file_error(path, "cannot open " + what);
  std::vector<NumberRow> rows;
  std::string line;
  int line_no = 0;
  int header_line = 0, second_words_line = 0;  // lines of words: the first is the header
  std::string second_words;
  while (std::getline(in, line)) {
    ++line_no;
    // A spreadsheet's "CSV UTF-8" begins with a byte order mark, which is
    // no character of the table (before 7 December 2026 the file was
    // refused as "no row of numbers" at its first line, the mark unseen).
    // UTF-16 text ("Unicode text") holds NUL bytes: named for what it is.
    if (line_no == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
    if (!line.empty() && line.back() == '\r') line.pop_back();  // (CR LF line ends, quoted without the CR)
    if (line_no == 1 && (line.compare(0, 2, "\xFF\xFE") == 0 || line.compare(0, 2, "\xFE\xFF") == 0))
      throw file_error(path, "line 1: UTF-16 text (it begins with the byte order mark " +
                                 std::string(line[0] == '\xFF' ? "FF FE" : "FE FF") + "), and " + what +
                                 " is plain text or UTF-8: save it as \"CSV UTF-8\" or \"CSV (comma delimited)\", "
                                 "lines " + expected + ", one per line");
    if (line.find('\0') != std::string::npos)
      throw file_error(path, "line " + std::to_string(line_no) + ": binary data (a NUL byte)" + not_this);
    // A '#' starts a comment, on a line of its own or after a row's values.
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos) continue;  // blank
    // A header starts with a letter; so do "nan" and "inf", a row's values
    // (before 7 December 2026 such a row was skipped as a header: a pore or
    // a box dropped without a word).
    char* number_end = nullptr;
    std::strtod(line.c_str() + first, &number_end);
    const bool starts_with_number = number_end != line.c_str() + first;
    if (std::isalpha(static_cast<unsigned char>(line[first])) && !starts_with_number) {
      // Words after the rows are no header: a row mistyped ("O.5 1 2"), or
      // text pasted on (before 7 December 2026 skipped without a word).
      if (!rows.empty())
        throw file_error(path, "line " + std::to_string(line_no) + ": '" + clipped(line.substr(first)) +
                                   "' is a line of words after the rows (the first on line " +
                                   std::to_string(rows.front().line) + "): only a header, before the rows, may "
                                   "hold words; make it a row of numbers, a comment ('# ...'), or remove it: "
                                   "expected " + expected);
      if (header_line == 0) header_line = line_no;
      else if (second_words_line == 0) second_words_line = line_no, second_words = line.substr(first);
      continue;
    }
    // Before any row, a line that neither starts with a number nor is words
    // ('[material]' of a scene, '// ...' of a geometry, '<?xml' of a VTK file).
    if (!starts_with_number && rows.empty())
      throw file_error(path, "line " + std::to_string(line_no) + ": '" + clipped(line.substr(first)) +
                                 "' is no row of numbers, and no line before it holds one: a text file" + not_this);
    // A spreadsheet in a locale with decimal commas saves its CSV with ';'
    // between values ("0,002;0,001;0,0005"; before 7 December 2026
    // "expected ..." or "found 1 value", the separator unsaid).
    if (line.find(';') != std::string::npos)
      throw file_error(path, "line " + std::to_string(line_no) + ": '" + clipped(line.substr(first)) +
                                 "' separates its values by ';' (a spreadsheet's CSV where the decimal point is a "
                                 "comma?): separate them by commas or blanks, with '.' as the decimal point: "
                                 "expected " + expected);
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream fields(line);
    std::vector<std::string> texts;
    for (std::string text; fields >> text;) texts.push_back(text);
    // A row cut short says how short (before 7 December 2026 only "expected ...").
    if (texts.size() < columns)
      throw file_error(path, "line " + std::to_string(line_no) + ": found " + std::to_string(texts.size()) +
                                 (texts.size() == 1 ? " value" : " values") + ", expected " + std::to_string(columns) +
                                 ": " + expected);
    NumberRow row{line_no, std::vector<double>(columns)};
    for (std::size_t i = 0; i < columns; ++i) {
      const std::string& text = texts[i];
      double& v = row.values[i];
      char* end = nullptr;
      v = std::strtod(text.c_str(), &end);
      if (end == text.c_str() || *end != '\0')
        throw file_error(path, "line " + std::to_string(line_no) + ": expected " + expected);
      if (!std::isfinite(v))
        throw file_error(path, "line " + std::to_string(line_no) + ": '" + text +
                                   "' is not a finite number: expected " + expected);
    }
    // A value more (a radius in another column, two rows run together) is no row of this file.
    if (texts.size() > columns)
      throw file_error(path, "line " + std::to_string(line_no) + ": more than " + std::to_string(columns) +
                                 " values ('" + texts[columns] + "' after them): expected " + expected);
    rows.push_back(std::move(row));
  }
  // A header and nothing else is this file with no row; a second line of
  // words and no row is some other text.
  if (rows.empty() && second_words_line > 0)
    throw file_error(path, "line " + std::to_string(second_words_line) + ": '" + clipped(second_words) +
                               "' is a second line of words after the header (line " + std::to_string(header_line) +
                               "), and no line holds numbers: a text file" + not_this);
  return rows;
}

}  // namespace pd::post
