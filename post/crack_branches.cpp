#include "crack_branches.hpp"
#include "number_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <numeric>
#include <set>
#include <sstream>

#include "error.hpp"
#include "neighbor_search.hpp"
#include "results_format.hpp"

namespace pd::post {
namespace {

double distance(double ax, double ay, double bx, double by) { return std::hypot(ax - bx, ay - by); }

// The cracked particles, in arrival order, with their links.
struct CrackedSet {
  std::vector<std::uint32_t> id;     // local index -> particle index
  std::vector<double> t, x, y, cell; // arrival [s], position [m], cell size [m]
  std::vector<std::size_t> link_begin;
  std::vector<std::uint32_t> links;  // local indices

  std::size_t size() const { return id.size(); }
};

CrackedSet collect_cracked(const ArrivalData& d, double link_factor) {
  CrackedSet c;
  for (std::uint32_t i = 0; i < d.size(); ++i)
    if (d.arrival[i] >= 0) c.id.push_back(i);
  if (c.id.empty())
    throw file_error(d.path, "empty crack: no particle ever reached the damage threshold (array '" +
                                 results::arrival_array_name(d.threshold) + "' is -1 everywhere)");
  std::stable_sort(c.id.begin(), c.id.end(), [&](std::uint32_t a, std::uint32_t b) {
    return d.arrival[a] < d.arrival[b];
  });
  double max_cell = 0;
  for (auto i : c.id) {
    c.t.push_back(d.arrival[i]);
    c.x.push_back(d.x[i]);
    c.y.push_back(d.y[i]);
    c.cell.push_back(d.cell_size[i]);
    max_cell = std::max(max_cell, d.cell_size[i]);
  }
  NeighborSearch search(c.x, c.y);
  std::vector<std::uint32_t> near;
  c.link_begin.push_back(0);
  for (std::size_t k = 0; k < c.size(); ++k) {
    search.within(c.x[k], c.y[k], link_factor * max_cell, near);
    for (auto m : near) {
      if (m == k) continue;
      const double r = link_factor * std::max(c.cell[k], c.cell[m]);
      if (distance(c.x[k], c.y[k], c.x[m], c.y[m]) <= r) c.links.push_back(m);
    }
    c.link_begin.push_back(c.links.size());
  }
  return c;
}

// Principal direction of a point cloud (unit vector) and its centroid.
void principal_line(const CrackedSet& c, const std::vector<std::uint32_t>& members, double& cx,
                    double& cy, double& dx, double& dy) {
  cx = cy = 0;
  for (auto k : members) cx += c.x[k], cy += c.y[k];
  cx /= members.size();
  cy /= members.size();
  double sxx = 0, sxy = 0, syy = 0;
  for (auto k : members) {
    const double ux = c.x[k] - cx, uy = c.y[k] - cy;
    sxx += ux * ux, sxy += ux * uy, syy += uy * uy;
  }
  const double angle = 0.5 * std::atan2(2 * sxy, sxx - syy);
  dx = std::cos(angle);
  dy = std::sin(angle);
}

class BranchFinder {
public:
  BranchFinder(const ArrivalData& d, const std::vector<Pore>& pores, const BranchSettings& s)
      : s_(s), pores_(pores), c_(collect_cracked(d, s.link_factor)), search_(c_.x, c_.y) {
    label_.assign(c_.size(), -1);
    mark_.assign(c_.size(), 0);
    // The particles' cells' bounding box: a branching point is never outside it.
    for (std::size_t i = 0; i < d.size(); ++i) {
      const double half = 0.5 * d.cell_size[i];
      x_min_ = std::min(x_min_, d.x[i] - half), x_max_ = std::max(x_max_, d.x[i] + half);
      y_min_ = std::min(y_min_, d.y[i] - half), y_max_ = std::max(y_max_, d.y[i] + half);
    }
  }

  CrackNetwork run();

private:
  struct Work {
    CrackBranch branch;                  // particles hold local indices while working
    bool origin_fixed = false;
    double initial_time = 0;
    std::vector<std::pair<double, double>> reach;  // (time, farthest distance from origin)
    double front_start = 0;              // fronts only count particles from here on
    bool ended = false;
    int joined_into = -1;                // >= 0: this group joined that branch
  };

  struct Line {
    double cx = 0, cy = 0, ux = 1, uy = 0;  // a point of it and its direction
  };

  void add(std::uint32_t k, int b);
  void fix_origin(Work& w, std::uint32_t first_growth);
  bool is_young_crack(int b) const;
  void join_groups(std::size_t begin, std::size_t end, std::set<int>& touched);
  void join(int group, int host);
  Line child_line(int child, double x, double y, double r_min, double r_max) const;
  void collect_lineage(int b, std::vector<std::uint32_t>& particles) const;
  std::vector<Line> lines_over_length(const BranchingEvent& e, const std::vector<Line>& near,
                                      std::vector<double>& fitted) const;
  void rebuild_reach(Work& w);
  double reach_at(const Work& w, double t) const;
  int latest_linked_label(std::uint32_t k) const;
  int attach_across_gap(const std::vector<std::uint32_t>& group, double t) const;
  int attach_at_pore(const std::vector<std::uint32_t>& group, double t);
  int new_root(const std::vector<std::uint32_t>& group, double t);
  void check_split(int b, double t);
  void split(int b, const std::vector<std::vector<std::uint32_t>>& fronts, double t);
  void refine_branching(BranchingEvent& e, bool joined) const;
  CrackNetwork finish();

