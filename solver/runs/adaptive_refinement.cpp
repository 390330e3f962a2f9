#include "adaptive_refinement.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <optional>
#include <ostream>
#include <sstream>
#include <tuple>

#include "error.hpp"
#include "families.hpp"
#include "run_report.hpp"
#include "units.hpp"

namespace pd::solver {
namespace {

// Set-up of a refined set: nothing cached (the cache belongs to the
// particle file); the squares that have their whole family at one horizon on
// the lattice sweep (theory.md Sec. 6.7), as in the run's first set.
SetupOptions refined_setup() { return {}; }

// Per particle of the split set `after`, its origin when its dual-horizon row is the
// origin's (theory.md Sec. 8.6), else Families::none. A row changes where
// the family was built again (the children, the particles bonded to a
// parent) or where it holds a dual entry of a child (a member of a child's
// family). A built family of a particle that did not split keeps its bonds
// to the particles that did not split, with the same partial volumes
// (Sec. 8.3): their rows keep its dual entries (rows_changed_by_event adds
// those whose bonds' weights change). The parent's members are bonded to
// it, so built again. The others keep their own bonds and, the split keeping
// the order of the particles that did not split, their dual entries in the
// same order.
std::vector<std::uint32_t> unchanged_rows(const ParticleSet& after, const SplitResult& split) {
  const std::size_t n = after.size();
  std::vector<std::uint8_t> changed(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!split.rebuilt[i]) continue;
    changed[i] = 1;
    if (split.is_child[i])
      for (auto k = after.family_offsets[i]; k < after.family_offsets[i + 1]; ++k) changed[after.neighbors[k]] = 1;
  }
  std::vector<std::uint32_t> same(n, Families::none);
  for (std::size_t i = 0; i < n; ++i)
    if (!changed[i] && !split.is_child[i]) same[i] = split.origin[i];
  return same;
}

}  // namespace

AdaptiveRefinement::AdaptiveRefinement(const Scene& scene, ParticleSet particles, std::ostream& log,
                                       FamilyRebuild rebuild)
    : scene_(scene), log_(log), current_(std::move(particles)), rebuild_(rebuild) {
  level_.assign(current_.size(), 0);
  initial_count_ = current_.size();
  if (scene_.refinement.has_region) require_particles_in_region();
  for (std::size_t i = 0; i < initial_count_; ++i) splittable_at_start_ += allowed(i) && can_split_cell(current_, i);
  // A budget the particle file already fills lets nothing split (each split adds 3).
  const long budget = scene_.refinement.particle_budget;
  if (budget > 0 && static_cast<std::size_t>(budget) < initial_count_ + 3)
    throw Error(scene_.source_of("refinement.particle_budget") + ": key 'refinement.particle_budget' = " +
                std::to_string(budget) + ": " + scene_.particle_file + " has " + std::to_string(initial_count_) +
                " particles already and a split adds 3: nothing could split; give a budget of at least " +
                std::to_string(initial_count_ + 3) + " (the total particle count allowed), or leave it out");
}

std::uint64_t AdaptiveRefinement::worst_case_particle_count(bool with_budget) const {
  const auto& spec = scene_.refinement;
  // (levels is at most 6: 4^6 = 4096 children of one particle.)
  const std::uint64_t worst = (initial_count_ - splittable_at_start_) +
                              (static_cast<std::uint64_t>(splittable_at_start_) << (2 * spec.levels));
  return with_budget && spec.particle_budget > 0 ? std::min<std::uint64_t>(worst, spec.particle_budget) : worst;
}

