// A label map meshed into one multi-material complex (core/pipeline/complex_run.h), on the
// material phantoms with analytic truth (core/phantom/material_phantom.h): every label's
// boundary a closed oriented manifold, no crossing triangle pair, every triangle on a
// true interface, the junction curves where the truth has them, the labels' volumes, and
// the one-slice joint with no shared interface.
#include <gtest/gtest.h>

#include <cmath>

#include "cpu/cpu_backend.h"
#include "io/mesh_io.h"
#include "multi/complex_figures.h"
#include "multi/region_support.h"
#include "multi/thin_wedges.h"
#include "phantom/complex_truth.h"
#include "phantom/material_phantom.h"
#include "pipeline/complex_run.h"
#include "test_support.h"

namespace mpumesh {
namespace {

struct Meshed {
  pipeline::ComplexResult result;
  phantom::ComplexTruth truth;
};

Meshed mesh_phantom(const std::string& name) {
  for (const phantom::MaterialPhantom& m : phantom::material_suite()) {
    if (m.name != name) continue;
    const Volume map = phantom::material_scan(m);
    CpuBackend cpu;
    std::vector<int64_t> labels;
    for (int l : m.labels()) labels.push_back(l);
    Meshed out;
    out.result = pipeline::run_complex(
        map, labels, false, pipeline::RunOptions{}, [&]() -> ComputeBackend& { return cpu; }, nullptr,
        [](pipeline::LabelRun&) {});
    out.truth = phantom::complex_truth(m, out.result.complex.mesh, 2 * map.in_plane_spacing());
    return out;
  }
  ADD_FAILURE() << "no phantom " << name;
  return {};
}

// The triangles' shape, the smallest angle at least 25 degrees away
// from the junction curves and 20 at them, the mean radius ratio at least 0.95 (25.2-39.7
// degrees, 37.4-39.7 away from the junctions, and 0.959-0.970 measured on the phantoms
// with the complex's optimisation; 24.4 degrees on the split ball before it).
// The optimisation moved vertices, lowered no smallest angle and was kept.
void expect_well_shaped(const pipeline::ComplexResult& r) {
  const multi::ComplexFigures& f = r.figures;
  EXPECT_GE(f.min_angle_off_junction_deg, 25);
  EXPECT_GE(f.min_angle_deg, 20);
  EXPECT_GE(f.mean_radius_ratio, 0.95);
  EXPECT_GT(r.optimization.moves, 0);
  EXPECT_GE(r.optimization.min_angle_after_deg, r.optimization.min_angle_before_deg);
  EXPECT_FALSE(r.optimization.reverted);
}

// `shells`: the label whose boundary has two pieces (a shell's outside and inside), if any.
void expect_closed_and_uncrossed(const Meshed& m, int64_t shells = 0) {
  const multi::ComplexFigures& f = m.result.figures;
  for (const multi::RegionFigures& r : f.regions) {
    EXPECT_EQ(r.defects, 0) << "label " << r.label;
    EXPECT_EQ(r.pinched_vertices, 0) << "label " << r.label;
    EXPECT_EQ(r.components, r.label == shells ? 2 : 1) << "label " << r.label;
  }
  EXPECT_EQ(f.crossing_pairs, 0);
  EXPECT_EQ(m.truth.foreign_triangles, 0);
  EXPECT_EQ(m.result.specks.merged, 0);  // no piece of a phantom's label is under a tenth of a voxel
  expect_well_shaped(m.result);
}

// Tolerances, once: the interfaces within a fifth of the in-plane voxel on average
// (0.04-0.07 mm measured), every label's volume within 1% of the analytic (0.19-0.30%
// measured, each label held to its voxels' volume; 0.37-1.44% without), the
// normals away from junctions and sharp rims within 2.5 degrees on average on the split
// ball (1.3 measured) and 4.5 on the sectors (3.4; one seam lies nearly along the
// slices). The junction curves' edges within 0.3 mm of the true curves and those within
// 0.3 mm of ours at the 95th percentile on the split ball (0.21 and 0.21 measured, 0.7 mm
// pixels), 0.4 mm on the sectors (0.30 and 0.33, whose seams run into the cylinder's
// rounded rims).
constexpr double kDistanceMean = 0.14, kVolume = 0.01;

// Each region competes within two voxels of its own voxels, along every axis; beyond the
// grid only the background does.
TEST(ComplexRun, RegionSupportReachesTwoVoxels) {
  Volume v;
  v.dims = {20, 10, 10};
  v.spacing = {0.5, 0.5, 2.0};
  v.origin = {10, 0, 0};
  v.voxels.assign(size_t(v.voxel_count()), 0.0f);
  v.voxels[size_t(v.index(5, 5, 5))] = 7;   // label 7: one voxel
  v.voxels[size_t(v.index(15, 5, 5))] = 9;  // label 9, not asked for: background
  const multi::RegionSupport s(v, {7});
  auto at = [&](double i, double j, double k) { return v.index_to_physical({i, j, k}); };
  EXPECT_TRUE(s.allows(1, at(5, 5, 5)));
  EXPECT_TRUE(s.allows(1, at(7, 7, 3)));   // two voxels along each axis
  EXPECT_FALSE(s.allows(1, at(8, 5, 5)));
  EXPECT_FALSE(s.allows(1, at(5, 5, 8)));
  EXPECT_FALSE(s.allows(1, at(15, 5, 5)));
  EXPECT_TRUE(s.allows(0, at(15, 5, 5)));
  EXPECT_TRUE(s.allows(0, at(6, 5, 5)));    // the background's voxels are next to it
  EXPECT_FALSE(s.allows(1, at(-3, 5, 5)));  // beyond the grid
  EXPECT_TRUE(s.allows(0, at(-3, 5, 5)));
}

TEST(ComplexRun, SplitBallSharesItsDiscAndMeetsAlongTheCircle) {
  const Meshed m = mesh_phantom("split ball");
  expect_closed_and_uncrossed(m);
  ASSERT_EQ(m.result.figures.interfaces.size(), 3u);  // (0,1), (0,2), (1,2)
  EXPECT_EQ(m.result.figures.junction_curves, 1);
  EXPECT_LT(m.truth.distance_mean, kDistanceMean);
  EXPECT_LT(m.truth.worst_volume_error, kVolume);
  EXPECT_LT(m.truth.junction_p95, 0.3);
  EXPECT_LT(m.truth.junction_cover_p95, 0.3);
  EXPECT_GT(m.result.sample.junction_particles, 20);
  // Each half's two faces meet at the circle at 90 degrees; within 5 (86.4 and 87.2 measured).
  for (const multi::RegionFigures& r : m.result.figures.regions) EXPECT_NEAR(r.min_wedge_deg, 90, 5) << r.label;
  EXPECT_LT(m.truth.normal_mean_away_deg, 2.5);
  // Every face, next to the circle too: mean within 2 and p95 within 5 degrees (1.34 and
  // 3.65 measured).
  EXPECT_LT(m.truth.normal_mean_deg, 2);
  EXPECT_LT(m.truth.normal_p95_deg, 5);
}

// A ball inside a shell of another label: two interfaces, no junction, the faces' normals
// within 2 degrees on average and 5 at p95 (1.25 and 3.22 measured).
TEST(ComplexRun, NestedBallInItsShell) {
  const Meshed m = mesh_phantom("nested");
  expect_closed_and_uncrossed(m, /*shells=*/2);
  EXPECT_EQ(m.result.figures.interfaces.size(), 2u);  // (0, 2), (1, 2)
  EXPECT_EQ(m.result.figures.junction_edges, 0);
  EXPECT_LT(m.truth.distance_mean, kDistanceMean);
  EXPECT_LT(m.truth.worst_volume_error, kVolume);
  EXPECT_LT(m.truth.normal_mean_deg, 2);
  EXPECT_LT(m.truth.normal_p95_deg, 5);
}

TEST(ComplexRun, SectorsMeetAlongTheAxisSeamsAndRadii) {
  const Meshed m = mesh_phantom("sectors");
  expect_closed_and_uncrossed(m);
  EXPECT_EQ(m.result.figures.interfaces.size(), 6u);
  EXPECT_LT(m.truth.normal_mean_away_deg, 4.5);
  EXPECT_LT(m.truth.distance_mean, kDistanceMean);
  EXPECT_LT(m.truth.worst_volume_error, kVolume);
  EXPECT_LT(m.truth.junction_p95, 0.4);
  EXPECT_LT(m.truth.junction_cover_p95, 0.4);
  // The sectors' faces meet at 90 degrees at least (120 at the axis). The smallest wedge
  // over a label's junction edges depends on where the particles fall (64.7-81.9 degrees
  // over the command line's seeds 1-4, 74.8 here); it stays far above the 15 under which
  // a wedge is trimmed (multi/region_wedges.h).
  for (const multi::RegionFigures& r : m.result.figures.regions) EXPECT_GT(r.min_wedge_deg, 45) << r.label;
}

TEST(ComplexRun, JointAcrossOneSliceSharesNoInterface) {
  const Meshed m = mesh_phantom("joint");
  expect_closed_and_uncrossed(m);
  for (const multi::InterfaceFigures& i : m.result.figures.interfaces) EXPECT_EQ(i.label_a, 0);
  EXPECT_EQ(m.result.figures.junction_edges, 0);
  EXPECT_LT(m.truth.distance_mean, kDistanceMean);
  EXPECT_LT(m.truth.worst_volume_error, kVolume);
}

// A scan's cut plane through a structure: tissue (2) in a slab the grid's first slice
// cuts, a tilted bone rod (1) through it. The cut face is flat, so its particles are as
// sparse as the sampling allows, while the circle where the rod meets it is sampled at
// the rod's spacing: the triangles between the two are needles (2.0 degrees, 152 under
// 10, without the refinement), which the triangulation's refinement grades away.
TEST(ComplexRun, CutPlaneGradesFromItsJunctionCurve) {
  const Volume v = test::label_volume({70, 70, 20}, {0.7, 0.7, 1.5}, [](const Eigen::Vector3d& p) {
    const double x = p.x() - 24.5, y = p.y() - 24.5;
    if (std::hypot(x - 0.2 * p.z(), y - 0.1 * p.z()) < 4) return 1.0f;
    return std::hypot(x, y) < 20 ? 2.0f : 0.0f;
  });
  CpuBackend cpu;
  const pipeline::ComplexResult r = pipeline::run_complex(
      v, {1, 2}, false, pipeline::RunOptions{}, [&]() -> ComputeBackend& { return cpu; }, nullptr,
      [](pipeline::LabelRun&) {});
  for (const multi::RegionFigures& f : r.figures.regions) EXPECT_EQ(f.defects, 0) << "label " << f.label;
  EXPECT_EQ(r.figures.crossing_pairs, 0);
  EXPECT_EQ(r.figures.junction_curves, 2);  // the rod's circles on the cut and on the slab's top
  EXPECT_GT(r.triangulation.refine_points, 0);
  EXPECT_GE(r.figures.min_angle_deg, 20);  // 20.6 measured
}

// Tissue (label 2) one voxel thick or less over a bone ball (label 1), rippled and cut
// off by a tilted plane: where the layer is thinner than the sample's spacing, its two
// faces touch at vertices at first (the layer pinched to a point); the repair samples it
// until every label's boundary is one disc at every vertex.
TEST(ComplexRun, ThinLayerIsSampledUntilManifold) {
  const Volume v = test::label_volume({50, 50, 24}, {0.7, 0.7, 1.5}, [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d q = p - Eigen::Vector3d(17.5, 17.5, 18);
    const double d = q.norm();
    if (d < 9) return 1.0f;
    const double layer = 0.7 + 0.6 * std::sin(q.x() * 0.7) * std::sin(q.y() * 0.5);
    return d < 9 + layer && q.z() + 0.3 * q.x() > -2 ? 2.0f : 0.0f;
  });
  CpuBackend cpu;
  const pipeline::ComplexResult r = pipeline::run_complex(
      v, {1, 2}, false, pipeline::RunOptions{}, [&]() -> ComputeBackend& { return cpu; }, nullptr,
      [](pipeline::LabelRun&) {});
  EXPECT_GT(r.triangulation.pinches_found, 0);  // 245 measured
  EXPECT_EQ(r.triangulation.pinches, 0);
  for (const multi::RegionFigures& f : r.figures.regions) {
    EXPECT_EQ(f.defects, 0) << "label " << f.label;
    EXPECT_EQ(f.pinched_vertices, 0) << "label " << f.label;
    EXPECT_GE(f.min_wedge_deg, multi::kMinWedgeDeg) << "label " << f.label;
  }
  EXPECT_EQ(r.figures.crossing_pairs, 0);
}

TEST(ComplexRun, ComplexPlyKeepsItsLabelPairs) {
  const Meshed m = mesh_phantom("nested");
  expect_closed_and_uncrossed(m, 2);
  const std::string path = test::temp_dir("complex") + "/complex.ply";
  write_mesh(m.result.complex.mesh, path);
  const TriangleMesh back = read_mesh(path);
  ASSERT_EQ(back.face_labels.size(), back.triangles.size());
  EXPECT_EQ(back.face_labels, m.result.complex.mesh.face_labels);
  EXPECT_EQ(multi::complex_labels(back), (std::vector<int64_t>{0, 1, 2}));
}

}  // namespace
}  // namespace mpumesh