  BranchSettings s_;
  const std::vector<Pore>& pores_;
  CrackedSet c_;
  NeighborSearch search_;
  std::vector<int> label_;
  std::vector<unsigned> mark_;
  unsigned stamp_ = 0;
  std::vector<Work> work_;
  std::vector<BranchingEvent> events_;
  std::vector<bool> joined_;  // per event: the children meet inside the parent
  double x_min_ = std::numeric_limits<double>::max(), x_max_ = std::numeric_limits<double>::lowest();
  double y_min_ = std::numeric_limits<double>::max(), y_max_ = std::numeric_limits<double>::lowest();
};

// A crack that starts as a set of simultaneous particles (a pre-crack)
// grows from one end: its origin is the initial particle farthest from the
// first growth.
void BranchFinder::fix_origin(Work& w, std::uint32_t first_growth) {
  double best = -1;
  for (auto m : w.branch.particles)
    if (c_.t[m] == w.initial_time) {
      const double r = distance(c_.x[m], c_.y[m], c_.x[first_growth], c_.y[first_growth]);
      if (r > best) best = r, w.branch.origin_x = c_.x[m], w.branch.origin_y = c_.y[m];
    }
  w.origin_fixed = true;
  rebuild_reach(w);
}

void BranchFinder::add(std::uint32_t k, int b) {
  label_[k] = b;
  Work& w = work_[b];
  w.branch.particles.push_back(k);
  if (!w.origin_fixed && c_.t[k] > w.initial_time) {
    fix_origin(w, k);
    return;
  }
  const double r = distance(c_.x[k], c_.y[k], w.branch.origin_x, w.branch.origin_y);
  if (w.reach.empty() || r > w.reach.back().second) w.reach.emplace_back(c_.t[k], r);
}

void BranchFinder::rebuild_reach(Work& w) {
  w.reach.clear();
  auto order = w.branch.particles;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return c_.t[a] < c_.t[b]; });
  for (auto m : order) {
    const double r = distance(c_.x[m], c_.y[m], w.branch.origin_x, w.branch.origin_y);
    if (w.reach.empty() || r > w.reach.back().second) w.reach.emplace_back(c_.t[m], r);
  }
}

double BranchFinder::reach_at(const Work& w, double t) const {
  double r = 0;
  for (const auto& [time, reach] : w.reach) {
    if (time > t) break;
    r = reach;
  }
  return r;
}

// The branch of the most recently cracked linked neighbour: new damage
// continues the front it touches, not the older crack faces beside it.
int BranchFinder::latest_linked_label(std::uint32_t k) const {
  int best = -1;
  double best_t = -1, best_r = 0;
  for (auto e = c_.link_begin[k]; e < c_.link_begin[k + 1]; ++e) {
    const auto m = c_.links[e];
    if (label_[m] < 0) continue;
    const double r = distance(c_.x[k], c_.y[k], c_.x[m], c_.y[m]);
    if (c_.t[m] > best_t || (c_.t[m] == best_t && r < best_r)) best = label_[m], best_t = c_.t[m], best_r = r;
  }
  return best;
}

int BranchFinder::attach_across_gap(const std::vector<std::uint32_t>& group, double t) const {
  int best = -1;
  double best_t = -1, best_r = 0;
  std::vector<std::uint32_t> near;
  for (auto k : group) {
    search_.within(c_.x[k], c_.y[k], s_.gap_bridge, near);
    for (auto m : near) {
      if (label_[m] < 0 || c_.t[m] > t) continue;
      const double r = distance(c_.x[k], c_.y[k], c_.x[m], c_.y[m]);
      if (c_.t[m] > best_t || (c_.t[m] == best_t && r < best_r)) best = label_[m], best_t = c_.t[m], best_r = r;
    }
  }
  return best;
}

