// core/mesh/voxel_grid: a marching-cubes surface is found on its voxel grid, also after a
// round trip through a float PLY and with the grid's origin off zero; a mesh of points
// sampled off any grid, and the same marching-cubes surface rotated, are not.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "cpu/cpu_backend.h"
#include "io/mesh_io.h"
#include "mc/marching_cubes.h"
#include "mesh/voxel_grid.h"

namespace mpumesh {
namespace {

// An ellipsoid off the grid's symmetries, its value a smooth function of the place (so
// that few vertices share an interpolated coordinate), meshed by marching cubes.
TriangleMesh ball_mc(const Eigen::Vector3d& spacing, const Eigen::Vector3d& origin) {
  Volume v;
  v.dims = {48, 48, 20};
  v.spacing = spacing;
  v.voxels.resize(size_t(v.voxel_count()));
  const Eigen::Vector3d centre(12.13, 11.71, 19.37), axes(9.0, 7.3, 8.1);
  for (int64_t k = 0; k < v.dims[2]; ++k)
    for (int64_t j = 0; j < v.dims[1]; ++j)
      for (int64_t i = 0; i < v.dims[0]; ++i)
        v.voxels[size_t(v.index(i, j, k))] = float(
            1.0 - (v.index_to_physical(Eigen::Vector3d(double(i), double(j), double(k))) - centre).cwiseQuotient(axes).norm());
  CpuBackend cpu;
  TriangleMesh m = marching_cubes(v, {0.0}, cpu);
  for (auto& p : m.vertices) p += origin;
  return m;
}

TEST(VoxelGrid, FindsTheGridOfAMarchingCubesSurface) {
  const Eigen::Vector3d spacing(0.55, 0.55, 2.0);
  const TriangleMesh m = ball_mc(spacing, Eigen::Vector3d(-113.7, 91.3, 412.25));
  const auto grid = voxel_grid_spacing(m);
  ASSERT_TRUE(grid.has_value());
  EXPECT_NEAR((*grid - spacing).norm(), 0, 1e-4);
  // Written as float and read back.
  const auto path = std::filesystem::temp_directory_path() / "mpumesh_voxel_grid_test.ply";
  write_mesh(m, path.string());
  const auto again = voxel_grid_spacing(read_mesh(path.string()));
  std::filesystem::remove(path);
  ASSERT_TRUE(again.has_value());
  EXPECT_NEAR((*again - spacing).norm(), 0, 1e-4);
}

TEST(VoxelGrid, FindsNoGridOffOne) {
  TriangleMesh m = ball_mc(Eigen::Vector3d(0.5, 0.5, 1.5), Eigen::Vector3d::Zero());
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  TriangleMesh turned = m;
  for (auto& v : turned.vertices) v = turn * v;
  EXPECT_FALSE(voxel_grid_spacing(turned).has_value());
  // The same connectivity with its vertices moved onto the true ellipsoid: no grid.
  const Eigen::Vector3d c(12.13, 11.71, 19.37), axes(9.0, 7.3, 8.1);
  for (auto& v : m.vertices) v = c + (v - c).cwiseQuotient(axes).normalized().cwiseProduct(axes);
  EXPECT_FALSE(voxel_grid_spacing(m).has_value());
}

}  // namespace
}  // namespace mpumesh
