#include "mpu/polygonize.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>

#include "common/error.h"
#include "common/option_names.h"
#include "mc/marching_cubes.h"
#include "mpu/mpu_eval_ref.h"
#include "mc/marching_cubes_ref.h"

namespace mpumesh::mpu {

TriangleMesh polygonize(const MpuSurface& s, double cell, ComputeBackend& backend, PolygonizeStats* stats) {
  const Eigen::Vector3d ext = s.data_max - s.data_min;
  if (!(cell > 0)) cell = std::max(ext.maxCoeff(), 1e-3) / 200.0;
  if (!std::isfinite(cell)) throw InputError("polygonize: " + option_ref("cell") + " must be a positive number of mm");
  // Two cells beyond the data box on each side, so that the surface closes inside the grid.
  Volume grid;
  grid.spacing = Eigen::Vector3d::Constant(cell);
  grid.origin = s.data_min - Eigen::Vector3d::Constant(2 * cell);
  double points = 1;
  for (int d = 0; d < 3; ++d) {
    grid.dims[size_t(d)] = int64_t(std::ceil(ext[d] / cell)) + 5;
    points *= double(grid.dims[size_t(d)] + 2);
  }
  if (points > double(1 << 30))
    throw InputError(fmt::format("polygonize: a {:.3g} mm cell gives {:.3g} grid points over the {:.0f} x {:.0f} x "
                                 "{:.0f} mm surface (limit 2^30); use a larger {}",
                                 cell, points, ext.x(), ext.y(), ext.z(), option_ref("cell")));
  const auto t0 = std::chrono::steady_clock::now();
  // The padded field of core/mc/mc_field.h: inside >= 0, one layer of outside padding.
  mc::McField field;
  field.dims = {grid.dims[0] + 2, grid.dims[1] + 2, grid.dims[2] + 2};
  field.values.assign(size_t(field.point_count()), -1.0f);
  int64_t inside = 0;
  const int64_t nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
  std::vector<int64_t> inside_per_slice(size_t(nz), 0);
  tbb::parallel_for(int64_t(0), nz, [&](int64_t k) {
    for (int64_t j = 0; j < ny; ++j)
      for (int64_t i = 0; i < nx; ++i) {
        const Eigen::Vector3d x = grid.index_to_physical(Eigen::Vector3d(double(i), double(j), double(k)));
        const float v = float(-evaluate_f(s, x));
        field.values[size_t((i + 1) + field.dims[0] * ((j + 1) + field.dims[1] * (k + 1)))] = v;
        inside_per_slice[size_t(k)] += v >= 0;
      }
  });
  for (int64_t c : inside_per_slice) inside += c;
  const auto t1 = std::chrono::steady_clock::now();
  if (inside == 0 || inside == nx * ny * nz)
    throw InputError("polygonize: f has no zero crossing on the grid (" + std::string(inside ? "all inside" : "all outside") +
                     "): the surface is empty or the cell is too coarse");
  TriangleMesh mesh = grid_mesh_to_physical(backend.marching_cubes(field), grid);
  if (stats) {
    stats->dims = grid.dims;
    stats->cell = cell;
    stats->eval_seconds = std::chrono::duration<double>(t1 - t0).count();
    stats->mc_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  }
  return mesh;
}

}  // namespace mpumesh::mpu