// A crack re-initiating on the far side of a pore continues the branch that
// ran into that pore most recently. A crack that the pore's stress
// concentration nucleated at its edge (with the children it split into)
// grows away from it and ran into nothing: a crack appearing elsewhere on
// the pore's edge is not its continuation. Such a crack is first seen where
// its damage first reaches the threshold, up to about two rings from the
// edge: a crack of its own born within two rings was born at the pore, as
// for the visits (pores.hpp). Children born at the pore of a crack that
// came from elsewhere (a restart that forked) continue that crack.
int BranchFinder::attach_at_pore(const std::vector<std::uint32_t>& group, double t) {
  for (const auto& pore : pores_) {
    bool near_pore = false;
    for (auto k : group)
      near_pore |= pore.within(c_.x[k], c_.y[k], s_.gap_bridge);
    if (!near_pore) continue;
    const auto ran_into_pore = [&](int b) {
      while (work_[static_cast<std::size_t>(b)].branch.parent >= 0) b = work_[static_cast<std::size_t>(b)].branch.parent;
      const CrackBranch& crack = work_[static_cast<std::size_t>(b)].branch;  // the crack of its own it grew from
      return !pore.within(crack.origin_x, crack.origin_y, 2 * s_.pore_ring);
    };
    int best = -1;
    double best_t = -1;
    std::vector<std::uint32_t> near;
    search_.within(pore.x, pore.y, pore.enclosing_radius() + s_.pore_ring, near);
    for (auto m : near)
      if (label_[m] >= 0 && c_.t[m] < t && c_.t[m] > best_t &&
          (!pore.has_outline() || pore.within(c_.x[m], c_.y[m], s_.pore_ring)) && ran_into_pore(label_[m]))
        best = label_[m], best_t = c_.t[m];
    if (best < 0) continue;
    work_[best].branch.pore_restart_times.push_back(t);
    work_[best].front_start = t;  // the old front stopped at the pore's near side
    return best;
  }
  return -1;
}

int BranchFinder::new_root(const std::vector<std::uint32_t>& group, double t) {
  Work w;
  w.branch.id = static_cast<int>(work_.size());
  w.branch.start_time = t;
  w.initial_time = t;
  w.front_start = t;
  double cx = 0, cy = 0;
  for (auto k : group) cx += c_.x[k], cy += c_.y[k];
  w.branch.origin_x = cx / group.size();  // provisional, see add()
  w.branch.origin_y = cy / group.size();
  w.origin_fixed = group.size() == 1;
  work_.push_back(std::move(w));
  return static_cast<int>(work_.size()) - 1;
}

// A crack of its own that appeared after t = 0 (not a pre-crack), has not
// branched and is still shorter than the join length.
bool BranchFinder::is_young_crack(int b) const {
  const Work& w = work_[b];
  const double grown = w.reach.empty() ? 0.0 : w.reach.back().second;
  return w.branch.parent < 0 && w.initial_time > 0 && !w.ended && w.branch.children.empty() &&
         grown < s_.join_length;
}

// One crack is one branch. A new particle that links two branches, one of
// which is a young crack of its own (is_young_crack), shows that the young
// crack was a damage group of the other one seen ahead of its tip: it joins
// the branch of the most recently cracked linked particle that is not a
// young crack (or, if all are, the oldest of them). Two cracks that each
// grew longer than the join length before they met stay two branches.
void BranchFinder::join_groups(std::size_t begin, std::size_t end, std::set<int>& touched) {
  for (std::size_t k = begin; k < end; ++k) {
    std::vector<int> young;
    int host = -1;
    double host_t = -1;
    for (auto e = c_.link_begin[k]; e < c_.link_begin[k + 1]; ++e) {
      const int b = label_[c_.links[e]];
      if (b < 0) continue;
      if (is_young_crack(b)) {
        if (std::find(young.begin(), young.end(), b) == young.end()) young.push_back(b);
      } else if (c_.t[c_.links[e]] > host_t && !work_[b].ended) {
        host = b, host_t = c_.t[c_.links[e]];
      }
    }
    if (young.empty() || (host < 0 && young.size() < 2)) continue;
    if (host < 0) {
      host = *std::min_element(young.begin(), young.end(), [&](int a, int b) {
        return work_[a].initial_time < work_[b].initial_time ||
               (work_[a].initial_time == work_[b].initial_time && a < b);
      });
    }
    for (int b : young)
      if (b != host) join(b, host);
    touched.insert(host);
  }
}

void BranchFinder::join(int group, int host) {
  Work& g = work_[group];
  Work& h = work_[host];
  for (auto m : g.branch.particles) label_[m] = host;
  const std::uint32_t first = g.branch.particles.front();
  h.branch.particles.insert(h.branch.particles.end(), g.branch.particles.begin(), g.branch.particles.end());
  // Local indices are in arrival order.
  std::sort(h.branch.particles.begin(), h.branch.particles.end());
  h.branch.pore_restart_times.insert(h.branch.pore_restart_times.end(), g.branch.pore_restart_times.begin(),
                                     g.branch.pore_restart_times.end());
  h.branch.joined_groups += 1 + g.branch.joined_groups;
  if (!h.origin_fixed) fix_origin(h, first);
  else rebuild_reach(h);
  g.branch.particles.clear();
  g.ended = true;
  g.joined_into = host;
}