void AdaptiveRefinement::require_particles_in_region() const {
  // A region that holds no particle centre lets nothing split: the run would
  // go on coarse as if refinement had been asked for (a region in mm read as
  // metres lies far off the plate). One that holds every centre and is more
  // than `far` times the plate's extent both ways limits nothing: most
  // likely a region in mm read as metres that starts at the plate's corner
  // (before 7 December 2026 the whole plate refined without a word).
  constexpr double far = 10;
  const auto& r = scene_.refinement.region;
  double xmin = INFINITY, ymin = INFINITY, xmax = -INFINITY, ymax = -INFINITY;
  bool some = false, all = true;
  for (std::size_t i = 0; i < current_.size(); ++i) {
    const bool inside =
        current_.x[i] >= r[0] && current_.x[i] <= r[2] && current_.y[i] >= r[1] && current_.y[i] <= r[3];
    some = some || inside;
    all = all && inside;
    xmin = std::min(xmin, current_.x[i]), xmax = std::max(xmax, current_.x[i]);
    ymin = std::min(ymin, current_.y[i]), ymax = std::max(ymax, current_.y[i]);
  }
  const bool limits_nothing = all && xmax > xmin && ymax > ymin && r[2] - r[0] > far * (xmax - xmin) &&
                              r[3] - r[1] > far * (ymax - ymin);
  if (some && !limits_nothing) return;
  const auto number = format_number;
  // The region as written (shortest_text): a region thinner than 6 digits
  // show must not read as [0.001, 0.0008, 0.001, 0.0008].
  const auto region = [&](double divisor, const char* unit) {
    return "[" + shortest_text(r[0] / divisor) + ", " + shortest_text(r[1] / divisor) + ", " +
           shortest_text(r[2] / divisor) + ", " + shortest_text(r[3] / divisor) + "] " + unit;
  };
  const std::string span = "(its centres span x = " + number(xmin) + " to " + number(xmax) + " m, y = " +
                           number(ymin) + " to " + number(ymax) + " m)";
  const std::string key = scene_.source_of("refinement.region") + ": key 'refinement.region' = " + region(1, "m");
  if (!some)
    throw Error(key + " holds no particle centre of " + scene_.particle_file + " " + span + ": nothing could split");
  throw Error(key + " holds every particle centre of " + scene_.particle_file + " and is more than " + number(far) +
              " times its extent both ways " + span + ": it limits nothing; the region is in m (" + region(1, "mm") +
              " is " + region(1000, "m") + "); to refine everywhere, leave it out");
}

void AdaptiveRefinement::apply(const SplitResult& split, std::size_t count_before) {
  std::vector<int> level(split.origin.size());
  for (std::size_t i = 0; i < level.size(); ++i) level[i] = level_[split.origin[i]] + split.is_child[i];
  level_ = std::move(level);
  // The caller replaces the set: find_reach at the next check, for the
  // particles whose family the split built only. A particle that kept its
  // origin's family (with the new indices) has the same members, none of
  // which split, at the same places with the same levels: the same reach.
  std::vector<std::uint8_t> reach;
  if (reach_complete_ && reach_.size() == count_before) {
    reach.resize(split.origin.size());
    for (std::size_t i = 0; i < reach.size(); ++i)
      reach[i] = split.rebuilt[i] || split.is_child[i] ? reach_unknown : reach_[split.origin[i]];
  }
  reach_ = std::move(reach);
  reach_complete_ = false;
  // The cell reaches set_up measured for this split (none when it did not set one up: a replay).
  cell_reach_.clear();
  if (cell_reach_after_.size() == split.origin.size()) cell_reach_ = std::move(cell_reach_after_);
  cell_reach_after_.clear();
}

void AdaptiveRefinement::replay(const std::vector<SplitEvent>& events) {
  for (const auto& e : events) {
    SplitResult split = split_particles(current_, e.parents, rebuild_, &area_memo_);
    families_built_ += split.families_built;
    apply(split, current_.size());
    current_ = std::move(split.particles);
    events_.push_back(e);
  }
}

