#pragma once
// The boundary of the material as closed polylines, and the rule that decides
// whether a bond may exist: a bond whose segment leaves the material (passes
// through a hole, a notch, or outside a re-entrant outer boundary) does not.
// docs/mesher.md, "Bonds respect voids".
#include <cstddef>
#include <cstdint>
#include <vector>

#include "geometry.hpp"

namespace pd {

class MaterialBoundary {
public:
  // `loops`: closed polylines (first point not repeated) with the material on
  // their left: the outer boundary counter-clockwise, holes clockwise. Loops
  // may touch each other or themselves at a shared vertex (a hole tangent to
  // the edge). For curved boundaries the polyline's vertices lie on the true
  // curve and its chords within a known distance of it (the caller's choice).
  // `tolerance` [m]: a segment that comes within this distance of a boundary
  // vertex or edge without entering the void by more counts as touching.
  // `typical_segment_length` [m] (about a horizon) sizes the search buckets.
  MaterialBoundary(const std::vector<std::vector<Vec2>>& loops, double tolerance, double typical_segment_length);

  // True if the segment a-b leaves the material: it crosses a boundary edge
  // (the edge's ends and the segment's ends each farther than the tolerance
  // from the other's line, on opposite sides), or passes through a boundary
  // vertex heading strictly into the void there, or starts on the boundary
  // heading into the void. Touching a vertex or running along an edge does
  // not leave the material. Symmetric: (a, b) and (b, a) give the same
  // answer. Thread-safe. a and b lie in the material or on its boundary
  // (particles' centroids).
  bool segment_leaves_material(Vec2 a, Vec2 b) const;

  // True if a boundary edge comes within `radius` of p; far from the boundary
  // no segment shorter than `radius` from p can leave the material.
  bool near(Vec2 p, double radius) const;

  double tolerance() const { return tolerance_; }

private:
  // All loops in one array: vertex k belongs to loop loop_of_[k]; its
  // neighbours along the loop are prev_[k] and next_[k].
  std::vector<Vec2> points_;
  std::vector<std::uint32_t> prev_, next_;
  double tolerance_;
  // Groups of consecutive edges (edge k runs from points_[k] to
  // points_[next_[k]]) with their boxes, in the buckets of a uniform grid
  // over the boundary's bounding box that their boxes meet.
  struct Group {
    std::uint32_t begin, end;  // edges begin .. end - 1
    double x0, y0, x1, y1;     // box grown by the tolerance
  };
  std::vector<Group> groups_;
  double x0_ = 0, y0_ = 0, bucket_ = 1;
  long nx_ = 0, ny_ = 0;
  std::vector<std::uint64_t> bucket_offsets_;
  std::vector<std::uint32_t> bucket_groups_;

  bool enters_void_at_vertex(std::uint32_t k, Vec2 direction, double angle_tolerance) const;
  // Calls f(edge) for every edge of the groups in the buckets that meet
  // [x0, x1] x [y0, y1] whose box meets it too and for which keep(group)
  // holds; stops and returns true as soon as f returns true.
  template <class GroupFilter, class F>
  bool any_edge_in_box(double x0, double y0, double x1, double y1, GroupFilter&& keep, F&& f) const;
};

}  // namespace pd
