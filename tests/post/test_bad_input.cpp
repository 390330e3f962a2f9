// Every rejection of bad input names the path or the array involved.
#include <catch2/catch.hpp>
#include <filesystem>

#include "error.hpp"
#include "post_pipeline.hpp"
#include "synthetic_output.hpp"

using namespace pd::post;
using namespace pd::post::test;
using Catch::Matchers::Contains;

namespace {
PostOptions options_for(const std::string& dir) {
  PostOptions o;
  o.outdir = dir;
  return o;
}
double cracked_row(double x, double y) { return std::abs(y - 1.05e-3) < 1e-5 ? x / 500.0 : -1; }
}  // namespace

TEST_CASE("a missing output directory is reported with its path", "[bad-input]") {
  const std::string dir = std::string(PD_POST_TEST_TMPDIR) + "/does_not_exist";
  std::filesystem::remove_all(dir);
  CHECK_THROWS_WITH(analyse(options_for(dir)), Contains(dir) && Contains("directory not found"));
}

TEST_CASE("a directory without arrival.vtp is reported", "[bad-input]") {
  const auto dir = fresh_dir("no_arrival");
  CHECK_THROWS_WITH(analyse(options_for(dir)), Contains(dir + "/arrival.vtp") && Contains("not found"));
}

TEST_CASE("a threshold without its arrival array is reported with the array name", "[bad-input]") {
  const auto dir = fresh_dir("wrong_threshold");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), cracked_row, 10e-6, {0.5});
  CHECK_THROWS_WITH(analyse(options_for(dir)),
                    Contains("arrival_time_0.35") && Contains("arrival_time_0.50") && Contains("arrival.vtp"));
  // The array that exists is accepted.
  PostOptions o = options_for(dir);
  o.threshold = 0.5;
  CHECK_NOTHROW(analyse(o));
}

TEST_CASE("an empty crack is reported", "[bad-input]") {
  const auto dir = fresh_dir("empty_crack");
  write_arrival_output(dir, make_lattice(4e-3, 2e-3, 0.1e-3), [](double, double) { return -1.0; }, 10e-6);
  CHECK_THROWS_WITH(analyse(options_for(dir)), Contains("empty crack") && Contains("arrival_time_0.35"));
}