std::unique_ptr<Simulation> AdaptiveRefinement::set_up(const ParticleSet& particles, const SplitResult* split,
                                                       const Simulation* before, std::size_t count_before) {
  SetupOptions options = refined_setup();
  options.moment_memo = &moment_memo_;
  // Its stable limit falls with each halving: a fixed step below the file's
  // limit may lie above this set's.
  if (split)
    options.particle_set_name = "the refined set after a refinement event (" + std::to_string(particles.size()) +
                                " particles; each halving of dx lowers the limit: a fixed step must lie below the "
                                "finest level's, docs/refinement.md)";
  // Per particle: its particle before the event, or Families::none for a child.
  std::vector<std::uint32_t> origin;
  if (split)
    for (std::size_t i = 0; i < particles.size(); ++i)
      origin.push_back(split->is_child[i] ? Families::none : split->origin[i]);
  // A particle whose family the split copied (not a child, bonded to no
  // parent) has the same bonds to the same cells as its origin: its weights
  // can be taken over, and whether it is on its level's stencil. The whole
  // rebuild computes every weight (the reference).
  EarlierBondWeights earlier;
  PrecrackCuts cuts;
  if (split && has_weights_ && rebuild_ == FamilyRebuild::local) {
    earlier.families = &weights_.families();
    earlier.weights = &weights_.energy_weight;
    earlier.same_family.resize(particles.size());
    for (std::size_t i = 0; i < particles.size(); ++i)
      earlier.same_family[i] = split->rebuilt[i] ? Families::none : split->origin[i];
    earlier.origin = origin;
    options.earlier_weights = &earlier;
    // The pre-cracks' cut bonds: a copied family's taken over (theory.md
    // Sec. 8.8), their particles listed as the families are collected.
    const PrecrackCuts& before_cuts = weights_.precrack_cuts;
    if (before_cuts.particle_count == count_before) {
      earlier.listed_before = &before_cuts.particles;
      cuts = precrack_cuts_after_event(particles, scene_.precracks, scene_.path, before_cuts, earlier.same_family);
      earlier.listed = &cuts.particles;
      options.precrack_cuts = &cuts;
    }
  }
  // Likewise the row stiffness sums of the stable step, where the rows are
  // the same (without the surface correction, whose factors are the whole set's).
  EarlierRowStiffness earlier_rows;
  if (split && has_weights_ && rebuild_ == FamilyRebuild::local && !scene_.effects.surface_correction &&
      row_stiffness_.sums.size() == count_before) {
    earlier_rows.sums = &row_stiffness_.sums;
    earlier_rows.same_row = unchanged_rows(particles, *split);
    earlier_rows.families = &weights_.families();
    earlier_rows.origin = std::move(origin);
    // A particle that did not split keeps its cell about the same centre,
    // and with it its reach: only the children's are measured.
    cell_reach_after_.resize(particles.size());
    const bool reaches_known = cell_reach_.size() == count_before;
    for (std::size_t i = 0; i < particles.size(); ++i)
      cell_reach_after_[i] = reaches_known && !split->is_child[i] ? cell_reach_[split->origin[i]]
                                                                   : cell_reach(particles, i);
    earlier_rows.longest_bond = longest_possible_bond(particles, cell_reach_after_);
    // The general particles' rows of the lattice split, where the set before
    // the event had them (theory.md Sec. 8.7): in its simulation's table.
    const BondTable* before_rows = before ? before->lattice_general_rows() : nullptr;
    if (general_rows_.is_lattice.size() == count_before && before_rows &&
        before_rows->particle_count == count_before && before_rows->size() == general_rows_.intact.size()) {
      earlier_rows.general_table = before_rows;
      earlier_rows.general_rows = &general_rows_;
    }
    options.earlier_row_stiffness = &earlier_rows;
  }
  // A refined set takes the run's state over at once (check: continue_from
  // evaluates its forces); a restart's set starts at rest, as the run's first.
  options.start_at_rest = split == nullptr;
  KeptBondWeights kept;
  options.keep_weights = &kept;
  KeptRowStiffness rows;
  options.keep_row_stiffness = &rows;
  KeptGeneralRows general_rows;
  options.keep_general_rows = &general_rows;
  auto sim = std::make_unique<Simulation>(scene_, particles, options);
  if (split) {
    bond_weights_computed_ += kept.computed;
    bond_weights_listed_ += kept.families().neighbors.size();
    row_sums_listed_ += rows.sums.size();
    row_sums_computed_ += rows.computed;
    const auto general = static_cast<std::uint64_t>(
        std::count(general_rows.is_lattice.begin(), general_rows.is_lattice.end(), std::uint8_t{0}));
    general_rows_listed_ += general;
    general_rows_built_ += general - general_rows.copied;
  }
  weights_ = std::move(kept);
  row_stiffness_ = std::move(rows);
  general_rows_ = std::move(general_rows);
  has_weights_ = true;
  return sim;
}