void BranchFinder::check_split(int b, double t) {
  Work& w = work_[b];
  if (w.ended) return;
  // The front: this branch's particles cracked during the last front window.
  std::vector<std::uint32_t> front;
  for (auto it = w.branch.particles.rbegin(); it != w.branch.particles.rend(); ++it) {
    if (c_.t[*it] <= t - s_.front_window) break;
    if (c_.t[*it] >= w.front_start) front.push_back(*it);
  }
  if (front.size() < 2u * s_.min_front_particles) return;
  ++stamp_;
  for (auto k : front) mark_[k] = stamp_;

  // Connected pieces of the front that keep growing and are as advanced as
  // the branch was one window ago: each is a crack tip region.
  const double behind = reach_at(w, t - s_.front_window) - s_.gap_bridge;
  std::vector<std::vector<std::uint32_t>> pieces;
  for (auto seed : front) {
    if (mark_[seed] != stamp_) continue;
    std::vector<std::uint32_t> piece{seed};
    mark_[seed] = 0;
    for (std::size_t q = 0; q < piece.size(); ++q)
      for (auto e = c_.link_begin[piece[q]]; e < c_.link_begin[piece[q] + 1]; ++e)
        if (mark_[c_.links[e]] == stamp_) mark_[c_.links[e]] = 0, piece.push_back(c_.links[e]);
    double latest = -1, reach = 0;
    for (auto k : piece) {
      latest = std::max(latest, c_.t[k]);
      reach = std::max(reach, distance(c_.x[k], c_.y[k], w.branch.origin_x, w.branch.origin_y));
    }
    if (static_cast<int>(piece.size()) >= s_.min_front_particles &&
        latest >= t - 0.5 * s_.front_window && reach >= behind)
      pieces.push_back(std::move(piece));
  }
  if (pieces.size() < 2) return;

  // Pieces closer than the separation are one front (a ragged band).
  std::vector<int> group(pieces.size());
  std::iota(group.begin(), group.end(), 0);
  auto root = [&](int i) { while (group[i] != i) i = group[i]; return i; };
  for (std::size_t i = 0; i < pieces.size(); ++i)
    for (std::size_t j = i + 1; j < pieces.size(); ++j) {
      double gap = std::numeric_limits<double>::max();
      for (auto a : pieces[i])
        for (auto bb : pieces[j]) gap = std::min(gap, distance(c_.x[a], c_.y[a], c_.x[bb], c_.y[bb]));
      if (gap < s_.min_front_separation) group[root(static_cast<int>(j))] = root(static_cast<int>(i));
    }
  std::vector<std::vector<std::uint32_t>> fronts;
  std::vector<int> front_of(pieces.size(), -1);
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const int r = root(static_cast<int>(i));
    if (front_of[r] < 0) front_of[r] = static_cast<int>(fronts.size()), fronts.emplace_back();
    auto& f = fronts[front_of[r]];
    f.insert(f.end(), pieces[i].begin(), pieces[i].end());
  }
  if (fronts.size() >= 2) split(b, fronts, t);
}

// Splits branch b into one child per front. Going back in time from the
// fronts, each child claims the particles linked to it; the first particle
// linked to two children is where they meet. The branching point is refined
// as the intersection of the two children's principal lines. Children that
// do not meet (a front restarted beyond a pore or across a gap) begin at
// the oldest particle they claimed, or at their own oldest particle where
// they claimed none (not at the parent's oldest, its birth); where one of
// them claimed back to the parent's birth (it is the parent going on, with
// no pore or gap between), the parent split where the other one begins.
void BranchFinder::split(int b, const std::vector<std::vector<std::uint32_t>>& fronts, double t) {
  const auto oldest_of = [&](const std::vector<std::uint32_t>& set) {
    long oldest = -1;
    for (auto k : set)
      if (oldest < 0 || c_.t[k] < c_.t[oldest]) oldest = k;
    return oldest;
  };
  std::vector<int> region(c_.size(), -1);
  for (std::size_t i = 0; i < fronts.size(); ++i)
    for (auto k : fronts[i]) region[k] = static_cast<int>(i);
  std::vector<std::uint32_t> older;
  for (auto k : work_[b].branch.particles)
    if (region[k] < 0) older.push_back(k);
  std::stable_sort(older.begin(), older.end(),
                   [&](std::uint32_t a, std::uint32_t bb) { return c_.t[a] > c_.t[bb]; });
  long meet = -1;
  bool meet_found = false;
  long earliest_claimed = -1;
  for (auto k : older) {
    std::set<int> touching;
    for (auto e = c_.link_begin[k]; e < c_.link_begin[k + 1]; ++e)
      if (label_[c_.links[e]] == b && region[c_.links[e]] >= 0) touching.insert(region[c_.links[e]]);
    if (touching.empty()) continue;
    if (touching.size() >= 2) { meet = k; meet_found = true; break; }
    region[k] = *touching.begin();
    earliest_claimed = k;
  }
  const auto members_of_children = [&] {
    std::vector<std::vector<std::uint32_t>> members(fronts.size());
    for (auto k : work_[b].branch.particles)
      if (region[k] >= 0) members[region[k]].push_back(k);
    return members;
  };
  if (!meet_found && earliest_claimed < 0) {
    for (const auto& front : fronts) {
      const long start = oldest_of(front);
      if (meet < 0 || c_.t[start] < c_.t[meet]) meet = start;
    }
  } else if (!meet_found && c_.t[earliest_claimed] > work_[b].branch.start_time) {
    meet = earliest_claimed;
  } else if (!meet_found) {
    long youngest_start = -1;
    for (const auto& m : members_of_children()) {
      const long start = oldest_of(m);
      if (youngest_start < 0 || c_.t[start] > c_.t[youngest_start]) youngest_start = start;
    }
    for (auto k : older)
      if (region[k] >= 0 && c_.t[k] < c_.t[youngest_start]) region[k] = -1;
    meet = youngest_start;
  }
  auto members = members_of_children();

  // Where the children meet; refined in finish() once they are long.
  const double jx = c_.x[meet], jy = c_.y[meet];
  const double t_branch = c_.t[meet];

  BranchingEvent event;
  event.time = t_branch;
  event.x = jx;
  event.y = jy;
  event.parent = b;
  for (auto& m : members) {
    std::stable_sort(m.begin(), m.end(), [&](std::uint32_t a, std::uint32_t bb) { return c_.t[a] < c_.t[bb]; });
    Work child;
    child.branch.id = static_cast<int>(work_.size());
    child.branch.parent = b;
    child.branch.origin_x = jx;
    child.branch.origin_y = jy;
    child.branch.start_time = t_branch;
    child.branch.particles = m;
    child.origin_fixed = true;
    child.front_start = t_branch;
    rebuild_reach(child);
    for (auto k : m) label_[k] = child.branch.id;
    event.children.push_back(child.branch.id);
    work_.push_back(std::move(child));
  }
  Work& parent = work_[b];
  auto& kept = parent.branch.particles;
  kept.erase(std::remove_if(kept.begin(), kept.end(), [&](std::uint32_t k) { return region[k] >= 0; }),
             kept.end());
  parent.branch.children = event.children;
  parent.branch.end_time = t_branch;
  parent.branch.ended_by_branching = true;
  parent.ended = true;
  rebuild_reach(parent);
  (void)t;
  events_.push_back(event);
  joined_.push_back(meet_found);
}

