// The product at its defaults on the CT-like phantoms (core/phantom), scored against the
// closed form from the mesh file it writes, as mpumesh_bench_truth scores it. The
// targets are stated once, below, and every phantom meets every one that its shape gives
// a meaning to:
// - the rank correlation of K with the true K on the shapes whose K varies smoothly (the
//   ellipsoid and the torus). The capsule's true K takes two values (0 on the barrel,
//   1/r² on the caps), and against such a variable Spearman's correlation is at most
//   √(3 p (1 - p)) with p the caps' share of the vertices (0.866 at p = 1/2), however
//   well the two parts are told apart; its parts' K are asserted instead. The shell's is
//   constant on each sphere: its K error is asserted;
// - the spacing against the true |K| where |K| varies (not on the shell's two spheres).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_support.h"
#include "io/mesh_io.h"
#include "io/read_file.h"
#include "io/volume_io.h"
#include "phantom/ct_phantom.h"
#include "phantom/truth_figures.h"

namespace mpumesh {
namespace {

struct Targets {
  double normal_mean_deg = 1.5, normal_p95_deg = 4;
  double distance_over_pixel = 0.1;  // mean distance to the truth, in in-plane voxels
  double gauss_rank = 0.9, gauss_error = 0.10, part_gauss = 0.20;
  double spacing_high_low = 0.6, spacing_rank = -0.5;
  int64_t min_triangles = 2000, max_triangles = 30000;
};
constexpr Targets kTarget;

struct Scored {
  phantom::TruthFigures ours, mc;
  double pixel = 0;
  nlohmann::json report;
};

// The phantom meshed by `run` from its scan, or (`remesh`) from the scan's marching-cubes
// surface, and that surface itself, scored against the closed form.
Scored mesh_phantom(const std::string& name, bool remesh = false) {
  Scored r;
  for (const auto& ph : phantom::suite()) {
    if (ph.name != name) continue;
    const std::string dir = test::temp_dir("truth_" + name + (remesh ? "_remesh" : ""));
    const Volume v = phantom::scan(ph.shape, ph.scan);
    r.pixel = v.in_plane_spacing();
    write_volume(v, dir + "/scan.nii.gz");
    const std::string t = std::to_string(phantom::half_level(ph.scan));
    const Result run_mc = run("mc " + dir + "/scan.nii.gz --threshold " + t + " --backend cpu --quiet -o " + dir + "/mc.ply");
    EXPECT_EQ(run_mc.code, 0) << run_mc.out;
    const std::string input = remesh ? dir + "/mc.ply" : dir + "/scan.nii.gz --threshold " + t;
    const Result run_ours =
        run("run " + input + " --backend cpu --quiet -o " + dir + "/ours.ply --report " + dir + "/ours.json");
    EXPECT_EQ(run_ours.code, 0) << run_ours.out;
    r.ours = phantom::truth_figures(read_mesh(dir + "/ours.ply"), ph.shape);
    r.mc = phantom::truth_figures(read_mesh(dir + "/mc.ply"), ph.shape);
    r.report = nlohmann::json::parse(read_file(dir + "/ours.json"));
  }
  return r;
}

// Count, distance and normals, on every phantom.
void expect_count_distance_and_normals(const Scored& s) {
  EXPECT_GE(s.ours.triangles, kTarget.min_triangles);
  EXPECT_LE(s.ours.triangles, kTarget.max_triangles);
  EXPECT_LE(s.ours.distance_mean, kTarget.distance_over_pixel * s.pixel);
  EXPECT_LT(s.ours.distance_mean, s.mc.distance_mean);
  EXPECT_LE(s.ours.normal_mean_deg, kTarget.normal_mean_deg);
  EXPECT_LE(s.ours.normal_p95_deg, kTarget.normal_p95_deg);
  EXPECT_TRUE(s.ours.curvature_from_file);
}

void expect_curvature(const Scored& s) {
  EXPECT_GE(s.ours.gauss_rank, kTarget.gauss_rank);
  EXPECT_LE(s.ours.gauss_median_error, kTarget.gauss_error);
}

void expect_adaptivity(const Scored& s) {
  EXPECT_LE(s.ours.spacing_high_low, kTarget.spacing_high_low);
  EXPECT_LE(s.ours.spacing_rank, kTarget.spacing_rank);
}

TEST(Truth, EllipsoidMeetsEveryTarget) {
  const Scored s = mesh_phantom("ellipsoid");
  expect_count_distance_and_normals(s);
  expect_curvature(s);
  expect_adaptivity(s);
  // The tolerance came from the scan, and the report says so.
  EXPECT_NEAR(s.report["fit"]["eps_mm"].get<double>(), 0.5, 1e-9);
  EXPECT_NE(s.report["fit"]["eps_source"].get<std::string>().find("in-plane voxel"), std::string::npos);
}

TEST(Truth, TorusMeetsEveryTarget) {
  const Scored s = mesh_phantom("torus");
  expect_count_distance_and_normals(s);
  expect_curvature(s);
  expect_adaptivity(s);
}

TEST(Truth, CapsuleCapsAndBarrel) {
  const Scored s = mesh_phantom("capsule");
  expect_count_distance_and_normals(s);
  EXPECT_LE(s.ours.gauss_median_error, kTarget.gauss_error);
  expect_adaptivity(s);
  // K of each part within 20% (of the caps' K = 1/r², for the barrel's zero as well), and
  // the caps spaced at most 0.6 times as far apart as the barrel.
  const double caps = 0.01;
  EXPECT_NEAR(s.ours.cap_gauss, caps, kTarget.part_gauss * caps);
  EXPECT_NEAR(s.ours.barrel_gauss, 0, kTarget.part_gauss * caps);
  EXPECT_LE(s.ours.cap_spacing, kTarget.spacing_high_low * s.ours.barrel_spacing);
}

// Two spheres 2.5 mm apart: a plate thinner than the fit's balls (two-sheet leaves).
TEST(Truth, ThinShell) {
  const Scored s = mesh_phantom("shell");
  expect_count_distance_and_normals(s);
  EXPECT_LE(s.ours.gauss_median_error, kTarget.gauss_error);
}

// The scan's marching-cubes surface remeshed, on every phantom: its vertices are the
// data. The grey levels' partial volume is lost with the scan, so the normals are held
// to a looser bound than the scan's (on the tilted torus they come out at 1.7° mean and
// 4.6° p95, against 1.4° and 3.0° from the scan); the distance to the same.
TEST(Truth, RemeshedMarchingCubesSurface) {
  constexpr double kNormalMeanDeg = 2, kNormalP95Deg = 5;
  for (const char* name : {"ellipsoid", "torus", "capsule", "shell"}) {
    SCOPED_TRACE(name);
    const Scored s = mesh_phantom(name, true);
    EXPECT_GE(s.ours.triangles, kTarget.min_triangles);
    EXPECT_LE(s.ours.triangles, kTarget.max_triangles);
    EXPECT_LE(s.ours.distance_mean, kTarget.distance_over_pixel * s.pixel);
    EXPECT_LT(s.ours.distance_mean, s.mc.distance_mean);
    EXPECT_LE(s.ours.normal_mean_deg, kNormalMeanDeg);
    EXPECT_LE(s.ours.normal_p95_deg, kNormalP95Deg);
    EXPECT_EQ(s.report["points"].get<int64_t>(), s.report["input"]["vertices"].get<int64_t>());
    EXPECT_NE(s.report["fit"]["eps_source"].get<std::string>().find("voxel grid the input's vertices lie on"),
              std::string::npos);
  }
}

}  // namespace
}  // namespace mpumesh
