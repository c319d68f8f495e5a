#include "mesh/slice_phase.h"

#include <cmath>

#include "mesh/surface_attributes.h"

namespace mpumesh {

SlicePhase slice_phase(const TriangleMesh& mesh, const Eigen::Vector3d& origin, const Eigen::Vector3d& slice_axis,
                       double slice_spacing, int bins) {
  TriangleMesh m;
  m.vertices = mesh.vertices;
  m.triangles = mesh.triangles;
  estimate_mesh_curvature(m);
  SlicePhase out;
  out.bin_mean_abs_h.assign(size_t(bins), 0.0);
  out.bin_vertices.assign(size_t(bins), 0);
  std::vector<char> used(m.vertices.size(), 0);
  for (const auto& t : m.triangles)
    for (uint32_t v : t) used[v] = 1;
  double total = 0;
  int64_t count = 0;
  for (size_t i = 0; i < m.vertices.size(); ++i) {
    if (!used[i]) continue;
    const double h = std::abs(double(m.curvature[i][3]));
    if (!std::isfinite(h)) continue;
    const double t = (m.vertices[i] - origin).dot(slice_axis) / slice_spacing;
    const int b = std::min(bins - 1, int((t - std::floor(t)) * bins));
    out.bin_mean_abs_h[size_t(b)] += h;
    ++out.bin_vertices[size_t(b)];
    total += h;
    ++count;
  }
  if (count == 0) return out;
  out.mean_abs_h = total / double(count);
  double lo = INFINITY, hi = 0;
  for (int b = 0; b < bins; ++b) {
    if (out.bin_vertices[size_t(b)] == 0) continue;
    out.bin_mean_abs_h[size_t(b)] /= double(out.bin_vertices[size_t(b)]);
    lo = std::min(lo, out.bin_mean_abs_h[size_t(b)]);
    hi = std::max(hi, out.bin_mean_abs_h[size_t(b)]);
  }
  out.modulation = out.mean_abs_h > 0 ? (hi - lo) / out.mean_abs_h : 0;
  return out;
}

SlicePhase slice_phase(const TriangleMesh& mesh, const Volume& scan, int bins) {
  return slice_phase(mesh, scan.origin, scan.direction.col(2).normalized(), scan.spacing.z(), bins);
}

}  // namespace mpumesh
