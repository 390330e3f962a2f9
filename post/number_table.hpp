#pragma once
// Small CSV inputs of numbers (pore circles, branch boxes): one row per line,
// comma- or space-separated; blank lines, '#' comments and a header line
// (starting with a letter) before the rows is skipped; words after the
// first row are refused. A spreadsheet's byte order mark (UTF-8) and CR LF
// line ends are read past; UTF-16 text and values separated by ';' are
// refused saying so.
#include <string>
#include <vector>

namespace pd::post {

struct NumberRow {
  int line = 0;                // line number in the file, for messages
  std::vector<double> values;  // exactly `columns` values
};

// Throws pd::Error "PATH: line N: found K values, expected COLUMNS: EXPECTED"
// for a row of fewer values, "PATH: line N: ... expected EXPECTED" for one
// that does not hold exactly `columns` numbers, and "PATH: cannot open WHAT"
// if unreadable. A file that is no such table is refused as not WHAT: a
// particle file, binary data (a NUL byte), text whose first line that is
// not words does not start with a number ('[material]' of a scene), or text
// with no row and more than one line of words ("PATH: line N: 'TEXT' is a second line of words after
// the header (line M), and no line holds numbers: a text file, not WHAT:
// expected a text file of lines EXPECTED, one per line"). A line of words
// after a row is refused: "PATH: line N: 'TEXT' is a line of words after the
// rows (the first on line M): ...".
std::vector<NumberRow> read_number_table(const std::string& path, std::size_t columns, const std::string& what,
                                         const std::string& expected);

}  // namespace pd::post
