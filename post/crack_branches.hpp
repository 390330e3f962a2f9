#pragma once
// The crack as a set of branches. A particle belongs to the crack from the
// time its damage reaches the chosen threshold (its arrival time). The cracked
// particles are linked to their near neighbours, labelled in arrival order
// and split into branches where the growth front of one branch becomes two
// fronts that move apart (docs/post.md, "Branches").
#include <cstdint>
#include <string>
#include <vector>

#include "arrival_data.hpp"
#include "pores.hpp"

namespace pd::post {

struct CrackBranch {
  int id = 0;
  int parent = -1;                        // -1: a crack of its own (pre-crack or nucleated)
  std::vector<std::uint32_t> particles;   // indices into ArrivalData, by arrival time
  double origin_x = 0, origin_y = 0;      // branching point, or where the crack started [m]
  double start_time = 0;                  // [s]
  double end_time = 0;                    // [s] last arrival, or the time it branched
  double first_arrival = -1;              // [s] its first particle's arrival (-1: none, or made by hand)
  bool ended_by_branching = false;
  std::vector<int> children;
  std::vector<double> pore_restart_times; // [s] times it re-initiated beyond a pore
  // Damage groups that appeared ahead of this crack, across a gap wider than
  // the gap bridge, and joined it (docs/post.md, "Branches", step 3).
  int joined_groups = 0;
};

struct BranchingEvent {
  double time = 0;        // [s]
  double x = 0, y = 0;    // branching point [m]
  int parent = 0;
  std::vector<int> children;
  // Largest angle between two children, each a straight line fitted to its
  // particles within `angle_length` of the branching point (the angle papers
  // quote; the same physical length at any resolution) [deg].
  double angle_deg = 0;
  double angle_length = 0;          // [m] the stated fit length
  std::vector<double> fit_lengths;  // [m] per child: the length fitted (shorter if the child is)
  // The same angle near the branching point: lines fitted between two and
  // eight horizons from where the children meet (depends on the resolution) [deg].
  double near_angle_deg = 0;
};

// A crack of its own that never grew beyond a few particles at the
// threshold (fewer than BranchSettings::min_front_particles) and never
// branched: a damage spot (e.g. a plate's corner under a traction), listed
// apart from the branches so that it does not count as a crack.
struct DamageSpot {
  double x = 0, y = 0;      // its first particle [m]
  double time = 0;          // its first particle's arrival [s]
  std::size_t particles = 0;
};

struct CrackNetwork {
  std::vector<CrackBranch> branches;
  std::vector<BranchingEvent> branchings;
  std::vector<DamageSpot> spots;
};

struct BranchSettings {
  // Two cracked particles are linked when closer than link_factor times the
  // larger of their cell sizes: 1.5 links the 8 lattice neighbours (diagonal
  // = 1.414) but not the next ring (2.0), so two cracks one horizon apart
  // stay apart (the horizon would merge them).
  double link_factor = 1.5;
  // Particles cracked within this time before "now" form a branch's front [s].
  double front_window = 0;
  // A front needs at least this many particles (one stray particle is noise).
  int min_front_particles = 3;
  // Two fronts are distinct cracks when at least this far apart [m]
  // (a horizon: PD cannot resolve two cracks closer than that).
  double min_front_separation = 0;
  // A cracked group separated from every branch by less than this [m]
  // continues the branch (damage bands may have one-particle gaps).
  double gap_bridge = 0;
  // A crack of its own that links to another branch before it has grown
  // this far [m] is a damage group of that crack seen ahead of its tip (a
  // kinking crack's damage often appears a little more than a horizon ahead
  // of the old tip): it joins that branch.
  double join_length = 0;
  // Distance from a pore's edge within which a tip is "at the pore" [m].
  double pore_ring = 0;
  // Branching angle: each child's line is fitted to its particles within
  // this distance of the branching point [m] (a stated physical length).
  double angle_length = 0;
  // Near angle and branching point: lines fitted between two separations
  // and this distance from where the children meet [m].
  double near_angle_length = 0;
};

// Default length over which branching angles are fitted [m].
inline constexpr double default_angle_length = 2e-3;

// Settings from the data: front window = speed window, separation and gap
// bridge = horizon, join length = 2 horizons, pore ring = 1.5 spacing,
// angle length = `angle_length`, near angle length = 8 horizons.
BranchSettings default_branch_settings(const ArrivalData& data, double window_seconds,
                                       double angle_length = default_angle_length);

// Keeps the times of a network in the order its branches grew (docs/post.md,
// "Branches", step 6): each branching is at or before the end and the first
// arrival of each of its children and at or after its parent's start; the parent ends and the
// children start at it; a branch that did not branch ends at its last
// arrival, not before its start. Branch ids are indices into `branches`.
void order_branching_times(CrackNetwork& network);

// Automatic branches (docs/post.md). Throws pd::Error when nothing cracked.
CrackNetwork find_branches(const ArrivalData& data, const std::vector<Pore>& pores,
                           const BranchSettings& settings);

// Manual branches as in [Peng, Chen, Bobaru 2023, App. 2]: the cracked
// particles inside each box [x_min, x_max] x [y_min, y_max] (metres).
struct BranchBox {
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;
  int line = 0;  // of the box file, for messages
};
std::vector<BranchBox> read_boxes_csv(const std::string& path);
// Throws pd::Error naming `path` (the box file), the line, the box in mm and
// the plate's extent for a box without a cracked particle; adds to
// `warnings` one line for each two boxes that hold the same cracked
// particles (one crack, its speeds counted twice).
CrackNetwork branches_from_boxes(const ArrivalData& data, const std::vector<BranchBox>& boxes,
                                 const std::string& path, std::vector<std::string>& warnings);

}  // namespace pd::post
