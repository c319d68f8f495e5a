#include "tet/tet_quality.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace mpumesh {
TetShape tet_shape(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                   const Eigen::Vector3d& d) {
  TetShape s;
  s.volume = (b - a).dot((c - a).cross(d - a)) / 6;
  const Eigen::Vector3d p[4] = {a, b, c, d};
  double area = 0;
  for (const auto& f : kTetFace) area += 0.5 * (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]).norm();
  s.min_dihedral_deg = 180, s.max_dihedral_deg = 0;
  for (double angle : dihedral_angles(a, b, c, d))
    s.min_dihedral_deg = std::min(s.min_dihedral_deg, angle), s.max_dihedral_deg = std::max(s.max_dihedral_deg, angle);
  // r_in = 3 V / A; r_circ from the circumcentre c: |c - a| with 2 (p_k - a) · c' = |p_k - a|².
  const double r_in = area > 0 ? 3 * std::abs(s.volume) / area : 0;
  Eigen::Matrix3d M;
  M.row(0) = b - a, M.row(1) = c - a, M.row(2) = d - a;
  const Eigen::Vector3d rhs(M.row(0).squaredNorm() / 2, M.row(1).squaredNorm() / 2, M.row(2).squaredNorm() / 2);
  const double det = M.determinant();
  const double r_circ = std::abs(det) > 0 ? (M.inverse() * rhs).norm() : INFINITY;
  s.radius_ratio = std::isfinite(r_circ) && r_circ > 0 ? 3 * r_in / r_circ : 0;
  if (!std::isfinite(s.min_dihedral_deg)) s.min_dihedral_deg = 0;
  return s;
}

TetQuality measure_tet_quality(const TetMesh& m) {
  TetQuality q;
  q.nodes = int64_t(m.nodes.size());
  q.tets = int64_t(m.tets.size());
  q.regions = m.regions;
  q.boundary_triangles = int64_t(m.boundary.size());
  if (m.tets.empty()) return q;
  // Each tetrahedron's figures in parallel, then added up in order (the same sums
  // whatever the threads).
  std::vector<TetShape> shape(m.tets.size());
  std::vector<std::array<uint8_t, 6>> bins(m.tets.size());
  tbb::parallel_for(size_t(0), m.tets.size(), [&](size_t t) {
    const auto& v = m.tets[t];
    const Eigen::Vector3d p[4] = {m.nodes[v[0]], m.nodes[v[1]], m.nodes[v[2]], m.nodes[v[3]]};
    shape[t] = tet_shape(p[0], p[1], p[2], p[3]);
    const std::array<double, 6> angle = dihedral_angles(p[0], p[1], p[2], p[3]);
    for (size_t e = 0; e < 6; ++e)
      bins[t][e] = uint8_t(std::isfinite(angle[e]) ? std::clamp(int(angle[e] / 5), 0, 35) : 0);
  });
  struct Acc {
    int64_t inverted = 0, below10 = 0, below15 = 0;
    double volume = 0, rr = 0, rr_min = INFINITY, dmin = 180, dmax = 0;
    std::array<int64_t, 36> hist{};
  } total;
  for (size_t t = 0; t < shape.size(); ++t) {
    const TetShape& s = shape[t];
    total.inverted += !(s.volume > 0);
    total.volume += s.volume;
    total.rr += s.radius_ratio;
    total.rr_min = std::min(total.rr_min, s.radius_ratio);
    total.dmin = std::min(total.dmin, s.min_dihedral_deg);
    total.dmax = std::max(total.dmax, s.max_dihedral_deg);
    total.below10 += s.min_dihedral_deg < 10;
    total.below15 += s.min_dihedral_deg < 15;
    for (uint8_t b : bins[t]) ++total.hist[b];
  }
  const double n = double(m.tets.size());
  q.inverted = total.inverted;
  q.volume_mm3 = total.volume;
  q.min_dihedral_deg = total.dmin;
  q.max_dihedral_deg = total.dmax;
  q.pct_min_dihedral_below_10 = 100.0 * double(total.below10) / n;
  q.pct_min_dihedral_below_15 = 100.0 * double(total.below15) / n;
  q.radius_ratio_mean = total.rr / n;
  q.radius_ratio_min = total.rr_min;
  q.dihedral_histogram = total.hist;
  return q;
}

}  // namespace mpumesh
