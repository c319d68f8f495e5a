// core/pipeline: the whole job called directly, as `mpumesh run`, the benchmark and the
// Python module call it: its stages in order with their times, what it derives apart
// from what it was asked, a remesh, and its errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "common/error.h"
#include "cpu/cpu_backend.h"
#include "io/mesh_io.h"
#include "io/volume_io.h"
#include "pipeline/run_pipeline.h"
#include "test_support.h"

namespace mpumesh {
namespace {

class Recorder : public pipeline::Observer {
 public:
  std::vector<std::string> stages, notes;
  int open = 0;  // stages still open
  // Per stage, the fractions told while it was the open stage (others: under "outside").
  std::map<std::string, std::vector<double>> fractions;
  void begin(const std::string& stage) override { stages.push_back(stage), ++open; }
  void end() override { --open; }
  void progress(const std::string& stage, double f) override {
    fractions[open == 1 && stage == stages.back() ? stage : "outside " + stage].push_back(f);
  }
  void note(const std::string& line) override { notes.push_back(line); }
};

TEST(Pipeline, RunsItsStagesInOrderAndOpensTheBackendOnce) {
  const std::string dir = test::temp_dir("pipeline_stages");
  const std::string ball = test::ball_phantom(dir);
  CpuBackend cpu;
  int opened = 0;
  Recorder rec;
  pipeline::RunOptions o = test::ball_run_options();
  o.baselines = true;
  const pipeline::RunResult r = pipeline::run_pipeline(
      ball, o,
      [&]() -> ComputeBackend& {
        ++opened;
        EXPECT_EQ(rec.stages, std::vector<std::string>{"read volume"}) << "the input is read first";
        return cpu;
      },
      &rec);
  EXPECT_EQ(opened, 1);
  EXPECT_EQ(rec.open, 0);
  EXPECT_EQ(rec.stages, (std::vector<std::string>{"read volume", "segment", "points", "marching cubes (report)", "fit",
                                                  "particles", "triangulate", "keep components", "optimize",
                                                  "curvature", "quality", "original MPU (report)"}));
  ASSERT_EQ(r.baselines.size(), 2u);
  EXPECT_EQ(r.baselines[0].first, "marching cubes");
  EXPECT_EQ(r.baselines[1].first, "original MPU");
  // The long stages tell how far they are, within themselves, from above 0 to 1.
  std::vector<std::string> told;
  for (const auto& [stage, f] : rec.fractions) {
    told.push_back(stage);
    ASSERT_FALSE(f.empty());
    EXPECT_EQ(f.back(), 1.0) << stage;
    for (double x : f) EXPECT_TRUE(x >= 0 && x <= 1) << stage << " " << x;
  }
  EXPECT_EQ(told, (std::vector<std::string>{"optimize", "particles", "triangulate"}));
  EXPECT_TRUE(std::is_sorted(rec.fractions["particles"].begin(), rec.fractions["particles"].end()));
  ASSERT_TRUE(r.quality);
  EXPECT_TRUE(r.quality->topo.closed);
  EXPECT_FALSE(r.input.mesh);
  ASSERT_TRUE(r.input.volume);
  EXPECT_EQ(r.input.volume->dims, (std::array<int64_t, 3>{30, 28, 12}));
  EXPECT_GT(r.points, 100u);
  // What the run derived, apart from what it was asked: the tolerance from the scan, the
  // voxel size the default count follows.
  EXPECT_EQ(r.derived.fit.eps, r.derived.tolerance.eps) << "no eps given: the tolerance follows the scan";
  EXPECT_EQ(o.fit.eps, 0) << "the options stay as given";
  EXPECT_FALSE(r.derived.eps_given);
  EXPECT_GT(r.derived.sample_source.voxel_size, 0);
  EXPECT_EQ(r.mesh.curvature.size(), r.mesh.vertices.size());
  // Each stage's time, in the order run.
  ASSERT_EQ(r.stage_seconds.size(), rec.stages.size());
  for (size_t k = 0; k < rec.stages.size(); ++k) {
    EXPECT_EQ(r.stage_seconds[k].first, rec.stages[k]);
    EXPECT_GE(r.stage_seconds[k].second, 0);
  }
}

TEST(Pipeline, RemeshesAClosedMeshAndRefusesAnOpenOne) {
  const std::string dir = test::temp_dir("pipeline_mesh");
  write_mesh(test::icosphere(10.0, 4), dir + "/ball.stl");
  CpuBackend cpu;
  pipeline::RunOptions o;
  o.sample.spacing = 1.5;
  o.quality.reset();
  const pipeline::RunResult r = pipeline::run_pipeline(dir + "/ball.stl", o, [&]() -> ComputeBackend& { return cpu; });
  ASSERT_TRUE(r.input.mesh);
  EXPECT_FALSE(r.input.volume);
  EXPECT_EQ(r.input.mesh->triangles, 20u * 256u);
  EXPECT_FALSE(r.quality);
  EXPECT_GT(r.mesh.triangles.size(), 500u);

  TriangleMesh open = test::icosphere(10.0, 2);
  open.triangles.pop_back();
  write_mesh(open, dir + "/open.stl");
  bool opened = false;
  try {
    pipeline::run_pipeline(dir + "/open.stl", o, [&]() -> ComputeBackend& {
      opened = true;
      return cpu;
    });
    ADD_FAILURE() << "an open mesh was remeshed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("open.stl: the input mesh is not a closed manifold (3 border edges"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(opened) << "the backend is opened only for a usable input";
}

TEST(Pipeline, NamesTheVolumeWhenItHoldsNoSurface) {
  const std::string dir = test::temp_dir("pipeline_empty");
  const std::string ball = test::ball_phantom(dir);
  CpuBackend cpu;
  pipeline::RunOptions o = test::ball_run_options();
  o.segment.threshold = {5000};  // nothing is that bright
  EXPECT_THROW(
      {
        try {
          pipeline::run_pipeline(ball, o, [&]() -> ComputeBackend& { return cpu; });
        } catch (const InputError& e) {
          EXPECT_NE(std::string(e.what()).find(ball), std::string::npos) << e.what();
          throw;
        }
      },
      InputError);
}

TEST(Pipeline, SaysSoWhenOnlySpecksAreFound) {
  // The ball counted as a speck (a bound of a million voxels): dropped with the rest, and the
  // run says why, not that --min-volume (not given) dropped it.
  const std::string dir = test::temp_dir("pipeline_specks");
  const std::string ball = test::ball_phantom(dir);
  CpuBackend cpu;
  pipeline::RunOptions o = test::ball_run_options();
  o.speck_voxels = 1e6;
  try {
    pipeline::run_pipeline(ball, o, [&]() -> ComputeBackend& { return cpu; });
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(ball + ": every structure is a speck"), std::string::npos) << what;
    // Core names the option by its stable name (common/option_names.h), which the command
    // line and the Python module spell their own ways (tests/tools/test_option_spelling.cpp).
    EXPECT_NE(what.find("(`keep_specks` keeps them)"), std::string::npos) << what;
  }
  o.speck_voxels = 0;  // kept
  EXPECT_GT(pipeline::run_pipeline(ball, o, [&]() -> ComputeBackend& { return cpu; }).mesh.triangles.size(), 1000u);
}

}  // namespace
}  // namespace mpumesh
