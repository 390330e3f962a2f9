#include "units.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <vector>

#include "error.hpp"

namespace pd {

namespace {

struct Unit {
  const char* name;
  double in_si;
};

const std::vector<Unit>& units_of(Quantity quantity) {
  static const std::vector<Unit> length{{"m", 1}, {"cm", 1e-2}, {"mm", 1e-3}, {"um", 1e-6}, {"µm", 1e-6}};
  static const std::vector<Unit> time{{"s", 1}, {"ms", 1e-3}, {"us", 1e-6}, {"µs", 1e-6}, {"ns", 1e-9}};
  static const std::vector<Unit> stress{{"Pa", 1},   {"kPa", 1e3},    {"MPa", 1e6},
                                        {"GPa", 1e9}, {"N/m^2", 1}, {"N/mm^2", 1e6}};
  static const std::vector<Unit> density{{"kg/m^3", 1}, {"g/cm^3", 1e3}};
  static const std::vector<Unit> energy_per_area{{"J/m^2", 1}, {"N/m", 1}, {"kJ/m^2", 1e3}, {"N/mm", 1e3}};
  switch (quantity) {
    case Quantity::length: return length;
    case Quantity::time: return time;
    case Quantity::stress: return stress;
    case Quantity::density: return density;
    case Quantity::energy_per_area: return energy_per_area;
  }
  return length;
}

std::string unit_list(Quantity quantity) {
  std::string list;
  for (const auto& u : units_of(quantity)) list += std::string(list.empty() ? "" : ", ") + u.name;
  return list;
}

std::string example_of(Quantity quantity, UnitSpacing spacing) {
  const char* spaced = "";
  switch (quantity) {
    case Quantity::length: spaced = "5 mm"; break;
    case Quantity::time: spaced = "80 us"; break;
    case Quantity::stress: spaced = "3.24 GPa"; break;
    case Quantity::density: spaced = "1.19 g/cm^3"; break;
    case Quantity::energy_per_area: spaced = "0.35 kJ/m^2"; break;
  }
  std::string example = spaced;
  if (spacing == UnitSpacing::attached) example.erase(example.find(' '), 1);
  return example;
}

// The text as the parsers read it: the Greek mu (U+03BC) as the micro sign
// (U+00B5) of the unit tables, no-break spaces (U+00A0, U+202F) as spaces.
std::string normalised(const std::string& text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text.compare(i, 2, "\xCE\xBC") == 0) out += "\xC2\xB5", ++i;
    else if (text.compare(i, 2, "\xC2\xA0") == 0) out += ' ', ++i;
    else if (text.compare(i, 3, "\xE2\x80\xAF") == 0) out += ' ', i += 2;
    else out += text[i];
  }
  return out;
}

// A decimal number leads `text` (strtod also reads hexadecimal, "0x10").
bool starts_decimal(const std::string& text) {
  std::size_t i = text.find_first_not_of(" \t");
  if (i != std::string::npos && (text[i] == '+' || text[i] == '-')) ++i;
  return i != std::string::npos && !(text.compare(i, 2, "0x") == 0 || text.compare(i, 2, "0X") == 0);
}

// A decimal number and nothing else but blanks around it.
bool is_plain_number(const std::string& text) {
  if (!starts_decimal(text)) return false;
  const char* begin = text.c_str();
  char* end = nullptr;
  std::strtod(begin, &end);
  while (end && *end && std::isspace(static_cast<unsigned char>(*end))) ++end;
  return end != begin && end && *end == '\0';
}

}  // namespace

double length_unit_in_metres(const std::string& unit, const std::string& what) {
  for (const auto& u : units_of(Quantity::length))
    if (unit == u.name) return u.in_si;
  throw Error(what + ": unknown length unit '" + clipped(unit) + "' (use " + unit_list(Quantity::length) + ")");
}

double parse_number(const std::string& text, const std::string& what) {
  if (!starts_decimal(text)) throw Error(what + ": '" + clipped(text) + "' is not a decimal number");
  const char* begin = text.c_str();
  char* end = nullptr;
  const double value = std::strtod(begin, &end);
  while (end && *end && std::isspace(static_cast<unsigned char>(*end))) ++end;
  if (end == begin || (end && *end != '\0'))
    throw Error(what + ": '" + clipped(text) + "' is not a number");
  if (!std::isfinite(value)) throw Error(what + ": '" + clipped(text) + "' is not a finite number");
  return value;
}

