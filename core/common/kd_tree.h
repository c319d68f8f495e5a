// A nanoflann k-d tree over a vector of points, and the median k-th-neighbour distance
// (the sampling spacing for k = 1; about the largest gap, e.g. between CT slices, for
// k = 12, since a slice's own contour holds only a few points that near).
#pragma once

#include <Eigen/Dense>
#include <nanoflann.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace mpumesh {

struct PointsAdaptor {
  const std::vector<Eigen::Vector3d>* pts;
  size_t kdtree_get_point_count() const { return pts->size(); }
  double kdtree_get_pt(size_t i, size_t d) const { return (*pts)[i][int(d)]; }
  template <class B>
  bool kdtree_get_bbox(B&) const { return false; }
};
using KdTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointsAdaptor>, PointsAdaptor, 3, uint32_t>;

// A k-d tree (leaves of up to 16 points) with its adaptor, built over `pts`, which must
// stay where they are while it is used. The same points give the same tree, so searches
// (ties included) answer the same whichever index of them is asked.
struct PointIndex {
  PointsAdaptor adaptor;
  KdTree tree;
  explicit PointIndex(const std::vector<Eigen::Vector3d>& pts)
      : adaptor{&pts}, tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {
    tree.buildIndex();
  }
  PointIndex(const PointIndex&) = delete;
  PointIndex& operator=(const PointIndex&) = delete;
};

// `given` (a caller's tree over pts), or else a tree over pts built into `own`.
inline const KdTree& given_or_built(const KdTree* given, const std::vector<Eigen::Vector3d>& pts,
                                    std::unique_ptr<PointIndex>& own) {
  if (given) return *given;
  own = std::make_unique<PointIndex>(pts);
  return own->tree;
}

// The median over up to 20,000 evenly picked points of the distance to their k-th
// nearest neighbour (k <= 15); 1 when there are too few points.
inline double median_spacing(const std::vector<Eigen::Vector3d>& pts, const KdTree& tree, size_t k = 1) {
  const size_t step = std::max<size_t>(1, pts.size() / 20000);
  std::vector<double> all((pts.size() + step - 1) / step, -1.0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, all.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t j = r.begin(); j != r.end(); ++j) {
      uint32_t idx[16];
      double d2[16];
      nanoflann::KNNResultSet<double, uint32_t> rs(k + 1);
      rs.init(idx, d2);
      tree.findNeighbors(rs, pts[j * step].data(), nanoflann::SearchParams());
      if (rs.size() == k + 1 && d2[k] > 0) all[j] = std::sqrt(d2[k]);
    }
  });
  std::vector<double> d;
  for (double v : all)
    if (v > 0) d.push_back(v);
  if (d.empty()) return 1.0;
  std::nth_element(d.begin(), d.begin() + ptrdiff_t(d.size() / 2), d.end());
  return d[d.size() / 2];
}

}  // namespace mpumesh