CrackNetwork BranchFinder::run() {
  const std::size_t n = c_.size();
  std::size_t i = 0;
  while (i < n) {
    std::size_t j = i;
    while (j < n && c_.t[j] == c_.t[i]) ++j;
    const double t = c_.t[i];
    std::set<int> touched;
    // New damage next to a branch joins it; repeat, since one new particle
    // can link the next one of the same time to the branch.
    for (bool changed = true; changed;) {
      changed = false;
      for (std::size_t k = i; k < j; ++k) {
        if (label_[k] >= 0) continue;
        const int b = latest_linked_label(static_cast<std::uint32_t>(k));
        if (b >= 0) add(static_cast<std::uint32_t>(k), b), touched.insert(b), changed = true;
      }
    }
    // What is left is a new connected group: across a small gap, beyond a
    // pore, or a new crack.
    for (std::size_t k = i; k < j; ++k) {
      if (label_[k] >= 0) continue;
      std::vector<std::uint32_t> group{static_cast<std::uint32_t>(k)};
      label_[k] = -2;
      for (std::size_t q = 0; q < group.size(); ++q)
        for (auto e = c_.link_begin[group[q]]; e < c_.link_begin[group[q] + 1]; ++e) {
          const auto m = c_.links[e];
          if (m >= i && m < j && label_[m] == -1) label_[m] = -2, group.push_back(m);
        }
      for (auto m : group) label_[m] = -1;
      int b = attach_across_gap(group, t);
      if (b < 0) b = attach_at_pore(group, t);
      if (b < 0) b = new_root(group, t);
      for (auto m : group) add(m, b);
      touched.insert(b);
    }
    join_groups(i, j, touched);
    for (int b : touched) check_split(b, t);
    i = j;
  }
  return finish();
}

// The principal line of a child's particles at distances [r_min, r_max]
// from (x, y), directed away from (x, y); all its particles if fewer than 3
// lie there.
BranchFinder::Line BranchFinder::child_line(int child, double x, double y, double r_min, double r_max) const {
  std::vector<std::uint32_t> near;
  for (auto k : work_[child].branch.particles) {
    const double r = distance(c_.x[k], c_.y[k], x, y);
    if (r >= r_min && r <= r_max) near.push_back(k);
  }
  if (near.size() < 3) near = work_[child].branch.particles;
  Line l;
  principal_line(c_, near, l.cx, l.cy, l.ux, l.uy);
  if ((l.cx - x) * l.ux + (l.cy - y) * l.uy < 0) l.ux = -l.ux, l.uy = -l.uy;
  return l;
}

// The particles of branch b and of every branch that grew out of it.
void BranchFinder::collect_lineage(int b, std::vector<std::uint32_t>& particles) const {
  const auto& own = work_[b].branch.particles;
  particles.insert(particles.end(), own.begin(), own.end());
  for (int ch : work_[b].branch.children) collect_lineage(ch, particles);
}