// (Before 7 December 2026 pd-mesh's own, and the validation tools and
// pd-post read their numbers with parse_number's words instead.)
double number_as_typed(const std::string& text, const std::string& option, const std::string& advice) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  const bool whole = end != text.c_str() && *end == '\0' && !std::isspace(static_cast<unsigned char>(text[0]));
  const bool hexadecimal = text.find_first_of("xX") != std::string::npos && std::isfinite(value);
  if (!whole || hexadecimal) throw Error(option + " " + clipped(text) + ": " + advice);
  return value;
}

double finite_number_as_typed(const std::string& text, const std::string& option, const std::string& advice) {
  const double value = number_as_typed(text, option, advice);
  if (!std::isfinite(value)) throw Error(option + " " + clipped(text) + ": " + advice);
  return value;
}

void check_length_in_range(double length, const std::string& option, double shortest,
                           const std::string& shortest_name, double longest, const std::string& longest_name,
                           const std::string& range, const std::string& example) {
  if (length >= shortest * (1 - 1e-9) && length <= longest * (1 + 1e-9)) return;
  const bool shorter = length < shortest;
  char text[600];
  std::snprintf(text, sizeof text,
                "%s %g mm is %s than the %s (%g mm): give a length from %s, %g to %g mm, with its unit (e.g. %s %s)",
                option.c_str(), length * 1e3, shorter ? "shorter" : "longer",
                (shorter ? shortest_name : longest_name).c_str(), (shorter ? shortest : longest) * 1e3, range.c_str(),
                shortest * 1e3, longest * 1e3, option.c_str(), example.c_str());
  throw Error(text);
}

double parse_length(const std::string& written, const std::string& what) {
  const std::string text = normalised(written);
  std::size_t split = text.size();
  while (split > 0 && (std::isalpha(static_cast<unsigned char>(text[split - 1])) ||
                       static_cast<unsigned char>(text[split - 1]) >= 0x80))
    --split;
  std::string number = text.substr(0, split);
  const std::string unit = text.substr(split);
  if (unit.empty()) {
    // Only a plain number lacks just its unit; "2mm," lacks nothing but has
    // a character after it (before, the advice was to write '2mm,mm').
    if (!is_plain_number(text)) {
      const std::size_t last_letter = text.find_last_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ");
      if (last_letter != std::string::npos) {
        const std::string length = text.substr(0, last_letter + 1);
        bool is_length = true;
        try {
          parse_length(length, what);
        } catch (const Error&) {
          is_length = false;
        }
        if (is_length)
          throw Error(what + ": '" + clipped(text) + "' has characters after the length '" + clipped(length) +
                      "' ('" + clipped(text.substr(last_letter + 1)) + "'); give one length, e.g. '" +
                      clipped(length) + "'");
      }
      throw Error(what + ": '" + clipped(text) + "' is not a length (a number with a unit, e.g. 0.5mm)");
    }
    throw Error(what + ": '" + clipped(text) + "' has no unit; write it as e.g. '" + clipped(text) + "mm' or '" +
                clipped(text) + "m'");
  }
  while (!number.empty() && std::isspace(static_cast<unsigned char>(number.back())))
    number.pop_back();
  // "nanmm", "infm": letters only, so no number is left to name.
  if (number.empty()) throw Error(what + ": '" + clipped(text) + "' is not a number with a unit (e.g. 0.5mm)");
  // "2mm,3mm", "2,mm": more than a number before the unit.
  if (starts_decimal(number) && !is_plain_number(number))
    throw Error(what + ": '" + clipped(text) + "' is not a length (a number with a unit, e.g. 0.5mm)");
  // strtod would read "1e" of "1em"; the unit split above already took letters,
  // so an exponent must be followed by digits to survive here.
  return parse_number(number, what) * length_unit_in_metres(unit, what);
}

double parse_positive_length(const std::string& text, const std::string& what) {
  const double v = parse_length(text, what);
  if (!(v > 0)) throw Error(what + ": " + clipped(text) + " is not a positive length (e.g. " + what + " 1mm)");
  return v;
}

const char* si_unit(Quantity quantity) { return units_of(quantity).front().name; }

