#pragma once
// Adaptive particle refinement during a dynamic run ([refinement] of the
// scene; theory.md Sec. 8; docs/refinement.md). Every check_interval steps
// the run asks `check`: particles whose damage exceeds phi_c or whose strain
// (the scene's `strain`: one of their intact bonds' stretch, or their
// accumulated normal strain) exceeds alpha times their critical stretch
// trigger a split of themselves and (`spread` = "family") of their family
// (the particles at most as fine as they are), within the region, the
// levels and the particle budget. The
// split and the families come from setup/refinement_split; the run then goes
// on with a new Simulation on the refined set, which takes the motion over
// (Simulation::continue_from).
//
// The list of events is what a checkpoint keeps: `replay` rebuilds the same
// refined set from the particle file, so that a restart goes on bit for bit.
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <vector>

#include "refinement_split.hpp"
#include "scene.hpp"
#include "simulation.hpp"

namespace pd::solver {

class AdaptiveRefinement {
public:
  // `particles`: the particle file's set with its cells and families.
  // `rebuild`: which families a split builds again (refinement_split.hpp;
  // the runs use the local rebuild, tests compare it with the whole one).
  AdaptiveRefinement(const Scene& scene, ParticleSet particles, std::ostream& log,
                     FamilyRebuild rebuild = FamilyRebuild::local);

  // With `on` (pd-solve --verbose) each event prints a second line: the
  // set-up's counts (families built, bond weights, row sums and general
  // rows computed of all) and the wall times of the event's parts.
  void show_details(bool on) { details_ = on; }

  // Warnings (a split that added energy) also go to `echo` when not null
  // (run_report.hpp, warning_echo).
  void echo_warnings_to(std::ostream* echo) { warning_echo_ = echo; }
  // The warnings this run's events printed (for summary.json).
  const std::vector<std::string>& warnings() const { return warnings_; }

  // Splits the set as the events of an earlier run did (a restart), without a simulation.
  void replay(const std::vector<SplitEvent>& events);

  // The simulation that continues `sim` on a refined set when particles meet
  // the criteria (and prints the event), else null. `sim`: the simulation on
  // the current set (the last this class set up, or the run's first); at an
  // event its evaluation scratch is freed (Simulation::release_evaluation_scratch).
  // `before_set_up`, when given, is called at an event just before the
  // refined set's simulation is set up (after the split and the carried
  // motion): the caller frees there what that simulation replaces (the run's
  // rollback copy of `sim`'s state), which would add to the event's peak memory.
  std::unique_ptr<Simulation> check(Simulation& sim, const std::function<void()>& before_set_up = {});

  // A simulation on the current set, at rest (the start of a restart).
  std::unique_ptr<Simulation> simulation();

  // The set-up options of the run's first simulation on the particle file's
  // set (not made by this class): with them it keeps its bond weights here
  // for the first event's set-up.
  SetupOptions first_setup(SetupOptions options);

  const ParticleSet& particles() const { return current_; }  // with cells and families
  const std::vector<SplitEvent>& events() const { return events_; }
  std::size_t initial_particle_count() const { return initial_count_; }
  // The particles of the particle file that may split: cells that can
  // (can_split_cell), inside the region when one is given.
  std::size_t splittable_at_start() const { return splittable_at_start_; }
  // The most particles the settings allow: each of those split `levels`
  // times, 4^levels particles in its place, the others as they are; at most
  // the budget when one is given (`with_budget`).
  std::uint64_t worst_case_particle_count(bool with_budget = true) const;
  double seconds() const { return seconds_; }
  // Families built again by the FamilyBuilder, summed over the events (the others kept theirs).
  std::size_t families_built() const { return families_built_; }
  // Listed bonds whose weights the set-ups of the refined sets computed, and
  // all their listed bonds (the others' weights were taken over), summed over the events.
  std::uint64_t bond_weights_computed() const { return bond_weights_computed_; }
  std::uint64_t bond_weights_listed() const { return bond_weights_listed_; }
  // The families and bond weights of the last simulation this class set up
  // (its families are that simulation's: read them while it lives).
  const KeptBondWeights& bond_weights() const { return weights_; }
  // The dual-horizon row stiffness sums of the last simulation this class set
  // up (empty when its force field did not form them: not bond-based dual horizons).
  const std::vector<double>& row_stiffness() const { return row_stiffness_.sums; }
  // Rows whose stiffness sums the set-ups of the refined sets computed, and
  // all their rows (the others' sums were taken over), summed over the events.
  std::uint64_t row_sums_computed() const { return row_sums_computed_; }
  std::uint64_t row_sums_listed() const { return row_sums_listed_; }
  // What the last simulation this class set up kept of the dual-horizon rows
  // of the general particles of its lattice split (empty without a lattice or
  // with a state-based model; the rows are its lattice_general_rows), and how
  // many rows of general particles the set-ups of the refined sets built, of
  // all (the others were copied; theory.md Sec. 8.7).
  const KeptGeneralRows& general_rows() const { return general_rows_; }
  std::uint64_t general_rows_built() const { return general_rows_built_; }
  std::uint64_t general_rows_listed() const { return general_rows_listed_; }
  // Directed bonds that broke at the first force evaluation after a split
  // (spurious damage made by the splits themselves), summed over the events.
  std::uint64_t bonds_broken_by_splits() const { return bonds_broken_by_splits_; }
  // The change of kinetic + strain energy those splits made [J], summed over
  // the events whose split broke bonds (a split that breaks none places its
  // children on the parent's linear field: it changes the energy by the
  // field's curvature only, and is not measured: the strain energy costs a sweep).
  double energy_added_by_splits() const { return energy_added_by_splits_; }

