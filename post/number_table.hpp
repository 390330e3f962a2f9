#pragma once
// Small CSV inputs of numbers (pore circles, branch boxes): one row per line,
// comma- or space-separated; blank lines, '#' comments and a header line
// (starting with a letter) are skipped.
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
// if unreadable.
std::vector<NumberRow> read_number_table(const std::string& path, std::size_t columns, const std::string& what,
                                         const std::string& expected);

}  // namespace pd::post