double parse_quantity(const std::string& written, Quantity quantity, const std::string& what, UnitSpacing examples) {
  const std::string text = normalised(written);
  if (text.find('\0') != std::string::npos || !starts_decimal(text)) {
    std::string shown;  // (a NUL would end the message)
    for (char c : written) shown += c == '\0' ? std::string("\\0") : std::string(1, c);
    throw Error(what + ": '" + clipped(shown) + "' is not a decimal number with a unit (e.g. '" + example_of(quantity, examples) + "')");
  }
  const char* begin = text.c_str();
  char* end = nullptr;
  const double value = std::strtod(begin, &end);
  if (end == begin)
    throw Error(what + ": '" + clipped(text) + "' is not a number with a unit (e.g. '" + example_of(quantity, examples) + "')");
  std::string unit(end);
  while (!unit.empty() && std::isspace(static_cast<unsigned char>(unit.front()))) unit.erase(unit.begin());
  while (!unit.empty() && std::isspace(static_cast<unsigned char>(unit.back()))) unit.pop_back();
  if (!std::isfinite(value)) throw Error(what + ": '" + clipped(text) + "' is not a finite number");
  if (unit.empty())
    throw Error(what + ": '" + clipped(text) + "' has no unit; write a number in " + si_unit(quantity) +
                " without quotes, or the value with its unit (" + unit_list(quantity) + ")");
  // A unit below SI divides by its exact inverse (200 us = 200 / 1e6 s, the
  // double nearest 2e-4, as the plain number 2e-4 reads; 200 * 1e-6 is not).
  for (const auto& u : units_of(quantity))
    if (unit == u.name) {
      const double si = u.in_si >= 1 ? value * u.in_si : value / std::round(1 / u.in_si);
      // 1e300 GPa is a number as written, and beyond double's range in SI.
      if (!std::isfinite(si) || (si == 0 && value != 0))
        throw Error(what + ": '" + clipped(text) + "' is beyond the range of numbers in " + si_unit(quantity));
      return si;
    }
  throw Error(what + ": unknown unit '" + clipped(unit) + "' in '" + clipped(text) + "' (use " + unit_list(quantity) + ")");
}

double parse_time(const std::string& text, const std::string& what) {
  std::string trimmed = text;
  while (!trimmed.empty() && std::isspace(static_cast<unsigned char>(trimmed.back()))) trimmed.pop_back();
  const bool has_unit = !trimmed.empty() && (std::isalpha(static_cast<unsigned char>(trimmed.back())) ||
                                             static_cast<unsigned char>(trimmed.back()) >= 0x80) &&
                        trimmed != "nan" && trimmed != "inf" && trimmed != "-inf";
  return has_unit ? parse_quantity(trimmed, Quantity::time, what, UnitSpacing::attached) : parse_number(text, what);
}

PlausibleRange plausible_range(Quantity quantity) {
  switch (quantity) {
    // From soft polymers to diamond.
    case Quantity::stress: return {1e5, 2e12, "the Young's moduli of solids"};
    // From foams to the densest metals.
    case Quantity::density: return {10, 3e4, "the densities of solids"};
    // From brittle crystals (about twice their surface energy) to tough steels.
    case Quantity::energy_per_area: return {0.1, 1e7, "the fracture energies of solids"};
    // Films to thick slabs; 1 m is the unit thickness of a 2D model.
    case Quantity::length: return {1e-6, 1, "plate thicknesses"};
    case Quantity::time: return {0, INFINITY, "times"};
  }
  return {0, INFINITY, ""};
}

std::string unit_hint(double plain_number, Quantity quantity) {
  const PlausibleRange range = plausible_range(quantity);
  if (!(range.low > 0 && std::isfinite(range.high))) return "";
  const double middle = 0.5 * (std::log10(range.low) + std::log10(range.high));
  std::string best;
  double best_distance = INFINITY;
  for (const auto& u : units_of(quantity)) {
    const double si = plain_number * u.in_si;
    if (u.in_si == 1 || !(si >= range.low && si <= range.high)) continue;
    const double distance = std::abs(std::log10(si) - middle);
    if (distance < best_distance) best = u.name, best_distance = distance;
  }
  return best;
}

std::string shortest_text(double value) {
  char text[32];
  // From printf's default (100, not 1e+02); a subnormal double from 1 digit:
  // it holds fewer than 6, and 1e-320 read back at 6 is 9.99989e-321, a
  // number the user never wrote (before 7 December 2026). It prints in
  // exponent form at any count.
  const int first = value != 0 && std::fabs(value) < std::numeric_limits<double>::min() ? 1 : 6;
  for (int digits = first; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, value);
    if (std::strtod(text, nullptr) == value || !std::isfinite(value)) break;
  }
  return text;
}

std::string format_number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

std::string format_bytes(double bytes) {
  char buf[64];
  if (bytes >= 1e12)
    std::snprintf(buf, sizeof buf, "%.3g TB", bytes / 1e12);
  else if (bytes >= 1e9)
    std::snprintf(buf, sizeof buf, "%.3g GB", bytes / 1e9);
  else
    std::snprintf(buf, sizeof buf, "%.3g MB", bytes / 1e6);
  return buf;
}

std::string format_mm(double metres) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.6g mm", metres * 1e3);
  return buffer;
}

}  // namespace pd