  // The particles that split if the run were refined now (sorted): the
  // criteria, the region, the levels and the budget applied to `sim`'s state.
  std::vector<std::uint32_t> candidates(const Simulation& sim);

private:
  // Per particle its strain over alpha's reference, s0 of its horizon (the
  // scene's `strain`: largest bond stretch or accumulated normal strain),
  // for the particles of reach_ (0 for the others).
  void strain_ratio(const Simulation& sim, std::vector<double>& ratio);
  // The levels of the split set; `count_before`: the particle count of the set before the split.
  void apply(const SplitResult& split, std::size_t count_before);
  // Refuses a region without a particle centre in it, and one that holds
  // every centre and is more than 10 times the plate's extent both ways (a
  // region in mm read as metres); names the key and the plate's extent.
  void require_particles_in_region() const;
  // Whether particle i of the current set may split (its level, the region).
  bool allowed(std::size_t i) const;
  // Whether member j of i's family splits with i when i meets the criteria
  // (at most as fine; with spread = a distance, at most that far).
  bool splits_with(std::size_t i, std::uint32_t j) const;
  void find_reach();  // reach_ of the current set
  // The set-up of a simulation on `particles` (the split set `split`, or the
  // current set when null): with the local rebuild it takes the bond weights
  // of the set before the split over where the split left the families
  // alone, and keeps its own for the next event. `before`: the simulation on
  // the set before the split, whose general particles' rows are copied (null:
  // all built); `count_before`: that set's particle count (the set itself
  // is gone by then: check).
  std::unique_ptr<Simulation> set_up(const ParticleSet& particles, const SplitResult* split,
                                     const Simulation* before = nullptr, std::size_t count_before = 0);
  // Prints where the first force evaluation of `next` broke bonds (its
  // broken pairs that `known`, sorted, does not hold): spurious damage of a
  // split. `p`: the split set (split.particles, moved out by then).
  void describe_broken_by_split(const Simulation& next, const ParticleSet& p, const SplitResult& split,
                                const std::vector<std::pair<std::uint32_t, std::uint32_t>>& known) const;

  Scene scene_;
  std::ostream& log_;
  std::ostream* warning_echo_ = nullptr;
  std::vector<std::string> warnings_;
  ParticleSet current_;
  FamilyRebuild rebuild_;
  std::vector<int> level_;  // halvings since the particle file, per particle
  // Per particle of the current set: 1 when it or a member of its family
  // that splits with it is allowed to split (only these need the criteria).
  // reach_unknown: not found yet (find_reach); reach_complete_: none is.
  std::vector<std::uint8_t> reach_;
  static constexpr std::uint8_t reach_unknown = 2;
  bool reach_complete_ = false;
  NormalStrains normal_strains_;  // strain_ratio's buffers (strain = "normal")
  std::vector<SplitEvent> events_;
  std::size_t initial_count_ = 0;
  std::size_t splittable_at_start_ = 0;
  double seconds_ = 0;
  std::size_t families_built_ = 0;
  std::uint64_t bonds_broken_by_splits_ = 0;
  double energy_added_by_splits_ = 0;  // [J]
  // The bond weights of the current set's simulation (theory.md Sec. 8.4), when one was set up.
  KeptBondWeights weights_;
  bool has_weights_ = false;
  // The distance moments and partial areas of cells between levels, the
  // same for the whole run (cell_disk_memo.hpp).
  CellDiskMemo moment_memo_, area_memo_;
  std::uint64_t bond_weights_computed_ = 0, bond_weights_listed_ = 0;
  // The row stiffness sums of the current set's simulation (theory.md Sec. 8.6), when it formed them.
  KeptRowStiffness row_stiffness_;
  std::uint64_t row_sums_computed_ = 0, row_sums_listed_ = 0;
  // Per particle of the current set: its cell reach (cell_reach, families.hpp),
  // for the refined set's longest possible bond; empty until an event's
  // set-up measured them. cell_reach_after_: the split set's, which set_up
  // measures for the children only and apply takes over.
  std::vector<double> cell_reach_, cell_reach_after_;
  // The general particles' rows of the current set's lattice split (theory.md Sec. 8.7).
  KeptGeneralRows general_rows_;
  std::uint64_t general_rows_built_ = 0, general_rows_listed_ = 0;
  bool told_free_cells_ = false, told_budget_ = false;
  bool details_ = false;  // show_details
};

}  // namespace pd::solver
