#include "units.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "error.hpp"

namespace pd {

double parse_number(const std::string& text, const std::string& what) {
  const char* begin = text.c_str();
  char* end = nullptr;
  const double value = std::strtod(begin, &end);
  while (end && *end && std::isspace(static_cast<unsigned char>(*end))) ++end;
  if (end == begin || (end && *end != '\0'))
    throw Error(what + ": '" + text + "' is not a number");
  if (!std::isfinite(value)) throw Error(what + ": '" + text + "' is not a finite number");
  return value;
}

double length_unit_in_metres(const std::string& unit, const std::string& what) {
  if (unit == "m") return 1.0;
  if (unit == "mm") return 1e-3;
  if (unit == "um" || unit == "µm") return 1e-6;
  if (unit == "cm") return 1e-2;
  throw Error(what + ": unknown length unit '" + unit + "' (use m, cm, mm or um)");
}

double parse_length(const std::string& text, const std::string& what) {
  std::size_t split = text.size();
  while (split > 0 && (std::isalpha(static_cast<unsigned char>(text[split - 1])) ||
                       static_cast<unsigned char>(text[split - 1]) >= 0x80))
    --split;
  std::string number = text.substr(0, split);
  const std::string unit = text.substr(split);
  if (unit.empty())
    throw Error(what + ": '" + text + "' has no unit; write it as e.g. '" + text + "mm' or '" +
                text + "m'");
  while (!number.empty() && std::isspace(static_cast<unsigned char>(number.back())))
    number.pop_back();
  // "nanmm", "infm": letters only, so no number is left to name.
  if (number.empty()) throw Error(what + ": '" + text + "' is not a number with a unit (e.g. 0.5mm)");
  // strtod would read "1e" of "1em"; the unit split above already took letters,
  // so an exponent must be followed by digits to survive here.
  return parse_number(number, what) * length_unit_in_metres(unit, what);
}

std::string format_mm(double metres) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.6g mm", metres * 1e3);
  return buffer;
}

}  // namespace pd
