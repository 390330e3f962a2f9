#pragma once
// Parsing of physical quantities given on the command line or in scene files.
// Everything inside the toolchain is SI; users may write lengths with a unit.
#include <string>

namespace pd {

// Parses a length such as "0.04mm", "40um", "4e-5m" or "4e-5 m" and returns metres.
// A bare number (no unit) is rejected, because 0.04 could mean metres or millimetres.
// `what` names the option or key in error messages.
double parse_length(const std::string& text, const std::string& what);

// The same for a length that must be more than 0: pd::Error "WHAT: TEXT is
// not a positive length (e.g. WHAT 1mm)" for 0 or less.
double parse_positive_length(const std::string& text, const std::string& what);

// Parses a finite floating-point number, the whole string; error names `what`.
double parse_number(const std::string& text, const std::string& what);

// A plain number typed for a command-line option (no unit), the one reading
// of every tool's number options: the whole text, one number ("nan" and
// "inf" are read, for the caller's range check to refuse in its words);
// anything else (a unit, a letter, hexadecimal, white space around it) is
// pd::Error "OPTION TEXT: ADVICE", ADVICE saying what the option takes
// ("expected a number of spacings (delta = m dx, e.g. -m 3)").
double number_as_typed(const std::string& text, const std::string& option, const std::string& advice);

// The same for a number that must be finite: "OPTION TEXT: ADVICE" for nan
// and inf too.
double finite_number_as_typed(const std::string& text, const std::string& option, const std::string& advice);

// A length given for `option` [m] held to the range from `shortest` to
// `longest` [m], which the message names (`shortest_name`: "run's particle
// spacing", `longest_name`: "plate's diagonal", `range`: "the spacing to the
// plate's diagonal"): pd::Error "OPTION L mm is longer than the plate's
// diagonal (D mm): give a length from the spacing to the plate's diagonal,
// S to D mm, with its unit (e.g. OPTION EXAMPLE)" outside it (a unit or an
// exponent gone wrong: 1e300m, 1e-300m).
void check_length_in_range(double length, const std::string& option, double shortest,
                           const std::string& shortest_name, double longest, const std::string& longest_name,
                           const std::string& range, const std::string& example);

// Factor that converts a unit name ("m", "mm", "um") to metres; error for others.
double length_unit_in_metres(const std::string& unit, const std::string& what);

// Formats metres as millimetres with a unit, for messages ("0.04 mm").
std::string format_mm(double metres);

// A size in memory or on disk for messages, decimal units with three
// significant digits: MB below 1 GB (a small disk then reads "512 MB", not
// "0 GB"), GB, TB from 1e12 ("0.0192 MB", "76.4 GB", "6.33 TB").
std::string format_bytes(double bytes);

// A double as written: the shortest form from 6 significant digits on that
// reads back to the same value ("1.19", not "1.1899999999999999"; "100", "3e-07");
// a subnormal one from 1 digit ("1e-320", not "9.99989e-321").
std::string shortest_text(double value);

// A double as a stream prints it by default (6 significant digits: "2.22507e-308"),
// for plan lines and messages about computed quantities.
std::string format_number(double value);

// A time on a command line: seconds as a plain number ("2e-6"), or with its
// unit ("2us", "2 us"); error naming `what` otherwise, with an example whose
// unit is attached ("80us").
double parse_time(const std::string& text, const std::string& what);

// The kinds of quantity a scene may write with a unit (docs/scenes.md, "Units").
enum class Quantity { length, time, stress, density, energy_per_area };

// The SI unit a plain number of this kind is read in ("Pa", "kg/m^3", ...).
const char* si_unit(Quantity quantity);

// How the examples in parse_quantity's errors write a unit: after a space, as
// a scene's string does ("80 us"), or attached, as a command line takes it
// in one argument ("80us"). Both forms parse; only the advice differs.
enum class UnitSpacing { spaced, attached };

// Parses a value written with its unit, e.g. "3.24 GPa", "1.19 g/cm^3",
// "0.35 kJ/m^2", "5 mm", "80 us", and returns it in SI units. A missing or
// unknown unit is an error that names `what` and lists the units known.
double parse_quantity(const std::string& text, Quantity quantity, const std::string& what,
                      UnitSpacing examples = UnitSpacing::spaced);

// Where a plain SI number of this kind is believable for a brittle plate
// (e.g. Young's modulus 1e5 to 2e12 Pa). A number outside is most likely in
// another unit (3.24 for 3.24 GPa); `unit_hint` then names the unit that
// brings it nearest the middle of the range, e.g. "GPa", or "" if none does.
struct PlausibleRange {
  double low, high;
  const char* what;  // "the Young's moduli of solids"
};
PlausibleRange plausible_range(Quantity quantity);
std::string unit_hint(double plain_number, Quantity quantity);

}  // namespace pd
