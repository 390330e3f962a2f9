// Length parsing: units are explicit because 0.04 could be metres or millimetres.
#include <catch2/catch.hpp>

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
}
