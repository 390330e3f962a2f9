#include "checkpoint_layout.hpp"

#include <cstdint>
#include <utility>
#include <vector>

#include "compact_families.hpp"
#include "error.hpp"
#include "processes.hpp"
#include "run.hpp"
#include "surface_correction.hpp"

namespace pd::solver {

void take_bond_states_by_family(const RunContext& run, const std::string& checkpoint_path, Simulation::State& state,
                                const Communicator& communicator) {
  if (state.bond_states_by_family) return;
  std::vector<std::uint8_t> by_family;
  on_every_process([&] {
    if (!communicator.is_root()) return;
    try {
      // The set-up of the run that wrote it: the whole plate's, on one
      // process, with the same options (its kernels lay its bond states out).
      auto read = read_compact_particle_file(run.scene.particle_file);
      SetupOptions options = run.setup_options();
      // The surface correction's factors from the folder's cache, which the
      // run that wrote the checkpoint left there (else computed): read only,
      // their write kept back in `unwritten`, which is never written.
      DeferredCacheWrite unwritten;
      options.surface_correction_cache = run.path(surface_correction_cache_file);
      options.deferred_cache = &unwritten;
      options.keep_families = true;
      Simulation one_process(run.scene, std::move(read.particles), std::move(read.families), options);
      one_process.restore_state(state);
      one_process.bond_states_by_family(by_family);
    } catch (const Error& e) {
      throw Error(checkpoint_path + ": a one-process run's checkpoint, whose bond states could not be turned family "
                                    "by family for several processes (" + std::string(e.what()) +
                  "); restart it on one process (without mpirun)");
    }
  });
  communicator.broadcast_from_root(by_family);
  state.bond_states = std::move(by_family);
  state.bond_states_by_family = true;
}

}  // namespace pd::solver
