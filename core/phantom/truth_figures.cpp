#include "phantom/truth_figures.h"

#include "geometry/angle.h"
#include "mesh/slice_phase.h"
#include "particles/spacing_stats.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace mpumesh::phantom {

double weighted_quantile(const std::vector<double>& x, const std::vector<double>& w, double q) {
  std::vector<size_t> o(x.size());
  std::iota(o.begin(), o.end(), size_t(0));
  std::sort(o.begin(), o.end(), [&](size_t a, size_t b) { return x[a] < x[b]; });
  const double total = std::accumulate(w.begin(), w.end(), 0.0);
  double acc = 0;
  for (size_t i : o)
    if ((acc += w[i]) >= q * total) return x[i];
  return o.empty() ? 0 : x[o.back()];
}

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// The mesh's discrete Gaussian curvature: 2π minus the angles at a vertex, over a third
// of the area of its triangles.
std::vector<double> discrete_gauss(const TriangleMesh& m) {
  std::vector<double> deficit(m.vertices.size(), 2 * 3.14159265358979), area(m.vertices.size(), 0);
  for (const auto& t : m.triangles) {
    const double a3 = 0.5 * (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm() / 3;
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d e1 = m.vertices[t[(c + 1) % 3]] - m.vertices[t[c]];
      const Eigen::Vector3d e2 = m.vertices[t[(c + 2) % 3]] - m.vertices[t[c]];
      deficit[t[c]] -= angle_between(e1, e2);
      area[t[c]] += a3;
    }
  }
  for (size_t i = 0; i < deficit.size(); ++i) deficit[i] = area[i] > 0 ? deficit[i] / area[i] : 0;
  return deficit;
}

}  // namespace

TruthFigures truth_figures(const TriangleMesh& m, const Shape& shape, const Volume* scan) {
  TruthFigures f;
  const size_t nv = m.vertices.size(), nt = m.triangles.size();
  f.vertices = int64_t(nv), f.triangles = int64_t(nt);
  if (nv == 0 || nt == 0) return f;
  std::vector<double> dist(nv), gauss(nv);
  tbb::parallel_for(size_t(0), nv, [&](size_t i) { dist[i] = shape.distance(m.vertices[i], nullptr, &gauss[i]); });
  std::vector<double> angle(nt), area(nt);
  tbb::parallel_for(size_t(0), nt, [&](size_t i) {
    const auto& t = m.triangles[i];
    const Eigen::Vector3d c = (m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]) / 3;
    const Eigen::Vector3d cr = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]);
    Eigen::Vector3d n;
    shape.distance(c, &n);
    area[i] = 0.5 * cr.norm();
    angle[i] = area[i] > 0 ? std::acos(std::clamp(cr.normalized().dot(n), -1.0, 1.0)) * 180 / 3.14159265358979 : 0;
  });
  f.distance_mean = std::accumulate(dist.begin(), dist.end(), 0.0) / double(nv);
  f.distance_p99 = weighted_quantile(dist, std::vector<double>(nv, 1.0), 0.99);
  double sa = 0, sw = 0;
  for (size_t i = 0; i < nt; ++i) sa += area[i] * angle[i], sw += area[i];
  f.normal_mean_deg = sw > 0 ? sa / sw : 0;
  f.normal_p95_deg = weighted_quantile(angle, area, 0.95);

  f.curvature_from_file = m.curvature.size() == nv;
  std::vector<double> k(nv);
  if (f.curvature_from_file)
    for (size_t i = 0; i < nv; ++i) k[i] = m.curvature[i][2];
  else
    k = discrete_gauss(m);
  f.gauss_rank = particles::rank_correlation(k, gauss);
  std::vector<double> err(nv);
  for (size_t i = 0; i < nv; ++i) err[i] = std::abs(k[i] - gauss[i]);
  f.gauss_median_error = median(err) / shape.max_abs_gauss();

  const std::vector<double> spacing = mean_edge_lengths(m);
  std::vector<double> absk(nv);
  for (size_t i = 0; i < nv; ++i) absk[i] = std::abs(gauss[i]);
  f.spacing_rank = particles::rank_correlation(spacing, absk);
  std::vector<size_t> o(nv);
  std::iota(o.begin(), o.end(), size_t(0));
  std::sort(o.begin(), o.end(), [&](size_t a, size_t b) { return absk[a] < absk[b]; });
  const size_t tenth = std::max<size_t>(1, nv / 10);
  std::vector<double> low, high;
  for (size_t i = 0; i < tenth; ++i) low.push_back(spacing[o[i]]), high.push_back(spacing[o[nv - 1 - i]]);
  f.spacing_high_low = median(high) / std::max(1e-12, median(low));

  f.volume_error = enclosed_volume(m) / shape.volume() - 1;
  if (scan) f.slice_modulation = slice_phase(m, *scan).modulation;

  if (shape.kind == Shape::kCapsule) {
    std::vector<double> kc, kb, sc, sb;
    for (size_t i = 0; i < nv; ++i) {
      const bool cap = shape.on_cap(m.vertices[i]);
      (cap ? kc : kb).push_back(k[i]);
      (cap ? sc : sb).push_back(spacing[i]);
    }
    f.cap_gauss = median(kc), f.barrel_gauss = median(kb), f.cap_spacing = median(sc), f.barrel_spacing = median(sb);
  }
  return f;
}

}  // namespace mpumesh::phantom
