#include "mesh/triangulation_cleanup.h"

#include <algorithm>
#include <cmath>

#include "mesh/cgal_geometry.h"
#include "mesh/edge_edit.h"
#include "mesh/thin_triangles.h"
#include "mpu/mpu_eval_ref.h"

namespace mpumesh {
namespace {

using Tri = std::array<uint32_t, 3>;

// The triangles as sorted vertex triples, sorted: the restricted facets to compare with.
std::vector<Tri> sorted_triples(const std::vector<Tri>& triangles) {
  std::vector<Tri> out;
  for (auto t : triangles) {
    std::sort(t.begin(), t.end());
    out.push_back(t);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The triangles of the cleaned mesh that changed: those that are no restricted facet (in
// the raw mesh's numbering, `kept`), or are one twice, and every triangle around a
// relaxed vertex; ascending.
std::vector<uint32_t> changed_triangles(const TriangleMesh& mesh, const std::vector<Tri>& raw_tris,
                                        const std::vector<uint32_t>& kept, const std::vector<uint32_t>& relaxed) {
  std::vector<std::pair<Tri, uint32_t>> now;
  for (uint32_t f = 0; f < mesh.triangles.size(); ++f) {
    Tri t;
    for (size_t k = 0; k < 3; ++k) t[k] = kept[mesh.triangles[f][k]];
    std::sort(t.begin(), t.end());
    now.emplace_back(t, f);
  }
  std::sort(now.begin(), now.end());
  std::vector<uint32_t> changed;
  for (size_t k = 0; k < now.size(); ++k)
    if (!std::binary_search(raw_tris.begin(), raw_tris.end(), now[k].first) ||
        (k > 0 && now[k - 1].first == now[k].first) || (k + 1 < now.size() && now[k + 1].first == now[k].first))
      changed.push_back(now[k].second);
  std::vector<char> moved(mesh.vertices.size(), 0);
  for (uint32_t v : relaxed) moved[v] = 1;
  for (uint32_t f = 0; f < mesh.triangles.size(); ++f)
    if (moved[mesh.triangles[f][0]] || moved[mesh.triangles[f][1]] || moved[mesh.triangles[f][2]])
      changed.push_back(f);
  std::sort(changed.begin(), changed.end());
  changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
  return changed;
}

// The distance of x from f = 0, |f| / |∇f|.
double surface_distance(const mpu::MpuSurface& s, const Eigen::Vector3d& x) {
  const mpu::Sample e = mpu::evaluate_fg(s, x);
  const double g = e.g.norm();
  return g > 0 ? std::abs(e.f) / g : INFINITY;
}

// x moved back onto f = 0 by four Newton steps (NaN where ∇f vanishes or no leaf holds it).
Eigen::Vector3d onto_surface(const mpu::MpuSurface& s, Eigen::Vector3d x) {
  for (int k = 0; k < 4; ++k) {
    const mpu::Sample e = mpu::evaluate_fg(s, x);
    const double g2 = e.g.squaredNorm();
    if (!(g2 > 0) || e.leaves == 0) return Eigen::Vector3d(Eigen::Vector3d::Constant(NAN));
    x -= e.f / g2 * e.g;
  }
  return x;
}

}  // namespace

void clean_up_triangulation(const mpu::MpuSurface& s, TriangleMesh& mesh, RestrictedDelaunayStats& stats) {
  const TriangleMesh raw = mesh;
  const std::vector<Tri> raw_tris = sorted_triples(raw.triangles);
  FrozenVertices frozen(raw.vertices.size());
  const auto distance = [&s](const Eigen::Vector3d& x) { return surface_distance(s, x); };
  const auto project = [&s](const Eigen::Vector3d& x) { return onto_surface(s, x); };
  ThinTriangleStats tt;
  std::vector<uint32_t> relaxed;
  for (int attempt = 0;; ++attempt) {
    mesh = raw;
    ThinTriangleOptions topt;
    topt.frozen = frozen;
    tt = remove_thin_triangles(mesh, distance, topt);
    RelaxOptions ropt;
    ropt.frozen = frozen.renumbered(tt.kept);
    relaxed = relax_thin_triangles(mesh, project, ropt);
    const std::vector<uint32_t> changed = changed_triangles(mesh, raw_tris, tt.kept, relaxed);
    const auto pairs = intersecting_triangles(mesh, &changed);
    if (pairs.empty()) break;
    stats.cleanup_retries = attempt + 1;
    if (attempt == 2) {
      mesh = raw;
      tt = ThinTriangleStats{};
      relaxed.clear();
      break;
    }
    for (const auto& [a, b] : pairs)
      for (const uint32_t f : {a, b})
        for (uint32_t v : mesh.triangles[f]) frozen.freeze(tt.kept[v]);
  }
  stats.edge_flips = tt.flips;
  stats.edge_collapses = tt.collapses;
  stats.vertices_relaxed = int64_t(relaxed.size());
}

}  // namespace mpumesh