std::unique_ptr<Simulation> AdaptiveRefinement::simulation() { return set_up(current_, nullptr); }

SetupOptions AdaptiveRefinement::first_setup(SetupOptions options) {
  options.keep_weights = &weights_;
  options.moment_memo = &moment_memo_;
  options.keep_row_stiffness = &row_stiffness_;
  options.keep_general_rows = &general_rows_;
  has_weights_ = true;
  return options;
}

bool AdaptiveRefinement::allowed(std::size_t i) const {
  const auto& spec = scene_.refinement;
  if (level_[i] >= spec.levels) return false;
  if (spec.has_region && !(current_.x[i] >= spec.region[0] && current_.x[i] <= spec.region[2] &&
                           current_.y[i] >= spec.region[1] && current_.y[i] <= spec.region[3]))
    return false;
  return true;
}

bool AdaptiveRefinement::splits_with(std::size_t i, std::uint32_t j) const {
  // Not finer than i: on a lattice the sizes differ by powers of two, and a
  // free cell's size differs from its neighbours' (1/sqrt(2): halfway, in
  // ratio, between one level and the next).
  if (!(current_.cell_size[j] >= current_.cell_size[i] * std::sqrt(0.5))) return false;
  const auto& spec = scene_.refinement;
  if (spec.spread != RefinementSpread::within) return true;
  const double dx = current_.x[j] - current_.x[i], dy = current_.y[j] - current_.y[i];
  const double reach = spec.spread_horizons * current_.horizon[i];
  return dx * dx + dy * dy <= reach * reach;
}

void AdaptiveRefinement::find_reach() {
  // A particle meeting the criteria can only choose itself and the members
  // of its family that split with it; when none of them is allowed (finest
  // level, outside the region) its criteria cannot change the choice, nor
  // the count of free cells, so they need not be evaluated. The levels and
  // the set change only at events.
  const std::size_t n = current_.size();
  if (reach_.size() != n) reach_.assign(n, reach_unknown);
  for (std::size_t i = 0; i < n; ++i) {
    if (reach_[i] != reach_unknown) continue;  // carried over from the set before the event (apply)
    bool reaches = allowed(i);
    const bool spreads = scene_.refinement.spread != RefinementSpread::none;
    for (auto k = current_.family_offsets[i]; spreads && !reaches && k < current_.family_offsets[i + 1]; ++k) {
      const auto j = current_.neighbors[k];
      reaches = splits_with(i, j) && allowed(j);
    }
    reach_[i] = reaches ? 1 : 0;
  }
  reach_complete_ = true;
}

void AdaptiveRefinement::strain_ratio(const Simulation& sim, std::vector<double>& ratio) {
  if (scene_.refinement.strain == RefinementStrain::bond) {
    sim.largest_stretch_ratio(ratio, reach_);
    return;
  }
  // The larger accumulated normal strain of the two axes over s0 (theory.md
  // Sec. 8.1): tension only, as a bond breaks in tension only.
  sim.normal_strains(normal_strains_, reach_);
  const auto& s = normal_strains_;
  ratio.assign(s.xx.size(), 0.0);
  for (std::size_t i = 0; i < ratio.size(); ++i)
    if (s.critical_stretch[i] > 0) ratio[i] = std::max(s.xx[i], s.yy[i]) / s.critical_stretch[i];
}

