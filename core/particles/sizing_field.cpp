#include "particles/sizing_field.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/kd_tree.h"
#include "common/neighbour_grid.h"

namespace mpumesh::particles {

void average_over_patches(const std::vector<Eigen::Vector3d>& x, const std::vector<Eigen::Vector3d>& normal,
                          const std::vector<double>& area, const std::vector<double>& radius, std::vector<double>& gauss,
                          std::vector<double>& kappa) {
  const size_t n = x.size();
  if (n == 0) return;
  const double reach = *std::max_element(radius.begin(), radius.end());
  const NeighbourGrid grid(x, reach);
  std::vector<double> g(n), k(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const double r2 = radius[i] * radius[i];
      double w = 0, sg = 0, sk = 0;
      grid.for_each_within(x[i], [&](uint32_t j) {
        if ((x[j] - x[i]).squaredNorm() > r2 || normal[j].dot(normal[i]) < 0.5) return;
        w += area[j];
        sg += area[j] * gauss[j];
        sk += area[j] * kappa[j];
      });
      g[i] = w > 0 ? sg / w : gauss[i];
      k[i] = w > 0 ? sk / w : kappa[i];
    }
  });
  gauss.swap(g);
  kappa.swap(k);
}

SizingField::SizingField(const std::vector<Eigen::Vector3d>& x, const std::vector<Eigen::Vector3d>& normal,
                         std::vector<double> value, const KdTree* index)
    : normal_(normal),
      value_(std::move(value)),
      tree_(given_or_built(index, x, own_index_)) {}

size_t SizingField::nearest(const Eigen::Vector3d& p, uint32_t idx[kNeighbours], double d2[kNeighbours]) const {
  nanoflann::KNNResultSet<double, uint32_t> rs(kNeighbours);
  rs.init(idx, d2);
  tree_.findNeighbors(rs, p.data(), nanoflann::SearchParams());
  return rs.size();
}

double SizingField::mean(const std::vector<double>& value, const Eigen::Vector3d& n, const uint32_t* idx,
                         const double* d2, size_t count) const {
  double w = 0, sum = 0, w_any = 0, sum_any = 0;
  for (size_t k = 0; k < count; ++k) {
    const double wk = 1.0 / (d2[k] + 1e-12);
    w_any += wk;
    sum_any += wk * value[idx[k]];
    if (normal_[idx[k]].dot(n) > 0) {
      w += wk;
      sum += wk * value[idx[k]];
    }
  }
  return w > 0 ? sum / w : sum_any / w_any;
}

double SizingField::at(const Eigen::Vector3d& p, const Eigen::Vector3d& n) const {
  uint32_t idx[kNeighbours];
  double d2[kNeighbours];
  const size_t count = nearest(p, idx, d2);
  return mean(value_, n, idx, d2, count);
}

std::pair<double, double> SizingField::at_with(const SizingField& other, const Eigen::Vector3d& p,
                                               const Eigen::Vector3d& n) const {
  MPUMESH_ASSERT(&other.tree_ == &tree_ && &other.normal_ == &normal_, "SizingField::at_with: not the same points");
  uint32_t idx[kNeighbours];
  double d2[kNeighbours];
  const size_t count = nearest(p, idx, d2);
  return {mean(value_, n, idx, d2, count), mean(other.value_, n, idx, d2, count)};
}

}  // namespace mpumesh::particles
