// A particle set that its bonds leave in two pieces, without any pre-crack
// (docs/robustness.md): a grid that dropped a neck or a ligament of the
// geometry. pd-solve ran it without a word (the pieces were counted only in
// scenes with pre-cracks); it says so in the plan and in summary.json.
#include <catch2/catch.hpp>
#include <fstream>
#include <string>

#include "lattice.hpp"
#include "particle_file.hpp"
#include "../test_folder.hpp"
#include "../test_commands.hpp"

namespace {

using namespace pd::test_support;

// The 10 mm x 6 mm lattice plate (dx = 1 mm, horizon 3 mm) with its bonds
// across x = `cut_x` removed when `cut_x` > 0: two pieces, 5 and 5 columns.
pd::ParticleSet plate(double cut_x) {
  auto p = pd::make_rectangle_lattice(10e-3, 6e-3, 1e-3, 3e-3, pd::Quadrature::analytic);
  if (cut_x <= 0) return p;
  std::vector<std::uint64_t> offsets{0};
  std::vector<std::uint32_t> neighbors;
  std::vector<double> partial_volume;
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (auto b = p.family_offsets[i]; b < p.family_offsets[i + 1]; ++b) {
      const auto j = p.neighbors[b];
      if ((p.x[i] < cut_x) != (p.x[j] < cut_x)) continue;
      neighbors.push_back(j);
      partial_volume.push_back(p.partial_volume[b]);
    }
    offsets.push_back(neighbors.size());
  }
  p.family_offsets = std::move(offsets);
  p.neighbors = std::move(neighbors);
  p.partial_volume = std::move(partial_volume);
  return p;
}

}  // namespace

TEST_CASE("a particle set in pieces without pre-cracks is said in the plan and in summary.json",
          "[robustness][pieces]") {
  const auto folder = fresh_folder_under(PD_TEST_TMPDIR, "pieces");
  std::ofstream(folder + "/scene.toml") << "particles = \"plate.pdp\"\n"
                                           "[material]\nyoungs_modulus = 3.24e9\ndensity = 1190\n"
                                           "fracture_energy = 200\n"
                                           "[time]\nstep = \"auto\"\nend = 1e-6\n"
                                           "[[loads]]\nset = \"right\"\ntype = \"velocity\"\nx = 0.3\n";
  const auto solve = [&](double cut_x, const std::string& name) {
    pd::write_particle_file(folder + "/plate.pdp", plate(cut_x));
    const auto log = folder + "/" + name + ".log";
    const int status =
        run_shell(std::string(PD_SOLVE_EXECUTABLE) + " " + folder + "/scene.toml --threads 1 -o " + folder + "/" +
                  name + " > " + log + " 2>&1");
    INFO(file_text(log));
    REQUIRE(status == 0);
    return file_text(log) + file_text(folder + "/" + name + "/summary.json");
  };
  const auto two = solve(5e-3, "two");
  CHECK_THAT(two, Catch::Contains("the particle set falls into 2 pieces that no intact bond joins (the largest of "
                                  "30 and 30 particles)") &&
                      Catch::Contains("neck or a ligament") && Catch::Contains("\"pieces\": 2"));
  const auto one = solve(0, "one");
  CHECK_THAT(one, Catch::Contains("\"pieces\": 1"));
  CHECK(one.find("pieces that no intact bond joins") == std::string::npos);
}
