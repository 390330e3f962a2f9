#pragma once
// Fixed-radius neighbour search over particle positions (k-d tree).
// The one place where the toolchain finds points near points.
#include <cstdint>
#include <memory>
#include <vector>

namespace pd {

class NeighborSearch {
public:
  // Keeps references to x and y: they must outlive the search object.
  NeighborSearch(const std::vector<double>& x, const std::vector<double>& y);
  ~NeighborSearch();
  NeighborSearch(const NeighborSearch&) = delete;
  NeighborSearch& operator=(const NeighborSearch&) = delete;

  // Indices of all points with distance <= radius from (px, py), sorted by
  // index (deterministic whatever the tree layout). Thread-safe.
  void within(double px, double py, double radius, std::vector<std::uint32_t>& out) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pd
