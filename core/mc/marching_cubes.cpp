#include "mc/marching_cubes.h"

#include <fmt/format.h>

#include "common/error.h"
#include "mc/marching_cubes_ref.h"

namespace mpumesh {

TriangleMesh grid_mesh_to_physical(const mc::McMesh& m, const Volume& vol) {
  TriangleMesh out;
  out.vertices.resize(m.grid_vertices.size());
  for (size_t i = 0; i < m.grid_vertices.size(); ++i) {
    const auto& g = m.grid_vertices[i];
    out.vertices[i] = vol.index_to_physical(Eigen::Vector3d(g[0] - 1.0, g[1] - 1.0, g[2] - 1.0));
  }
  out.triangles = m.triangles;
  if (vol.direction.determinant() < 0)
    for (auto& t : out.triangles) std::swap(t[1], t[2]);
  return out;
}

TriangleMesh marching_cubes(const Volume& vol, mc::ThresholdRange range, ComputeBackend& backend) {
  validate_volume(vol, vol.source);
  require_3d(vol);
  const mc::McField field = mc::make_threshold_field(vol, range);
  int64_t inside = 0;
  for (float f : field.values) inside += f >= 0.0f;
  const std::string what = vol.source.empty() ? std::string("volume") : vol.source;
  const std::string range_text =
      std::isinf(range.hi) ? fmt::format("{}", range.lo) : fmt::format("{}:{}", range.lo, range.hi);
  if (inside == 0)
    throw InputError(fmt::format("{}: the threshold {} selects no voxel: there is no surface", what, range_text));
  if (inside == vol.voxel_count())
    throw InputError(fmt::format("{}: the threshold {} selects every voxel (the surface would be the volume's "
                                 "bounding box)",
                                 what, range_text));
  return grid_mesh_to_physical(backend.marching_cubes(field), vol);
}

}  // namespace mpumesh
