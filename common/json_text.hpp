#pragma once
// JSON text as the tools write it (pd-solve's and pd-post's summary.json,
// pd-mesh's provenance): strings that JSON readers take whatever bytes a
// path or a name holds.
#include <string>

namespace pd {

// `s` as a quoted JSON string: '"' and '\\' escaped, a control character
// escaped (a newline as \n, a tab as \t, another as \u00XX), well-formed UTF-8
// kept as it is, and a byte that begins no UTF-8 sequence (a folder named in
// Latin-1) written as U+FFFD, the replacement character: JSON is UTF-8 text,
// and readers refuse such a byte.
std::string json_string(const std::string& s);

// `v` as a JSON number in the shortest text that reads back to it (a reader
// gets the double the tool used), a whole number below 2^53 in full, 0 for
// -0, and null if not finite (JSON has no NaN or infinity).
std::string json_number(double v);

}  // namespace pd
