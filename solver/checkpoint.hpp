#pragma once
// Checkpoints: the complete evolving state of a run in one binary file,
// written atomically, with a checksum over the payload. The key (scene text
// after overrides + particle-file hash) makes --restart refuse a checkpoint
// from a different scene or particle file.
//
// Layout (little-endian): magic "PDCHK001", u64 key length, key bytes, then
// the payload (step, time, external work, arrays, energy.csv rows, each array
// as u64 count + raw values), then u64 checksum of the payload (pd::Checksum).
#include <string>
#include <vector>

#include "simulation.hpp"

namespace pd::solver {

struct Checkpoint {
  Simulation::State state;
  std::vector<std::string> energy_rows;
};

void write_checkpoint(const std::string& path, const std::string& key, const Checkpoint& checkpoint);

// pd::Error naming the file when it is missing, corrupt or made for another key.
Checkpoint read_checkpoint(const std::string& path, const std::string& key);

}  // namespace pd::solver
