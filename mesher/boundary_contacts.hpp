#pragma once
// Where boundary polylines cross or touch: the check that a geometry's
// boundary curves are simple and apart, in O(n) expected time (bucketed by a
// grid whose cell is the mean edge length; crowded cells are bucketed again).
#include <cstddef>
#include <optional>
#include <vector>

#include "geometry.hpp"

namespace pd {

struct BoundaryContact {
  std::size_t loop_a = 0, loop_b = 0;  // loop_a == loop_b: a loop meets itself
  Vec2 where;                          // a point at (or next to) the contact
};

// `loops`: closed polylines, first point not repeated. Two edges that share
// an end point exactly (neighbours in a loop, or the edges of two passes
// through one shared vertex, as where a hole touches the outer boundary) may
// meet at that point only; any other common point is a contact. Returns the
// first contact found, or nothing. `pair_tests`, if given, receives the
// number of edge pairs tested (linear in the edges for spread-out loops).
std::optional<BoundaryContact> find_boundary_contact(const std::vector<std::vector<Vec2>>& loops,
                                                    std::size_t* pair_tests = nullptr);

}  // namespace pd
