#include "slab_band.hpp"

#include <limits>

#include "bond_setup.hpp"
#include "error.hpp"
#include "families.hpp"
#include "horizon_mode.hpp"
#include "particle_band.hpp"

namespace pd::solver {
namespace {

// `step`'s pd::Error as a BandSceneError.
template <class Step>
auto scene_part(Step&& step) {
  try {
    return step();
  } catch (const BandSceneError&) {
    throw;
  } catch (const Error& e) {
    throw BandSceneError(e.what());
  }
}

}  // namespace

std::string distributed_setup_refusal(const Scene& scene) {
  if (scene.refinement.enabled) return "[refinement] splits the whole particle set";
  if (scene.quasi_static.enabled) return "[quasi_static] runs on the whole plate";
  return {};
}

SlabBand read_slab_band(const Scene& scene, int rank, int size) {
  const std::string& path = scene.particle_file;
  SlabBand s;
  SlabCuts slabs;
  const auto choose = [&](const ParticleSet& whole) {
    // (Throws for a scene the horizons do not allow, as the whole plate's set-up would.)
    PlateHorizons& horizons = s.whole.horizons;
    horizons.mode = scene_part([&] { return horizon_mode(scene, whole); });
    horizons.horizon = horizons.mode == HorizonMode::uniform ? uniform_horizon(whole, path) : largest_horizon(whole);
    slabs = scene_part([&] { return slab_cuts(whole, file_family_lengths(whole), size, path); });
    const std::vector<double>& position = slabs.axis == 0 ? whole.x : whole.y;
    WholePlateFacts& w = s.whole;
    w.particle_count = whole.size();
    w.bond_count = whole.family_offsets.back();
    for (std::uint32_t i = 0; i < whole.size(); ++i)
      if (slabs.slab_of(position[i]) == rank) {
        w.owned_family_start.push_back(whole.family_offsets[i]);
        w.owned_family_length.push_back(
            static_cast<std::uint32_t>(whole.family_offsets[i + 1] - whole.family_offsets[i]));
      }
    // Three bond reaches (docs/solver.md, "A slab's band of the particle
    // file"): an owned particle's bonds read its family (r), a ghost's
    // directional shape (or state-based distortion factor and dilatation
    // row) its family (2 r), the lattice choice the shapes of a ghost's
    // neighbours (3 r). What reaches further (the coupled factors, the
    // state-based stable step's g_j / m_j^2 of a ghost) comes from the
    // ghost's owner (Simulation). With variable horizons r is the largest
    // horizon's: a ghost owning a bond towards the slab lies within r of it,
    // its family (its bonds' weights, its dilatation) within 2 r.
    const double reach = longest_possible_bond(whole) * static_cast<double>(s.band_width_reaches);
    constexpr double unbounded = std::numeric_limits<double>::max();
    const BandChoice band{slabs.axis, rank > 0 ? slabs.cuts[rank - 1] - reach : -unbounded,
                          rank < size - 1 ? slabs.cuts[rank] + reach : unbounded};
    // The particles the band keeps (read_particle_band's test), with where their families start in the file.
    if (horizons.mode != HorizonMode::uniform)
      for (std::uint32_t i = 0; i < whole.size(); ++i)
        if (position[i] >= band.lo && position[i] <= band.hi) w.band_family_start.push_back(whole.family_offsets[i]);
    return band;
  };
  const auto whole_arrays = [&](const ParticleSet& whole) {
    scene_part([&] {
      s.whole.loads = resolve_loads(scene, whole);
      if (scene.stop.enabled) s.stop_region = resolve_region(scene.stop.region, whole, scene.path, "stop");
    });
  };
  ParticleBand band = read_particle_band(path, choose, whole_arrays);
  if (s.whole.horizons.mode != HorizonMode::uniform && s.whole.band_family_start.size() != band.particles.size())
    throw Error(path + ": process " + std::to_string(rank) + " read " + std::to_string(band.particles.size()) +
                " particles of its band but chose " + std::to_string(s.whole.band_family_start.size()));
  // Dual horizons: a particle's row also holds the reactions of the bonds others own towards it.
  const GhostReach reach =
      s.whole.horizons.mode == HorizonMode::dual_horizon ? GhostReach::bonds_both_ways : GhostReach::own_bonds;
  s.partition = slab_partition_of_part(band.particles, band.families, band.global_id, band.family_complete,
                                       band.whole_count, slabs, rank, path, s.whole.band_index, reach);
  if (s.partition.owned.size() != s.whole.owned_family_start.size())
    throw Error(path + ": process " + std::to_string(rank) + " owns " + std::to_string(s.partition.owned.size()) +
                " particles of its band but " + std::to_string(s.whole.owned_family_start.size()) +
                " of the whole file");
  s.particles = std::move(band.particles);
  s.families = std::move(band.families);
  return s;
}

}  // namespace pd::solver
