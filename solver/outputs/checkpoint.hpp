#pragma once
// Checkpoints: the complete evolving state of a run in one binary file,
// written atomically, with a checksum over the payload. The key (scene text
// after overrides, without what a restart may change, + particle-file hash)
// makes --restart refuse a checkpoint from a different scene or particle file.
//
// Layout (little-endian): magic "PDCHK003" (dynamic; 001 held positions
// instead of displacements, 002 not the energy checks' state) or "PDQSC002"
// (quasi-static), u64 key length, key bytes, then
// the payload (step, time, external work, the energy checks' state, arrays,
// energy.csv rows, each array as u64 count + raw values; after a refinement
// also its events: steps, times, parent counts, parents), then u64 checksum
// of the payload
// (pd::Checksum). A run without refinement writes no event section, so its
// files are those of earlier versions.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "load_steps.hpp"
#include "refinement_split.hpp"
#include "simulation.hpp"

namespace pd::solver {

// A checkpoint's key: the scene's restart text, then a line "particles
// HASH", then, for a run on several processes (their bond states saved
// family by family, not as the lattice sweep's pair bits), a line that says
// so. A restart compares keys without that line and reads the layout from
// it (Simulation::State::bond_states_by_family): any process count restarts
// any other's checkpoint.
std::string checkpoint_key(const std::string& scene_key_text, const std::string& particle_hash, int processes);

// The run's identifier (docs/formats.md, "Run identifier"): 16 hex digits,
// a hash of the key a restart must match (the scene without what a restart
// may change, numbers as their doubles, and the particle file's hash; not the
// process count, which changes no result). Derived, not drawn at random: a
// restart, whose key equals its checkpoint's, keeps it without the checkpoint
// holding it, and a run made again from the same inputs writes the same files
// byte for byte; another material, load or particle file of the same size
// is another key, so another identifier.
std::string run_identifier(const std::string& scene_key_text, const std::string& particle_hash);

// What a dynamic run's energy checks carry from its start (dynamic_run.cpp):
// a restart goes on with them, as the run that never stopped.
struct EnergyCheckState {
  double energy_beyond_work = 0;  // the start's energy beyond the work counted then [J]
  double largest_supplied = 0;    // the largest energy supplied at an energy row so far [J]
  std::uint64_t broken_at_start = 0;  // directed bonds broken before the first step (pre-cracks)
  std::string gain_warning;       // the energy-gain warning, once given (empty before)
};

// A dynamic checkpoint's records besides the state: energy.csv's rows so
// far and the energy checks' state.
struct EnergyRecords {
  std::vector<std::string> rows;
  EnergyCheckState check;
};

struct Checkpoint {
  Simulation::State state;
  EnergyRecords energy;
  std::vector<SplitEvent> refinements;  // adaptive refinement's events so far (empty without)
};

// Streams the state from where it is (Simulation::state_view: no copy of
// the state on one process), atomically.
void write_checkpoint(const std::string& path, const std::string& key, const Simulation::StateView& state,
                      const EnergyRecords& energy, const std::vector<SplitEvent>& refinements);
inline void write_checkpoint(const std::string& path, const std::string& key, const Checkpoint& checkpoint) {
  write_checkpoint(path, key, Simulation::view_of(checkpoint.state), checkpoint.energy, checkpoint.refinements);
}

// pd::Error naming the file when it is missing, cut short (its size and the
// size the counts of its arrays need), corrupt or made for another key (keys
// compared with every number as its double: docs/solver.md, "Safety").
// The file is streamed (checked, then read), never held whole.
Checkpoint read_checkpoint(const std::string& path, const std::string& key);
// The same checks without reading the state (a restart's early check);
// returns whether its bond states are family by family (written on several
// processes).
bool check_checkpoint(const std::string& path, const std::string& key);
// A checkpoint without refinement events read into `state`, whose arrays
// have the run's sizes (Simulation::restore_state_in_place: they are the
// simulation's own); a file of other sizes, or with its bond states family
// by family, is refused. Returns the energy rows and checks' state.
EnergyRecords read_checkpoint_in_place(const std::string& path, const std::string& key, Simulation::State& state);

// A quasi-static run after a load step (magic "PDQSC002", same layout): the
// load-step state, the energy table's bond states, the rows of load_steps.csv
// and the snapshots written so far (load factor, file name).
struct QuasiStaticCheckpoint {
  LoadStepState state;
  std::vector<std::uint8_t> bond_states;
  std::vector<std::string> load_step_rows;
  std::vector<std::pair<double, std::string>> snapshots;
};

void write_checkpoint(const std::string& path, const std::string& key, const QuasiStaticCheckpoint& checkpoint);
QuasiStaticCheckpoint read_quasi_static_checkpoint(const std::string& path, const std::string& key);

}  // namespace pd::solver
