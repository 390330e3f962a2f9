#include "neighbor_search.hpp"

#include <algorithm>
#include <nanoflann.hpp>

namespace pd {

namespace {
struct PointCloud {
  const std::vector<double>& x;
  const std::vector<double>& y;
  std::size_t kdtree_get_point_count() const { return x.size(); }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const { return dim == 0 ? x[i] : y[i]; }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const {
    return false;
  }
};
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointCloud>,
                                                 PointCloud, 2, std::uint32_t>;
}  // namespace

struct NeighborSearch::Impl {
  PointCloud cloud;
  Tree tree;
  Impl(const std::vector<double>& x, const std::vector<double>& y)
      : cloud{x, y}, tree(2, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {
    tree.buildIndex();
  }
};

NeighborSearch::NeighborSearch(const std::vector<double>& x, const std::vector<double>& y)
    : impl_(std::make_unique<Impl>(x, y)) {}
NeighborSearch::~NeighborSearch() = default;

void NeighborSearch::within(double px, double py, double radius, std::vector<std::uint32_t>& out) const {
  out.clear();
  if (impl_->cloud.x.empty()) return;
  const double query[2] = {px, py};
  std::vector<std::pair<std::uint32_t, double>> matches;
  nanoflann::SearchParams params;
  params.sorted = false;
  // nanoflann's L2 adaptor works with squared distances.
  impl_->tree.radiusSearch(query, radius * radius, matches, params);
  out.reserve(matches.size());
  for (const auto& m : matches) out.push_back(m.first);
  std::sort(out.begin(), out.end());
}

}  // namespace pd
