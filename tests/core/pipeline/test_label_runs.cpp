// --labels in core (core/pipeline/label_runs.h): which labels are meshed, and a run of
// every label of a small map: each closed, the later one kept out of the earlier, the
// crossings counted, a label too small skipped with its reason.
#include <gtest/gtest.h>

#include "common/error.h"
#include "cpu/cpu_backend.h"
#include "mesh/cgal_geometry.h"
#include "mesh/topology.h"
#include "pipeline/label_runs.h"
#include "segment/label_map.h"
#include "test_support.h"

namespace mpumesh {
namespace {

TEST(LabelRuns, AllLabelsOrThoseNamedWhenPresentAndLargeEnough) {
  const std::map<int64_t, int64_t> counts = {{1, 500}, {3, 2}, {7, 900}};
  EXPECT_EQ(pipeline::labels_to_mesh("map.nii", {}, counts), (std::vector<int64_t>{1, 3, 7}));
  EXPECT_EQ(pipeline::labels_to_mesh("map.nii", {7, 1}, counts), (std::vector<int64_t>{7, 1}));
  auto message = [&](const std::vector<int64_t>& named, const std::map<int64_t, int64_t>& c) {
    try {
      pipeline::labels_to_mesh("map.nii", named, c);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message({5}, counts).find("map.nii: no voxel holds label 5 (the labels present: 1, 3, 7)"),
            std::string::npos);
  EXPECT_NE(message({3}, counts).find("map.nii (label 3)"), std::string::npos);
  EXPECT_NE(message({}, {}).find("holds no label"), std::string::npos);
}

TEST(LabelRuns, EveryLabelClosedTheLaterKeptOutOfTheEarlier) {
  const Volume map = test::LabelPhantom{}.volume();
  CpuBackend cpu;
  pipeline::RunOptions base;
  base.sample.particles = 1500;
  std::vector<int64_t> done;
  std::vector<TriangleMesh> meshes;
  const pipeline::LabelsResult r = pipeline::run_labels(
      map, {1, 2, 4}, true, base, [&]() -> ComputeBackend& { return cpu; }, nullptr, [&](pipeline::LabelRun& run) {
        done.push_back(run.label);
        meshes.push_back(run.result.mesh);
        EXPECT_EQ(run.separation.has_value(), run.label == 2) << run.label;  // 2 touches 1
      });
  EXPECT_EQ(done, (std::vector<int64_t>{1, 2}));
  EXPECT_EQ(r.meshed, done);
  ASSERT_EQ(r.skipped.size(), 1u);
  EXPECT_EQ(r.skipped[0].label, 4);
  EXPECT_NE(r.skipped[0].reason.find("too small"), std::string::npos) << r.skipped[0].reason;
  ASSERT_EQ(r.crossings.size(), 1u);
  EXPECT_EQ(r.crossings[0].a, 1);
  EXPECT_EQ(r.crossings[0].b, 2);
  EXPECT_EQ(r.crossings[0].triangle_pairs, count_crossings(meshes[0], meshes[1]));
  EXPECT_EQ(r.crossings[0].triangle_pairs, 0);
  for (const TriangleMesh& m : meshes) EXPECT_TRUE(analyze_topology(m).oriented);
  // Named rather than all, a failure is the run's.
  EXPECT_THROW(pipeline::run_labels(map, {4}, false, base, [&]() -> ComputeBackend& { return cpu; }, nullptr,
                                    [](pipeline::LabelRun&) {}),
               InputError);
}

}  // namespace
}  // namespace mpumesh