// Each child's straight line over the stated length: the principal line of
// the particles of the child and of the branches that grew out of it (a
// child that branched again within the length is still one crack) within
// `angle_length` of the branching point. `fitted`: per child, how far from
// the point its particles reach (at most the length).
std::vector<BranchFinder::Line> BranchFinder::lines_over_length(const BranchingEvent& e, const std::vector<Line>& near,
                                                                std::vector<double>& fitted) const {
  std::vector<Line> lines;
  fitted.assign(near.size(), 0.0);
  for (std::size_t c = 0; c < e.children.size(); ++c) {
    std::vector<std::uint32_t> crack, within;
    collect_lineage(e.children[c], crack);
    for (auto k : crack) {
      const double r = distance(c_.x[k], c_.y[k], e.x, e.y);
      if (r > s_.angle_length) continue;
      within.push_back(k);
      fitted[c] = std::max(fitted[c], r);
    }
    if (within.size() < 3) {
      lines.push_back(near[c]);
      continue;
    }
    Line l;
    principal_line(c_, within, l.cx, l.cy, l.ux, l.uy);
    if ((l.cx - e.x) * l.ux + (l.cy - e.y) * l.uy < 0) l.ux = -l.ux, l.uy = -l.uy;
    // A child that forked again within the length is a wedge of two cracks,
    // whose principal axis can lie anywhere (across the wedge for a wide
    // fork): where it points more than 30 degrees off the direction from the
    // branching point to the particles' centroid, that direction is the
    // child's (the wedge's bisector). A straight or gently curved child's
    // axis and centroid direction agree within a few degrees.
    const double to_x = l.cx - e.x, to_y = l.cy - e.y, to_length = std::hypot(to_x, to_y);
    if (to_length > 0 && (to_x * l.ux + to_y * l.uy) < std::cos(30.0 * M_PI / 180.0) * to_length)
      l.ux = to_x / to_length, l.uy = to_y / to_length;
    lines.push_back(l);
  }
  return lines;
}

// With the children grown: each child's near line is the principal line of
// its particles between two separations and the near angle length from the
// meeting point (the near angle is the angle between them). The branching
// point is where lines fitted closer to the junction cross (if they are not
// nearly parallel and cross near the meeting point), and the branching time
// the arrival of the crack particle nearest to it. Children that do not
// meet inside the parent (one front was joined to it across a pore or a
// gap) have no common start to refine: the event stays where the other child
// begins. The reported angle is measured from the branching point over the
// stated angle length (lines_over_length).
void BranchFinder::refine_branching(BranchingEvent& e, bool joined) const {
  std::vector<Line> near;
  for (int ch : e.children)
    near.push_back(child_line(ch, e.x, e.y, 2 * s_.min_front_separation, s_.near_angle_length));
  if (joined && e.children.size() == 2) {
    // Lines fitted close to the junction, between one and four separations
    // from the current estimate, crossed; twice, each time from the new
    // estimate. Lines fitted farther out would cross ahead of where curved
    // children meet (0.3 mm for +-15 degree branches turning 5 degrees per
    // mm, fitted 0.6-2.4 mm out).
    const double range = 4 * s_.min_front_separation;
    double px = e.x, py = e.y;
    for (int pass = 0; pass < 2; ++pass) {
      const Line a = child_line(e.children[0], px, py, s_.min_front_separation, range);
      const Line b = child_line(e.children[1], px, py, s_.min_front_separation, range);
      const double det = a.ux * (-b.uy) - a.uy * (-b.ux);
      if (std::abs(det) <= std::sin(3.0 * M_PI / 180.0)) break;
      const double rx = b.cx - a.cx, ry = b.cy - a.cy;
      const double s = (rx * (-b.uy) - ry * (-b.ux)) / det;
      const double qx = a.cx + s * a.ux, qy = a.cy + s * a.uy;
      if (distance(qx, qy, e.x, e.y) > range) break;
      // Children that meet at an edge (a crack running into it and turning
      // both ways) cross beyond it: the meeting point stays.
      if (qx < x_min_ || qx > x_max_ || qy < y_min_ || qy > y_max_) break;
      px = qx, py = qy;
    }
    e.x = px, e.y = py;
    double best = std::numeric_limits<double>::max();
    for (int br : {e.parent, e.children[0], e.children[1]})
      for (auto k : work_[br].branch.particles) {
        const double r = distance(c_.x[k], c_.y[k], e.x, e.y);
        if (r < best) best = r, e.time = c_.t[k];
      }
  }
  // Over the stated length from the branching point: the same stretch of
  // crack at any resolution.
  e.angle_length = s_.angle_length;
  const std::vector<Line> stated = lines_over_length(e, near, e.fit_lengths);
  auto widest = [](const std::vector<Line>& lines) {
    double w = 0;
    for (std::size_t a = 0; a < lines.size(); ++a)
      for (std::size_t b = a + 1; b < lines.size(); ++b)
        w = std::max(w, std::acos(std::clamp(lines[a].ux * lines[b].ux + lines[a].uy * lines[b].uy, -1.0, 1.0)));
    return w * 180.0 / M_PI;
  };
  e.angle_deg = widest(stated);
  e.near_angle_deg = widest(near);
}

