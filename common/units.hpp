#pragma once
// Parsing of physical quantities given on the command line or in scene files.
// Everything inside the toolchain is SI; users may write lengths with a unit.
#include <string>

namespace pd {

// Parses a length such as "0.04mm", "40um", "4e-5m" or "4e-5 m" and returns metres.
// A bare number (no unit) is rejected, because 0.04 could mean metres or millimetres.
// `what` names the option or key in error messages.
double parse_length(const std::string& text, const std::string& what);

// Parses a finite floating-point number, the whole string; error names `what`.
double parse_number(const std::string& text, const std::string& what);

// Factor that converts a unit name ("m", "mm", "um") to metres; error for others.
double length_unit_in_metres(const std::string& unit, const std::string& what);

// Formats metres as millimetres with a unit, for messages ("0.04 mm").
std::string format_mm(double metres);

}  // namespace pd
