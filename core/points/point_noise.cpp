#include "points/point_noise.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "common/kd_tree.h"

namespace mpumesh::pts {

double estimate_noise(const PointCloud& cloud, const KdTree* index) {
  constexpr size_t kNear = 32, kPicked = 4000;
  const auto& pts = cloud.positions;
  if (pts.size() < kNear + 1) return 0;
  std::unique_ptr<PointIndex> own;
  const KdTree& tree = given_or_built(index, pts, own);
  const size_t step = std::max<size_t>(1, pts.size() / kPicked);
  std::vector<double> sigma((pts.size() + step - 1) / step, -1.0);
  tbb::parallel_for(size_t(0), sigma.size(), [&](size_t j) {
    uint32_t idx[kNear];
    double d2[kNear];
    nanoflann::KNNResultSet<double, uint32_t> rs(kNear);
    rs.init(idx, d2);
    tree.findNeighbors(rs, pts[j * step].data(), nanoflann::SearchParams());
    if (rs.size() < kNear) return;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < kNear; ++i) mean += pts[idx[i]];
    mean /= double(kNear);
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (size_t i = 0; i < kNear; ++i) cov += (pts[idx[i]] - mean) * (pts[idx[i]] - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    const Eigen::Vector3d n = es.eigenvectors().col(0), u = es.eigenvectors().col(2), v = es.eigenvectors().col(1);
    Eigen::Matrix<double, kNear, 6> A;
    Eigen::Matrix<double, kNear, 1> h;
    for (size_t i = 0; i < kNear; ++i) {
      const Eigen::Vector3d q = pts[idx[i]] - mean;
      const double x = q.dot(u), y = q.dot(v);
      A.row(long(i)) << x * x, x * y, y * y, x, y, 1;
      h[long(i)] = q.dot(n);
    }
    const Eigen::Matrix<double, 6, 1> c = A.colPivHouseholderQr().solve(h);
    const double rss = (A * c - h).squaredNorm();
    sigma[j] = std::sqrt(rss / double(kNear - 6));
  });
  std::vector<double> s;
  for (double x : sigma)
    if (x >= 0 && std::isfinite(x)) s.push_back(x);
  if (s.empty()) return 0;
  std::nth_element(s.begin(), s.begin() + long(s.size() / 2), s.end());
  return s[s.size() / 2];
}

}  // namespace mpumesh::pts
