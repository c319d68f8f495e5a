#include "mesh/voxel_grid.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <vector>

namespace mpumesh {
namespace {

// An axis's planes: the values v0 + i s.
struct Planes {
  double v0 = 0, s = 0;
  double steps(double v) const { return (v - v0) / s; }
  // Within `tolerance` of the spacing, and the rounding of float-stored coordinates.
  bool on(double v, double tolerance = 1e-3) const {
    return std::abs(steps(v) - std::round(steps(v))) * s <= tolerance * s + 1e-6 * std::abs(v);
  }
};

// v0 and s fitted by least squares to the values on the planes (each value once).
Planes refit(const Planes& p, const std::vector<double>& values) {
  double n = 0, si = 0, sv = 0, sii = 0, siv = 0;
  for (double v : values) {
    if (!p.on(v)) continue;
    const double i = std::round(p.steps(v));
    n += 1, si += i, sv += v, sii += i * i, siv += i * v;
  }
  const double det = n * sii - si * si;
  if (n < 3 || !(std::abs(det) > 0)) return p;
  return {(sii * sv - si * siv) / det, (n * siv - si * sv) / det};
}

// The planes along axis d (see the header), or s = 0.
Planes axis_planes(const TriangleMesh& m, int d) {
  std::unordered_map<double, int64_t> count;
  count.reserve(m.vertices.size());
  for (const auto& v : m.vertices) ++count[v[d]];
  std::vector<std::pair<int64_t, double>> by_count;
  by_count.reserve(count.size());
  for (const auto& [value, n] : count) by_count.push_back({-n, value});
  const size_t top = std::min<size_t>(kGridTopValues, by_count.size());
  std::partial_sort(by_count.begin(), by_count.begin() + ptrdiff_t(top), by_count.end());
  std::vector<double> v, shared;
  for (size_t i = 0; i < top; ++i)
    if (-by_count[i].first >= std::max<int64_t>(3, -by_count[0].first / 10)) v.push_back(by_count[i].second);
  for (const auto& [minus_n, value] : by_count)
    if (-minus_n >= 3) shared.push_back(value);
  std::sort(v.begin(), v.end());
  double gap = INFINITY;
  for (size_t i = 1; i < v.size(); ++i) gap = std::min(gap, v[i] - v[i - 1]);
  Planes none{0, 0};
  if (!(gap > 0) || !std::isfinite(gap)) return none;
  // The common values may skip planes: the largest gap / k that holds kGridAxisShare of
  // the vertices' coordinates (on a coarse axis, most vertices lie on its edges, off its
  // planes).
  for (int k = 1; k <= 4; ++k) {
    const Planes q = refit(refit({by_count[0].second, gap / k}, v), shared);
    int64_t on = 0;
    for (const auto& [value, n] : count) on += q.on(value) ? n : 0;
    if (double(on) >= kGridAxisShare * double(m.vertices.size())) return q;
  }
  return none;
}

}  // namespace

std::optional<Eigen::Vector3d> voxel_grid_spacing(const TriangleMesh& mesh) {
  if (mesh.vertices.size() < 8) return std::nullopt;
  Planes p[3];
  for (int d = 0; d < 3; ++d)
    if (!((p[d] = axis_planes(mesh, d)).s > 0)) return std::nullopt;
  size_t on_edges = 0;
  for (const auto& v : mesh.vertices) on_edges += int(p[0].on(v.x())) + int(p[1].on(v.y())) + int(p[2].on(v.z())) >= 2;
  if (double(on_edges) < kGridVertexShare * double(mesh.vertices.size())) return std::nullopt;
  return Eigen::Vector3d(p[0].s, p[1].s, p[2].s);
}

}  // namespace mpumesh
