// Length parsing: units are explicit because 0.04 could be metres or millimetres.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <limits>

#include "error.hpp"
#include "units.hpp"

TEST_CASE("lengths are parsed with their unit into metres", "[units]") {
  CHECK(pd::parse_length("0.04mm", "--spacing") == Approx(4e-5).epsilon(1e-15));
  CHECK(pd::parse_length("40um", "--spacing") == Approx(4e-5).epsilon(1e-15));
  CHECK(pd::parse_length("4e-5m", "--spacing") == Approx(4e-5).epsilon(1e-15));
  CHECK(pd::parse_length("1.5e-1 mm", "--spacing") == Approx(1.5e-4).epsilon(1e-15));
}

TEST_CASE("lengths without a unit, with an unknown unit or non-finite are rejected", "[units]") {
  CHECK_THROWS_WITH(pd::parse_length("0.04", "--spacing"), Catch::Contains("--spacing") && Catch::Contains("no unit"));
  CHECK_THROWS_WITH(pd::parse_length("0.04in", "--spacing"), Catch::Contains("unknown length unit 'in'"));
  CHECK_THROWS_WITH(pd::parse_length("nanmm", "--horizon"), Catch::Contains("--horizon"));
  CHECK_THROWS_WITH(pd::parse_length("inf mm", "--horizon"), Catch::Contains("--horizon"));
  CHECK_THROWS_WITH(pd::parse_length("abcmm", "--horizon"), Catch::Contains("not a number"));
  // Letters only: the whole value is named, not an empty number.
  CHECK_THROWS_WITH(pd::parse_length("nanmm", "--horizon"), Catch::Contains("'nanmm' is not a number"));
  // Characters after the unit are no missing unit (the advice was '2mm,mm').
  CHECK_THROWS_WITH(pd::parse_length("2mm,", "--spacing"),
                    Catch::Contains("--spacing: '2mm,' has characters after the length '2mm' (',')") &&
                        !Catch::Contains("2mm,mm"));
  CHECK_THROWS_WITH(pd::parse_length("2,mm", "--spacing"), Catch::Contains("'2,mm' is not a length"));
  CHECK_THROWS_WITH(pd::parse_length("", "--spacing"), Catch::Contains("'' is not a length"));
}

TEST_CASE("quantities with a unit are converted to SI, and a plain number's likely unit is named", "[units]") {
  using pd::Quantity;
  CHECK(pd::parse_quantity("3.24 GPa", Quantity::stress, "E") == Approx(3.24e9).epsilon(1e-15));
  CHECK(pd::parse_quantity("3.24GPa", Quantity::stress, "E") == Approx(3.24e9).epsilon(1e-15));
  CHECK(pd::parse_quantity("6 N/mm^2", Quantity::stress, "E") == Approx(6e6).epsilon(1e-15));
  CHECK(pd::parse_quantity("1.19 g/cm^3", Quantity::density, "rho") == Approx(1190).epsilon(1e-15));
  CHECK(pd::parse_quantity("0.35 N/mm", Quantity::energy_per_area, "G0") == Approx(350).epsilon(1e-15));
  CHECK(pd::parse_quantity("80 us", Quantity::time, "end") == Approx(8e-5).epsilon(1e-15));
  CHECK(pd::parse_quantity("2 mm", Quantity::length, "h") == Approx(2e-3).epsilon(1e-15));
  CHECK_THROWS_WITH(pd::parse_quantity("3.24", Quantity::stress, "E"), Catch::Contains("E: '3.24' has no unit"));
  CHECK_THROWS_WITH(pd::parse_quantity("3.24 psi", Quantity::stress, "E"), Catch::Contains("unknown unit 'psi'"));
  CHECK_THROWS_WITH(pd::parse_quantity("nan GPa", Quantity::stress, "E"), Catch::Contains("not a finite number"));
  // Finite as written, not in SI: 1e300 GPa overflows, 1e-320 us underflows to 0.
  CHECK_THROWS_WITH(pd::parse_quantity("1e300 GPa", Quantity::stress, "E"),
                    Catch::Contains("E: '1e300 GPa' is beyond the range of numbers in Pa"));
  CHECK_THROWS_WITH(pd::parse_quantity("1e-320 us", Quantity::time, "end"), Catch::Contains("beyond the range of numbers in s"));
  CHECK_THROWS_WITH(pd::parse_quantity("GPa", Quantity::stress, "E"), Catch::Contains("not a number with a unit"));
  // The unit that brings a plain number nearest the middle of its believable range.
  CHECK(pd::unit_hint(3.24, Quantity::stress) == "GPa");
  CHECK(pd::unit_hint(3240, Quantity::stress) == "MPa");
  CHECK(pd::unit_hint(1.19, Quantity::density) == "g/cm^3");
  CHECK(pd::unit_hint(5, Quantity::length) == "mm");
  CHECK(pd::unit_hint(1e300, Quantity::stress).empty());
  CHECK(pd::unit_hint(1e-3, Quantity::time).empty());  // times have no believable range
}

TEST_CASE("command-line times are seconds or carry their unit", "[units]") {
  CHECK(pd::parse_time("2e-6", "--window-time") == 2e-6);
  CHECK(pd::parse_time("2us", "--window-time") == Approx(2e-6).epsilon(1e-15));
  CHECK(pd::parse_time("150 us", "--times") == Approx(1.5e-4).epsilon(1e-15));
  CHECK_THROWS_WITH(pd::parse_time("nan", "--times"), Catch::Contains("--times: 'nan' is not a finite number"));
  CHECK_THROWS_WITH(pd::parse_time("2 mm", "--times"), Catch::Contains("--times: unknown unit 'mm'"));
}