CrackNetwork BranchFinder::finish() {
  for (std::size_t i = 0; i < events_.size(); ++i) refine_branching(events_[i], joined_[i]);
  // Groups that joined another branch leave no branch of their own, nor do
  // damage spots (a crack of its own, not a pre-crack, of fewer particles
  // than a front needs, that never branched nor took a group in): number
  // the others consecutively.
  CrackNetwork net;
  const auto is_spot = [&](const CrackBranch& br) {
    return br.parent < 0 && br.children.empty() && br.joined_groups == 0 && !br.particles.empty() &&
           br.particles.size() < static_cast<std::size_t>(s_.min_front_particles) && c_.t[br.particles.front()] > 0;
  };
  std::vector<int> id(work_.size(), -1);
  int next = 0;
  for (std::size_t b = 0; b < work_.size(); ++b) {
    if (work_[b].joined_into >= 0) continue;
    const CrackBranch& br = work_[b].branch;
    if (is_spot(br)) {
      const auto first = br.particles.front();
      net.spots.push_back({c_.x[first], c_.y[first], c_.t[first], br.particles.size()});
      continue;
    }
    id[b] = next++;
  }
  for (std::size_t b = 0; b < work_.size(); ++b) {
    if (id[b] < 0) continue;
    CrackBranch br = work_[b].branch;
    br.id = id[b];
    if (br.parent >= 0) br.parent = id[br.parent];
    for (auto& ch : br.children) ch = id[ch];
    if (!br.ended_by_branching) {
      br.end_time = br.start_time;
      for (auto k : br.particles) br.end_time = std::max(br.end_time, c_.t[k]);
    }
    for (auto k : br.particles)
      br.first_arrival = br.first_arrival < 0 ? c_.t[k] : std::min(br.first_arrival, c_.t[k]);
    for (auto& k : br.particles) k = c_.id[k];
    net.branches.push_back(std::move(br));
  }
  for (auto e : events_) {
    e.parent = id[e.parent];
    for (auto& ch : e.children) ch = id[ch];
    for (int ch : e.children) {
      net.branches[ch].origin_x = e.x;
      net.branches[ch].origin_y = e.y;
    }
    net.branchings.push_back(e);
  }
  order_branching_times(net);
  return net;
}

}  // namespace

void order_branching_times(CrackNetwork& net) {
  auto& branches = net.branches;
  auto& events = net.branchings;
  const std::size_t none = events.size();
  std::vector<std::size_t> ended_by(branches.size(), none), born_in(branches.size(), none);
  for (std::size_t i = 0; i < events.size(); ++i) {
    ended_by[events[i].parent] = i;
    for (int ch : events[i].children) born_in[ch] = i;
  }
  // The splits are seen in the order the branches grew, but a branching
  // time is refined afterwards from geometry alone (the arrival of the
  // particle nearest to where the children's lines cross). On the step grid
  // a child's own split can sit in the very step its parent's children met
  // (equal raw times: in the full C3-A run a child whose second front
  // restarted beyond a pore, so that its split stays at its oldest
  // particle), and a refined time one step later put the parent's branching
  // after the child's: the child ended before it started and its children
  // were born before it. A lagging particle near the branching point can
  // likewise put it after a short child's last particle. The refinement
  // may move a time only within the order the analysis saw. So, first from
  // the leaves up: a branching is at or before the end of each child (its
  // own branching, or its last arrival).
  std::vector<char> capped(events.size(), 0);
  std::function<double(std::size_t)> capped_time = [&](std::size_t i) {
    if (!capped[i]) {
      capped[i] = 1;
      for (int ch : events[i].children) {
        const double child_end = ended_by[ch] != none ? capped_time(ended_by[ch]) : branches[ch].end_time;
        events[i].time = std::min(events[i].time, child_end);
        // A child is born at or before its first particle: the particle
        // nearest to the refined point can be the parent's, cracked late
        // beside the junction (its faces' damage spreading).
        if (branches[ch].first_arrival >= 0) events[i].time = std::min(events[i].time, branches[ch].first_arrival);
      }
    }
    return events[i].time;
  };
  for (std::size_t i = 0; i < events.size(); ++i) capped_time(i);
  // Then from the roots down: a branching is at or after its parent's start
  // (the parent's own birth, or the first arrival of a crack of its own).
  std::vector<char> raised(events.size(), 0);
  std::function<double(std::size_t)> raised_time = [&](std::size_t i) {
    if (!raised[i]) {
      raised[i] = 1;
      const std::size_t birth = born_in[events[i].parent];
      const double parent_start = birth != none ? raised_time(birth) : branches[events[i].parent].start_time;
      events[i].time = std::max(events[i].time, parent_start);
    }
    return events[i].time;
  };
  for (std::size_t i = 0; i < events.size(); ++i) raised_time(i);
  for (const auto& e : events) {
    branches[e.parent].end_time = e.time;
    for (int ch : e.children) branches[ch].start_time = e.time;
  }
  for (std::size_t b = 0; b < branches.size(); ++b)
    if (ended_by[b] == none) branches[b].end_time = std::max(branches[b].end_time, branches[b].start_time);
}

