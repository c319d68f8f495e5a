// Shared test fixtures: analytic phantoms and meshes whose answers are known, the Vulkan
// backend with validation on (skipped when no device exists, a failure when CI sets
// MPUMESH_REQUIRE_VULKAN=1), and the real sample data from Debian packages.
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <string>

#include "geometry/triangle_mesh.h"
#include "geometry/point_cloud.h"
#include "mpu/mpu_surface.h"
#include "particles/particle_system.h"
#include "particles/spacing_stats.h"
#include "pipeline/run_pipeline.h"
#include "segment/segmentation.h"
#include "volume/volume.h"
#include "vulkan_backend.h"

namespace mpumesh::test {

// Three draws of `d` as a vector, drawn z, then y, then x: the order is fixed here, since a
// constructor's arguments are evaluated in the order each compiler chooses.
template <class Dist, class Rng>
Eigen::Vector3d random_vector(Dist& d, Rng& rng) {
  const double z = d(rng), y = d(rng), x = d(rng);
  return {x, y, z};
}

bool env_flag(const char* name);

// A Vulkan backend with validation layers on, or null with the reason in `why`.
std::unique_ptr<vk::VulkanBackend> try_vulkan(std::string& why);

// Expects that the backend's validation layer reported nothing.
void expect_no_validation_messages(vk::VulkanBackend& b);

// A label map of `dims` voxels of `spacing` (origin 0) whose voxel at p holds label(p).
Volume label_volume(std::array<int64_t, 3> dims, Eigen::Vector3d spacing,
                    const std::function<float(const Eigen::Vector3d&)>& label);

// A ball of radius r (mm) at `centre`, smooth intensity: 1000 at the centre side of the
// surface, -1000 outside, linear across one voxel, so the 0 isosurface is the sphere.
Volume sphere_volume(std::array<int64_t, 3> dims, Eigen::Vector3d spacing, Eigen::Vector3d centre, double r);

// An ellipsoid "bone" phantom with known surface: a bright shell (shell_hu, shell_mm thick
// inside the outer surface) around a dimmer interior (interior_hu) on background 0 HU,
// thin slices (voxels sampled at the slice plane), in-plane partial volume (each pixel
// the mean of 4 x 4 sub-samples), plus Gaussian noise. The outer surface is the truth.
struct ShellPhantom {
  Eigen::Vector3d centre{0, 0, 0};
  Eigen::Vector3d radii{20, 20, 20};  // outer semi-axes, mm
  double shell_mm = 2.0;
  double shell_hu = 1000, interior_hu = 700;
  double noise_hu = 0;
  uint32_t seed = 1;
  Eigen::Vector3d spacing{0.5, 0.5, 2.0};
  double margin_mm = 4;  // space around the ellipsoid
  Volume volume() const;
  // Distance (mm) from p to the outer surface and the outward unit normal at the closest
  // surface point.
  double distance(const Eigen::Vector3d& p, Eigen::Vector3d* normal = nullptr) const;
  // 1 inside the outer surface, 0 outside (no partial volume).
  bool inside(const Eigen::Vector3d& p) const;
};

// Every pixel the segmentation labels differently from the phantom's truth lies within
// one in-plane pixel of its true surface (printed with `what`).
void expect_boundary_within_one_pixel(const ShellPhantom& ph, const Volume& vol, const seg::Segmentation& s,
                                      const char* what);

// Analytic closed surfaces with known distance, normal and Gaussian curvature: a sphere
// (radius a), an ellipsoid (semi-axes a, b, c) and a torus (major a, minor b) around the
// z axis, centred at the origin.
struct AnalyticShape {
  enum Kind { kSphere, kEllipsoid, kTorus } kind = kSphere;
  double a = 20, b = 20, c = 20;
  double value(const Eigen::Vector3d& p) const;  // < 0 inside
  Eigen::Vector3d gradient(const Eigen::Vector3d& p) const;
  // Distance to the surface, the closest surface point's outward normal and K there.
  double distance(const Eigen::Vector3d& p, Eigen::Vector3d* normal = nullptr, double* gauss = nullptr) const;
  Eigen::Vector3d half_extent() const;
};

// Oriented points exactly on the surface: the roots of `value` on the edges of a grid of
// spacing (h_xy, h_xy, h_z) that cross it. dense: every edge (dense-uniform sampling).
// Otherwise a slice stack as the points stage makes one from a CT: contours at
// z = k h_z, plus caps, the roots on z edges where the surface lies within 45° of the
// slice plane.
PointCloud sample_shape(const AnalyticShape& s, double h_xy, double h_z, bool dense);

// A spherical shell (a thin plate): the outer sphere and the inner one, dense at 0.5 mm,
// the inner normals toward the centre (outward of the shell).
PointCloud spherical_shell(double r_outer, double r_inner);

// A label map (whole numbers, 0 the background; no partial volume, as segmenters write
// them), 0.8 x 0.8 x 1.6 mm voxels: an ellipsoid (semi-axes 12, 9, 10 mm) cut by a plane
// tilted against the slices into label 1 and label 2, which touch across the cut; a ball
// of radius 5 mm apart, label 3; label 4 of 2 voxels, too small to mesh; and a ball of
// radius 4 mm, label 5, inside a ball of radius 8.5 mm, label 6, which touch on a sphere.
struct LabelPhantom {
  Eigen::Vector3d centre{19, 18, 16}, radii{12, 9, 10};
  Eigen::Vector3d cut_normal = Eigen::Vector3d(1, 0.3, 0.5).normalized();  // label 2 on its side
  Eigen::Vector3d ball_centre{38, 18, 16};
  double ball_radius = 5;
  Eigen::Vector3d nest_centre{56.3, 18.2, 17.1};
  double core_radius = 4, nest_radius = 8.5;
  Volume volume() const;
};

// The k-th of n nearly even directions on the unit sphere (a Fibonacci spiral).
Eigen::Vector3d fibonacci_direction(int k, int n);

// Particles on an analytic shape: its points (sample_shape, dense or a slice stack at 2
// mm), their fit, the particles asked for `count` on the CPU, their spacing against the
// true |K|, and their largest distance from the true surface.
struct ShapeRun {
  mpu::MpuSurface surface;
  PointCloud cloud;
  particles::ParticleState st;
  particles::SampleStats stats;
  particles::SpacingStats spacing;
  double max_true_distance = 0;
};
ShapeRun run_shape(const AnalyticShape& shape, int64_t count, bool dense = true);
// Its figures on one line, and the population's history.
void print_run(const char* name, const ShapeRun& r);

// A ball of radius 6 mm (0.6 x 0.6 x 2 mm voxels, 0 HU at its surface) written to `dir`
// (ball.mha); its path. And the pipeline's options for it as `run --threshold 0
// --particles 1500` makes them.
std::string ball_phantom(const std::string& dir);
pipeline::RunOptions ball_run_options();

// Random binary volume (values +-100), fixed seed.
Volume random_volume(std::array<int64_t, 3> dims, double fill, uint32_t seed);

TriangleMesh icosahedron(double edge);      // regular, outward
TriangleMesh unit_cube();                   // 12 triangles, [0,1]^3, outward
TriangleMesh icosphere(double r, int subdivisions);

// Real data from Debian packages, or "" when the package is missing (see
// MPUMESH_DATA_OR_SKIP): the InVesalius head CT (invesalius-examples, or the path in
// MPUMESH_SAMPLE_CT) and pydicom's test files (python3-pydicom).
std::string sample_ct_path();
std::string pydicom_file(const std::string& name);

// A fresh empty directory under the test temp dir.
std::string temp_dir(const std::string& name);

}  // namespace mpumesh::test

#define MPUMESH_VULKAN_OR_SKIP(var)                                                            \
  std::string var##_why;                                                                       \
  auto var = ::mpumesh::test::try_vulkan(var##_why);                                           \
  if (!var) {                                                                                  \
    if (::mpumesh::test::env_flag("MPUMESH_REQUIRE_VULKAN")) FAIL() << var##_why;              \
    GTEST_SKIP() << var##_why;                                                                 \
  }

// Declares `var` = path_expr; an empty path skips the test, or fails it when
// MPUMESH_REQUIRE_DATA=1 (scripts/test.sh installs the packages).
#define MPUMESH_DATA_OR_SKIP(var, path_expr, package)                                          \
  const std::string var = (path_expr);                                                         \
  if (var.empty()) {                                                                           \
    if (::mpumesh::test::env_flag("MPUMESH_REQUIRE_DATA")) FAIL() << "missing: install " package; \
    GTEST_SKIP() << "missing: install " package;                                               \
  }

#define MPUMESH_SAMPLE_CT_OR_SKIP(var) \
  MPUMESH_DATA_OR_SKIP(var, ::mpumesh::test::sample_ct_path(), "invesalius-examples")