TEST_CASE("an error's example writes the unit as its caller takes it", "[units]") {
  using pd::Quantity;
  // A command line takes one word, a scene's string a space before the unit.
  CHECK_THROWS_WITH(pd::parse_time("abc", "--times"), "--times: 'abc' is not a number with a unit (e.g. '80us')");
  CHECK_THROWS_WITH(pd::parse_time("0x10us", "--times"),
                    "--times: '0x10us' is not a decimal number with a unit (e.g. '80us')");
  CHECK_THROWS_WITH(pd::parse_quantity("abc", Quantity::time, "end"), "end: 'abc' is not a number with a unit (e.g. '80 us')");
  CHECK_THROWS_WITH(pd::parse_quantity("abc", Quantity::stress, "E", pd::UnitSpacing::attached),
                    "E: 'abc' is not a number with a unit (e.g. '3.24GPa')");
  CHECK_THROWS_WITH(pd::parse_quantity("GPa", Quantity::stress, "E"), "E: 'GPa' is not a number with a unit (e.g. '3.24 GPa')");
  // pd-mesh's and pd-post's lengths: attached, as they were.
  CHECK_THROWS_WITH(pd::parse_length("abc", "--spacing"), "--spacing: 'abc' is not a number with a unit (e.g. 0.5mm)");
  CHECK_THROWS_WITH(pd::parse_length("2", "--spacing"), "--spacing: '2' has no unit; write it as e.g. '2mm' or '2m'");
  CHECK_THROWS_WITH(pd::parse_length("2,3", "--horizon"),
                    "--horizon: '2,3' is not a length (a number with a unit, e.g. 0.5mm)");
}

TEST_CASE("units take the Greek mu and no-break spaces, and hexadecimal and embedded NUL are refused", "[units]") {
  using pd::Quantity;
  CHECK(pd::parse_quantity("20 \xCE\xBCs", Quantity::time, "end") == Approx(2e-5).epsilon(1e-15));  // Greek mu
  CHECK(pd::parse_quantity("20 \xC2\xB5s", Quantity::time, "end") == Approx(2e-5).epsilon(1e-15));  // micro sign
  CHECK(pd::parse_quantity("3.24\xC2\xA0GPa", Quantity::stress, "E") == Approx(3.24e9).epsilon(1e-15));
  CHECK(pd::parse_quantity("3.24\xE2\x80\xAFGPa", Quantity::stress, "E") == Approx(3.24e9).epsilon(1e-15));
  CHECK(pd::parse_length("500\xCE\xBCm", "--spacing") == Approx(5e-4).epsilon(1e-15));
  CHECK(pd::parse_time("5\xCE\xBCs", "--times") == Approx(5e-6).epsilon(1e-15));
  CHECK_THROWS_WITH(pd::parse_quantity("0x10 Pa", Quantity::stress, "E"), Catch::Contains("not a decimal number"));
  CHECK_THROWS_WITH(pd::parse_quantity(std::string("3.24 GPa\0", 9), Quantity::stress, "E"),
                    Catch::Contains("not a decimal number"));
  CHECK_THROWS_WITH(pd::parse_time("0x14", "--times"), Catch::Contains("not a decimal number"));
}

// Sizes on disk in messages: below 1 GB in MB (the snapshot-space check of
// pd-solve said "0 GB" free in whole gigabytes before), then GB and TB.
TEST_CASE("sizes on disk are shown in MB below 1 GB, in GB and TB above", "[units]") {
  CHECK(pd::format_bytes(19200) == "0.0192 MB");
  CHECK(pd::format_bytes(512.3e6) == "512 MB");
  CHECK(pd::format_bytes(76.43e9) == "76.4 GB");
  CHECK(pd::format_bytes(6329.4e9) == "6.33 TB");
}

// A number quoted back in a message reads as written. A subnormal double
// holds fewer than 6 digits: before 7 December 2026 1e-320 read back as
// "9.99989e-321" (increments = [[2, 1e-320]] was refused as "load factor
// 9.99989e-321"), a number nobody wrote.
TEST_CASE("a double is quoted in its shortest form that reads back, subnormal ones too", "[units]") {
  CHECK(pd::shortest_text(1.19) == "1.19");
  CHECK(pd::shortest_text(100) == "100");
  CHECK(pd::shortest_text(3e-7) == "3e-07");
  CHECK(pd::shortest_text(0.1 + 0.2) == "0.30000000000000004");
  CHECK(pd::shortest_text(1e-320) == "1e-320");
  CHECK(pd::shortest_text(-2e-320) == "-2e-320");
  CHECK(pd::shortest_text(5e-324) == "5e-324");
  CHECK(pd::shortest_text(1e-309) == "1e-309");
  CHECK(pd::shortest_text(1.2345678e-310) == "1.2345678e-310");
  CHECK(pd::shortest_text(std::numeric_limits<double>::min()) == "2.2250738585072014e-308");
  CHECK(pd::shortest_text(0) == "0");
  for (const double v : {1e-320, 4.9406564584124654e-324, 1.2345678e-310, 2.2250738585072009e-308})
    CHECK(std::strtod(pd::shortest_text(v).c_str(), nullptr) == v);
}
