// A surface mesh of several closed parts remeshed as one complex
// (core/pipeline/complex_run.h run_parts_complex), on the parts phantom
// (core/phantom/parts_phantom.h): five parts out, each closed as one piece, the two that
// share a disc sharing one interface, the parts a fifth of an edge apart staying apart,
// no crossing triangle pair, each part's volume and the surface's distance to the input.
#include <gtest/gtest.h>

#include <cmath>

#include "common/error.h"
#include "cpu/cpu_backend.h"
#include "mesh/cgal_geometry.h"
#include "mesh/topology.h"
#include "multi/complex_figures.h"
#include "multi/material_field.h"
#include "phantom/parts_phantom.h"
#include "phantom/truth_figures.h"
#include "pipeline/complex_run.h"
#include "test_support.h"

namespace mpumesh {
namespace {

pipeline::ComplexResult remesh_parts(const TriangleMesh& mesh, int64_t particles) {
  CpuBackend cpu;
  pipeline::RunOptions options;
  options.sample.particles = particles;
  options.quality.reset();
  return pipeline::run_parts_complex(mesh, "parts.ply", options, [&]() -> ComputeBackend& { return cpu; }, nullptr);
}

// Tolerances, once: each part's volume within 1% of the input part's (0.01-0.1%
// measured at 40,000 particles, 0.8% for the smallest at 12,000); the surface within a
// twentieth of the input's edge of the input on average (0.005 mm measured) and within
// 0.1 edges at the 99th percentile (0.025 mm; the input's facets are chords of the smooth
// parts, 0.01-0.04 mm inside them); within 0.03 and 0.08 edges of the smooth parts (0.016
// and 0.049 mm); the junction circle's length within 3% of the true rim's.
constexpr double kVolume = 0.01, kMeanDistance = 0.05, kP99Distance = 0.1, kTruthMean = 0.03, kTruthP99 = 0.08,
                 kJunctionLength = 0.03;

TEST(PartsComplex, FivePartsStayFiveTheTouchingPairSharesItsDiscTheOthersStayApart) {
  const double edge = 1.0;
  const phantom::PartsPhantom p = phantom::parts_phantom(edge, 0.2 * edge);
  const pipeline::ComplexResult r = remesh_parts(p.mesh, 12000);
  ASSERT_EQ(r.regions.size(), 5u);
  EXPECT_TRUE(r.from_mesh);
  EXPECT_EQ(r.shells_removed, 0);
  const multi::ComplexFigures& f = r.figures;
  ASSERT_EQ(f.regions.size(), 5u);
  for (const multi::RegionFigures& g : f.regions) {
    EXPECT_EQ(g.defects, 0) << "part " << g.label;
    EXPECT_EQ(g.pinched_vertices, 0) << "part " << g.label;
    EXPECT_EQ(g.components, 1) << "part " << g.label;
    const double want = p.part_volumes[size_t(g.label - 1)];
    EXPECT_NEAR(g.volume_mm3, want, kVolume * want) << "part " << g.label;
    EXPECT_NEAR(r.regions[size_t(g.label - 1)].reference_volume_mm3, want, 1e-9 * want);
  }
  std::vector<std::pair<int64_t, int64_t>> pairs;
  for (const multi::InterfaceFigures& i : f.interfaces) pairs.push_back({i.label_a, i.label_b});
  const std::vector<std::pair<int64_t, int64_t>> want = {{0, 1}, {0, 2}, {0, 3}, {0, 4}, {0, 5}, {1, 2}};
  EXPECT_EQ(pairs, want) << "only the touching pair shares an interface";
  EXPECT_EQ(f.crossing_pairs, 0);
  EXPECT_EQ(f.junction_curves, 1);
  const double rim = 2 * M_PI * std::sqrt(100 - 2.5 * 2.5);
  EXPECT_NEAR(f.junction_length_mm, rim, kJunctionLength * rim);
  const DistanceSamples d = sample_distances(r.complex.mesh, p.mesh);
  double mean = 0, area = 0;
  for (size_t k = 0; k < d.distance.size(); ++k) mean += d.distance[k] * d.weight[k], area += d.weight[k];
  EXPECT_LT(mean / area, kMeanDistance * edge);
  EXPECT_LT(phantom::weighted_quantile(d.distance, d.weight, 0.99), kP99Distance * edge);
  const phantom::PartsPhantom::Distances truth = p.distance_to_truth(r.complex.mesh);
  EXPECT_LT(truth.mean, kTruthMean * edge);
  EXPECT_LT(truth.p99, kTruthP99 * edge);
}

TEST(PartsComplex, ARemeshKeepsAtMostAsManyShellsAsItsInputHasParts) {
  TriangleMesh two = test::icosphere(5, 3);
  const TriangleMesh other = test::icosphere(3, 3);
  const uint32_t base = uint32_t(two.vertices.size());
  for (const auto& v : other.vertices) two.vertices.push_back(v + Eigen::Vector3d(20, 0, 0));
  for (const auto& t : other.triangles) two.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  CpuBackend cpu;
  pipeline::RunOptions options;
  options.sample.particles = 3000;
  const pipeline::RunResult r =
      pipeline::run_pipeline(two, "two.ply", options, [&]() -> ComputeBackend& { return cpu; }, nullptr);
  ASSERT_TRUE(r.input.mesh);
  EXPECT_EQ(r.input.mesh->parts, 2);
  EXPECT_EQ(r.derived.components.largest, 2);
  EXPECT_EQ(analyze_topology(r.mesh).components, 2);
}

TEST(PartsComplex, APartTooSmallToFitIsSkippedWithItsReason) {
  phantom::PartsPhantom p = phantom::parts_phantom();
  TriangleMesh speck;  // a tetrahedron: 4 vertices and 4 centroids, too few points to fit
  speck.vertices = {{0, 0, 0}, {0.5, 0, 0}, {0, 0.5, 0}, {0, 0, 0.5}};
  speck.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const uint32_t base = uint32_t(p.mesh.vertices.size());
  for (const auto& v : speck.vertices) p.mesh.vertices.push_back(v + Eigen::Vector3d(0, 0, 40));
  for (const auto& t : speck.triangles) p.mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  const pipeline::ComplexResult r = remesh_parts(p.mesh, 6000);
  ASSERT_EQ(r.labels.skipped.size(), 1u);
  EXPECT_EQ(r.labels.skipped[0].label, 6) << "the speck is the smallest part";
  EXPECT_NE(r.labels.skipped[0].reason.find("fit"), std::string::npos) << r.labels.skipped[0].reason;
  EXPECT_EQ(r.labels.meshed.size(), 5u);
  EXPECT_EQ(r.figures.regions.size(), 5u);
  EXPECT_EQ(r.figures.crossing_pairs, 0);
}

TEST(PartsComplex, AOnePartMeshIsNoComplex) {
  EXPECT_THROW(remesh_parts(test::icosphere(5, 3), 2000), InputError);
}

}  // namespace
}  // namespace mpumesh