std::vector<std::uint32_t> AdaptiveRefinement::candidates(const Simulation& sim) {
  const auto& spec = scene_.refinement;
  const std::size_t n = current_.size();
  if (!reach_complete_ || reach_.size() != n) find_reach();
  std::vector<double> ratio;
  strain_ratio(sim, ratio);
  const auto& damage = sim.damage();
  // How strongly a particle meets the criteria at strain fraction `alpha`
  // (> 1: it does). Asked only of the particles that reach an allowed one
  // (find_reach): the others' ratios are 0.
  const auto score = [&](std::size_t i, double alpha) {
    return std::max(damage[i] / spec.damage_threshold, ratio[i] / alpha);
  };
  std::vector<std::uint8_t> chosen(n, 0);
  std::size_t free_cells = 0;
  const auto choose = [&](std::size_t j) {
    if (chosen[j] || !allowed(j)) return;
    if (!can_split_cell(current_, j)) {
      ++free_cells;
      return;
    }
    chosen[j] = 1;
  };
  // Chooses the particles meeting the criteria at `alpha`, and their families.
  const auto choose_at = [&](double alpha) {
    for (std::size_t i = 0; i < n; ++i) {
      if (!reach_[i] || !(score(i, alpha) > 1)) continue;
      choose(i);
      if (spec.spread == RefinementSpread::none) continue;
      // The family splits with it: the tip's whole horizon at one resolution.
      for (auto k = current_.family_offsets[i]; k < current_.family_offsets[i + 1]; ++k) {
        const auto j = current_.neighbors[k];
        if (splits_with(i, j)) choose(j);
      }
    }
  };
  choose_at(spec.strain_fraction);
  // When that makes an event, the fine zone's lead splits with it: the
  // particles meeting the criteria at lead_fraction (docs/refinement.md, "Fewer events").
  const double lead = spec.event_split_fraction();
  if (lead < spec.strain_fraction && std::find(chosen.begin(), chosen.end(), 1) != chosen.end()) {
    free_cells = 0;
    choose_at(lead);
  }
  if (free_cells > 0 && !told_free_cells_) {
    told_free_cells_ = true;
    log_ << "refinement: " << free_cells
         << " particles whose cells have neither three nor four corners met the criteria and stay as they are "
            "(docs/refinement.md)\n";
  }
  std::vector<std::uint32_t> parents;
  for (std::uint32_t i = 0; i < n; ++i)
    if (chosen[i]) parents.push_back(i);
  // Each split adds 3 particles; over budget, the strongest candidates go first.
  if (spec.particle_budget > 0) {
    const auto budget = static_cast<std::size_t>(spec.particle_budget);
    const std::size_t room = budget > n ? (budget - n) / 3 : 0;
    if (parents.size() > room) {
      if (!told_budget_) {
        told_budget_ = true;
        log_ << "refinement: particle budget " << budget << " reached at step " << sim.step_index() << " ("
             << n << " particles); further splits are limited to it\n";
      }
      std::stable_sort(parents.begin(), parents.end(),
                       [&](std::uint32_t a, std::uint32_t b) { return score(a, lead) > score(b, lead); });
      parents.resize(room);
      std::sort(parents.begin(), parents.end());
    }
  }
  return parents;
}

void AdaptiveRefinement::describe_broken_by_split(
    const Simulation& next, const ParticleSet& p, const SplitResult& split,
    const std::vector<std::pair<std::uint32_t, std::uint32_t>>& known) const {
  const auto broken = next.broken_pairs();
  std::vector<std::pair<std::uint32_t, std::uint32_t>> fresh;
  std::set_difference(broken.begin(), broken.end(), known.begin(), known.end(), std::back_inserter(fresh));
  const auto& k = next.kinematics();
  const auto kind = [&](std::uint32_t i) { return split.is_child[i] ? "child" : "particle"; };
  log_ << "refinement: the split broke the bonds of " << fresh.size() << " pairs:";
  constexpr std::size_t shown = 8;
  for (std::size_t n = 0; n < fresh.size() && n < shown; ++n) {
    const auto [i, j] = fresh[n];
    const double rest = std::hypot(p.x[j] - p.x[i], p.y[j] - p.y[i]);
    const double stretch =
        (std::hypot(p.x[j] - p.x[i] + k.ux[j] - k.ux[i], p.y[j] - p.y[i] + k.uy[j] - k.uy[i]) - rest) / rest;
    log_ << (n ? "; " : " ") << kind(i) << " at (" << format_mm(p.x[i]) << ", " << format_mm(p.y[i]) << ") - "
         << kind(j) << " at (" << format_mm(p.x[j]) << ", " << format_mm(p.y[j]) << "), stretch " << stretch
         << ", damage " << next.damage()[i] << " and " << next.damage()[j];
  }
  log_ << (fresh.size() > shown ? "; ...\n" : "\n");
}