BranchSettings default_branch_settings(const ArrivalData& data, double window_seconds, double angle_length) {
  BranchSettings s;
  s.front_window = window_seconds;
  s.min_front_separation = std::max(data.horizon, 2.0 * s.link_factor * data.spacing);
  s.gap_bridge = std::max(data.horizon, 2.0 * s.link_factor * data.spacing);
  s.join_length = 2.0 * s.gap_bridge;
  s.pore_ring = 1.5 * data.spacing;
  s.angle_length = angle_length;
  s.near_angle_length = 8.0 * std::max(data.horizon, data.spacing);
  return s;
}

CrackNetwork find_branches(const ArrivalData& data, const std::vector<Pore>& pores,
                           const BranchSettings& settings) {
  BranchFinder finder(data, pores, settings);
  return finder.run();
}

std::vector<BranchBox> read_boxes_csv(const std::string& path) {
  const std::string expected = "x_min_m,x_max_m,y_min_m,y_max_m with min < max";
  std::vector<BranchBox> boxes;
  for (const auto& row : read_number_table(path, 4, "the branch box file", expected)) {
    const BranchBox b{row.values[0], row.values[1], row.values[2], row.values[3], row.line};
    if (b.x_min >= b.x_max || b.y_min >= b.y_max)
      throw file_error(path, "line " + std::to_string(row.line) + ": expected " + expected);
    boxes.push_back(b);
  }
  if (boxes.empty()) throw file_error(path, "no boxes");
  return boxes;
}

CrackNetwork branches_from_boxes(const ArrivalData& data, const std::vector<BranchBox>& boxes,
                                 const std::string& path, std::vector<std::string>& warnings) {
  const PlateExtent plate = plate_extent(data);
  CrackNetwork net;
  std::vector<std::vector<std::uint32_t>> held;  // each box's cracked particles, by index
  for (const auto& box : boxes) {
    CrackBranch br;
    br.id = static_cast<int>(net.branches.size());
    for (std::uint32_t i = 0; i < data.size(); ++i)
      if (data.arrival[i] >= 0 && data.x[i] >= box.x_min && data.x[i] <= box.x_max &&
          data.y[i] >= box.y_min && data.y[i] <= box.y_max)
        br.particles.push_back(i);
    if (br.particles.empty()) {
      // A box beside the plate was most likely written in mm.
      const bool off_plate = box.x_max < plate.x_min || box.x_min > plate.x_max || box.y_max < plate.y_min ||
                             box.y_min > plate.y_max;
      char text[200];
      std::snprintf(text, sizeof text,
                    "line %d: no cracked particle inside branch box %d (x %g to %g mm, y %g to %g mm)", box.line, br.id,
                    box.x_min * 1e3, box.x_max * 1e3, box.y_min * 1e3, box.y_max * 1e3);
      throw file_error(path, text + (" in " + data.path) + "; the plate spans " + plate.text() +
                                 (off_plate ? ": the box lies off it, and the file is in metres "
                                              "(x_min_m,x_max_m,y_min_m,y_max_m)"
                                            : ""));
    }
    // Two boxes around the same cracked particles (a row copied twice) are
    // one crack as two branches, its speeds counted twice: said, as a pore
    // file's repeated pore is (before 7 December 2026 without a word).
    for (std::size_t k = 0; k < held.size(); ++k)
      if (held[k] == br.particles) {
        warnings.push_back(path + ": lines " + std::to_string(boxes[k].line) + " and " + std::to_string(box.line) +
                           " hold the same " + std::to_string(br.particles.size()) + " cracked particles: branches " +
                           std::to_string(k) + " and " + std::to_string(br.id) +
                           " are one crack, its speeds counted twice");
        break;
      }
    held.push_back(br.particles);
    std::stable_sort(br.particles.begin(), br.particles.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return data.arrival[a] < data.arrival[b]; });
    br.start_time = data.arrival[br.particles.front()];
    br.end_time = data.arrival[br.particles.back()];
    // Origin: of the first cracked particles, the one farthest from the
    // first later one (the far end of a pre-crack inside the box).
    std::uint32_t first_later = br.particles.front();
    for (auto k : br.particles)
      if (data.arrival[k] > br.start_time) { first_later = k; break; }
    double best = -1;
    for (auto k : br.particles) {
      if (data.arrival[k] > br.start_time) break;
      const double r = distance(data.x[k], data.y[k], data.x[first_later], data.y[first_later]);
      if (r > best) best = r, br.origin_x = data.x[k], br.origin_y = data.y[k];
    }
    net.branches.push_back(std::move(br));
  }
  return net;
}

}  // namespace pd::post
