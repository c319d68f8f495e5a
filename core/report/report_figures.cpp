#include "report/report_figures.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "mesh/surface_attributes.h"
#include "particles/spacing_stats.h"

namespace mpumesh::report {

ViewRegion pick_region(const TriangleMesh& m) {
  Eigen::Vector3d lo = m.vertices[0], hi = m.vertices[0];
  for (const auto& v : m.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const double r = std::max(0.04 * (hi - lo).norm(), 1e-3);
  std::vector<double> area(m.vertices.size(), 0.0);
  for (const auto& t : m.triangles) {
    const double a = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm() / 6;
    for (uint32_t i : t) area[i] += a;
  }
  struct Cell {
    double score = 0;
    Eigen::Vector3d weighted = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::Zero();
    double weight = 0;
    int count = 0;
  };
  const Eigen::Vector3d mid = (lo + hi) / 2;
  std::vector<double> dist(m.vertices.size());
  for (size_t i = 0; i < m.vertices.size(); ++i) dist[i] = (m.vertices[i] - mid).norm();
  std::vector<double> sorted = dist;
  std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(sorted.size() * 2 / 3), sorted.end());
  const double outer = sorted[sorted.size() * 2 / 3];
  std::unordered_map<uint64_t, Cell> cells;
  for (size_t i = 0; i < m.vertices.size(); ++i) {
    const Eigen::Vector3d out = m.vertices[i] - mid;
    if (dist[i] < outer || m.normals[i].cast<double>().dot(out) < 0.5 * dist[i]) continue;
    const Eigen::Vector3d g = ((m.vertices[i] - lo) / r).array().floor();
    const uint64_t key = (uint64_t(g.x()) << 42) | (uint64_t(g.y()) << 21) | uint64_t(g.z());
    Cell& c = cells[key];
    const double w = std::abs(double(m.curvature[i][2])) * area[i];
    c.score += w;
    c.weighted += (w + 1e-12) * m.vertices[i];
    c.weight += w + 1e-12;
    c.normal += m.normals[i].cast<double>();
    ++c.count;
  }
  const Cell* best = nullptr;
  for (const auto& [k, c] : cells)
    if (c.count >= 30 && (!best || c.score > best->score)) best = &c;
  if (!best)
    for (const auto& [k, c] : cells)
      if (!best || c.count > best->count) best = &c;
  if (!best) return {mid, Eigen::Vector3d(1, -1, 1).normalized(), r};
  ViewRegion reg;
  const Eigen::Vector3d target = best->weighted / best->weight;
  size_t nearest = 0;
  for (size_t i = 1; i < m.vertices.size(); ++i)
    if ((m.vertices[i] - target).squaredNorm() < (m.vertices[nearest] - target).squaredNorm()) nearest = i;
  reg.centre = m.vertices[nearest];
  reg.view = best->normal.norm() > 0 ? Eigen::Vector3d(best->normal.normalized()) : Eigen::Vector3d(1, -1, 1).normalized();
  reg.radius = r;
  return reg;
}

VertexAdaptivity vertex_adaptivity(const TriangleMesh& m) {
  const std::vector<double> gauss = gauss_at_mesh_scale(m), edge = mean_edge_lengths(m);
  VertexAdaptivity a;
  for (size_t i = 0; i < m.vertices.size(); ++i)
    if (edge[i] > 0) a.abs_gauss.push_back(std::abs(gauss[i])), a.spacing.push_back(edge[i]);
  a.rank_correlation = particles::rank_correlation(a.abs_gauss, a.spacing);
  return a;
}

}  // namespace mpumesh::report
