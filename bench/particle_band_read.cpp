// Peak resident set of reading a particle file as a distributed run's
// process would: whole and compact (what every process reads today), or one
// slab's band (read_particle_band) of `size` equal-width slabs along x,
// widened by three bond reaches (docs/solver.md, "A slab's band of the
// particle file"). Built and run by bench/particle_band_read.sh.
#include <sys/resource.h>

#include <cstdio>
#include <string>

#include "compact_families.hpp"
#include "families.hpp"
#include "particle_band.hpp"

int main(int argc, char** argv) {
  if (argc < 3 || (std::string(argv[2]) == "band" && argc < 5)) {
    std::fprintf(stderr, "usage: %s PARTICLE_FILE whole | band RANK SIZE\n", argv[0]);
    return 2;
  }
  const std::string path = argv[1];
  if (std::string(argv[2]) == "whole") {
    const auto read = pd::read_compact_particle_file(path);
    std::printf("whole: %zu particles, %zu listed bonds", read.particles.size(), read.families.neighbors.size());
  } else {
    const int rank = std::stoi(argv[3]), size = std::stoi(argv[4]);
    double lo = 0, hi = 0;
    {
      // The first pass: the cells and family lengths, no family kept.
      const pd::ParticleSet cells = pd::read_particle_file(
          path, [](const pd::ParticleSet&, std::uint32_t, const std::uint32_t*, const double*, std::size_t) {});
      const double reach = pd::longest_possible_bond(cells);
      const double width = (cells.xmax - cells.xmin) / size;
      lo = cells.xmin + rank * width - 3 * reach;
      hi = cells.xmin + (rank + 1) * width + 3 * reach;
    }
    const pd::ParticleBand band = pd::read_particle_band(path, 0, lo, hi);
    std::printf("band %d of %d: %zu of %zu particles, %zu listed bonds", rank, size, band.particles.size(),
                band.whole_count, band.families.neighbors.size());
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf(", peak %.1f MiB\n", static_cast<double>(usage.ru_maxrss) / 1024.0);
}