std::unique_ptr<Simulation> AdaptiveRefinement::check(Simulation& sim, const std::function<void()>& before_set_up) {
  // The wall time of each part of an event, for its line in the log.
  auto lap_start = std::chrono::steady_clock::now();
  double total = 0;
  const auto lap = [&] {
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - lap_start).count();
    lap_start = now;
    total += seconds;
    return seconds;
  };
  std::vector<std::uint32_t> parents = candidates(sim);
  const double criteria_seconds = lap();
  if (parents.empty()) {
    seconds_ += total;
    return nullptr;
  }
  // `sim` takes no further step: its force evaluation's scratch goes before
  // the split and the refined set's set-up come on top of it (energies()
  // below, after a split that broke bonds, makes again what it needs).
  sim.release_evaluation_scratch();
  SplitResult split = split_particles(current_, parents, rebuild_, &area_memo_);
  families_built_ += split.families_built;
  const double split_seconds = lap();
  Simulation::Continuation c;
  c.step = sim.step_index();
  c.time = sim.time();
  c.external_work = sim.external_work();
  {
    const Kinematics& k = sim.kinematics();
    const auto broken_pairs = sim.broken_pairs();
    // A child that splits again places its children by its gradient over its
    // intact bonds, a particle of the file by its whole family's (theory.md Sec. 8.2).
    std::vector<std::uint8_t> by_intact_bonds(current_.size(), 0);
    bool any_child = false;
    for (auto parent : parents)
      if (level_[parent] >= 1) by_intact_bonds[parent] = 1, any_child = true;
    const std::optional<BrokenPartners> broken_before =
        any_child ? std::optional<BrokenPartners>(std::in_place, broken_pairs, current_.size()) : std::nullopt;
    std::tie(c.ux, c.uy) = displacements_after_split(current_, k.ux, k.uy, split,
                                                     broken_before ? &*broken_before : nullptr, &by_intact_bonds);
    c.vx = values_by_origin(k.vx, split.origin);
    c.vy = values_by_origin(k.vy, split.origin);
    c.arrival = values_by_origin(sim.arrival_times(), split.origin, scene_.output.damage_thresholds.size());
    c.broken_pairs = inherited_broken_pairs(split, broken_pairs);
    c.pieces = sim.setup_facts().pieces;
    c.pieces_without_cuts = sim.setup_facts().pieces_without_cuts;
  }
  const double carry_seconds = lap();
  // The set before the event (its cells and families) has served the split
  // and the carried motion: it goes before the refined set's simulation is
  // set up, at the event's peak memory, which it would add to. The set-up
  // and apply need its particle count only.
  const std::size_t count_before = current_.size();
  current_ = std::move(split.particles);
  const std::uint64_t computed_before = bond_weights_computed_, listed_before = bond_weights_listed_;
  const std::uint64_t rows_computed_before = row_sums_computed_, rows_listed_before = row_sums_listed_;
  const std::uint64_t general_built_before = general_rows_built_, general_listed_before = general_rows_listed_;
  // Here rather than before the split: freed there (freed memory is kept for
  // reuse), its blocks were carved up by the split's many small lists and
  // the set-up's tables no longer fitted in them: case 1 then peaked higher.
  if (before_set_up) before_set_up();
  auto next = set_up(current_, &split, &sim, count_before);
  const double setup_seconds = lap();
  // The bond states before the first forces (those the scene's pre-cracks
  // cut in the refined set): the message below, when the first forces break
  // bonds, names the pairs broken neither there nor by inheritance.
  std::vector<std::uint8_t> states_at_set_up;
  next->bond_states(states_at_set_up);
  const std::uint64_t broken_by_split = next->continue_from(std::move(c));  // (its motion; the clock and pairs stay for below)
  bonds_broken_by_splits_ += broken_by_split;
  // A split that breaks bonds placed children where no linear field fits
  // (across a crack that ran past them before they split): what it did to
  // the energy, from both sets at this step (the kinetic energy is the same:
  // velocities and masses carried over).
  double energy_added = 0;    // [J]
  double energy_scale = 0;    // [J] the larger of the external work so far and the plate's energy
  if (broken_by_split > 0) {
    auto known = next->broken_pairs_in(states_at_set_up);
    known.insert(known.end(), c.broken_pairs.begin(), c.broken_pairs.end());
    std::sort(known.begin(), known.end());
    describe_broken_by_split(*next, current_, split, known);
    const EnergyTotals before = sim.energies(), after = next->energies();
    energy_added = (after.kinetic + after.strain) - (before.kinetic + before.strain);
    energy_added_by_splits_ += energy_added;
    energy_scale = std::max(std::fabs(c.external_work), before.kinetic + before.strain);
  }
  apply(split, count_before);
  events_.push_back({c.step, c.time, std::move(parents)});
  const double state_seconds = lap();
  seconds_ += total;
  // One short line per event; with --verbose a second with the set-up's
  // counts and the parts' wall times.
  const auto precision = log_.precision(4);
  log_ << "refinement: step " << c.step << " (" << c.time * 1e6 << " us), +" << 3 * events_.back().parents.size()
       << " particles, total " << current_.size() << " (" << total << " s; time step " << next->time_step()
       << " s)";
  if (broken_by_split > 0)
    log_ << "; " << broken_by_split << " bonds broken by the split, energy " << std::showpos << energy_added
         << std::noshowpos << " J";
  log_ << "\n";
  // Energy the split made, beyond 1 % of the work done on the plate: the
  // run's energy balance no longer holds (docs/refinement.md, "Splits that come too late").
  if (energy_added > 0.01 * energy_scale) {
    std::ostringstream warning;
    warning.precision(4);
    warning << "refinement: the split at step " << c.step << " added " << energy_added << " J (the external "
            << "work so far " << c.external_work << " J): particles split after the crack had run past them, "
               "their children placed across it; check more often (refinement.check_interval = "
            << scene_.refinement.check_interval << " steps) or split earlier (a lower refinement.strain_fraction)";
    log_ << "warning: " << warning.str() << "\n";
    warnings_.push_back(warning.str());
    if (warning_echo_) *warning_echo_ << "pd-solve: warning: " << warning.str() << std::endl;
  }
  log_.precision(precision);
  if (details_)
    log_ << "refinement details: " << split.families_built << " families built, "
         << bond_weights_computed_ - computed_before << " of " << bond_weights_listed_ - listed_before
         << " listed bond weights computed, " << row_sums_computed_ - rows_computed_before << " of "
         << row_sums_listed_ - rows_listed_before << " row stiffness sums computed, "
         << general_rows_built_ - general_built_before << " of " << general_rows_listed_ - general_listed_before
         << " general particles' rows built (" << total << " s: " << criteria_seconds << " s criteria, "
         << split_seconds << " s split and families, " << carry_seconds << " s motion and broken pairs, "
         << setup_seconds << " s set-up, " << state_seconds << " s first forces; " << broken_by_split
         << " bonds broken by the split)\n";
  // Now, not when the buffer fills: a log followed while the run goes on
  // (stdout to a file) shows each event as it happens.
  log_ << std::flush;
  return next;
}

}  // namespace pd::solver
