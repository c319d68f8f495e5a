// The JSON report of a run (tools/run_json.h): the pipeline called directly writes the
// bytes the command line writes, and what the HTML page shows of a run reads back from
// its JSON report as it was written.
#include <gtest/gtest.h>

#include "cli_support.h"
#include "cpu/cpu_backend.h"
#include "io/mesh_io.h"
#include "io/read_file.h"
#include "option_spelling.h"
#include "pipeline/run_pipeline.h"
#include "run_json.h"
#include "test_support.h"

namespace mpumesh {
namespace {

TEST(RunJson, ThePipelineWritesTheBytesTheCommandLineWrites) {
  const std::string dir = test::temp_dir("pipeline");
  const std::string ball = test::ball_phantom(dir);
  ASSERT_EQ(run("run " + ball + " --threshold 0 --particles 1500 --backend cpu --quiet -o " + dir + "/cli.ply").code, 0);
  CpuBackend cpu;
  const pipeline::RunResult r = pipeline::run_pipeline(ball, test::ball_run_options(), [&]() -> ComputeBackend& { return cpu; });
  write_mesh(r.mesh, dir + "/pipeline.ply");
  EXPECT_EQ(read_file(dir + "/pipeline.ply"), read_file(dir + "/cli.ply"));
}

TEST(RunJson, WhatTheReportShowsReadsBackAsWritten) {
  const std::string dir = test::temp_dir("run_json");
  const std::string ball = test::ball_phantom(dir);
  CpuBackend cpu;
  pipeline::RunOptions o = test::ball_run_options();
  o.spacing_figures = true;
  o.components.largest = 1;
  o.volume_mesh = TetOptions{};
  const pipeline::RunResult r = pipeline::run_pipeline(ball, o, [&]() -> ComputeBackend& { return cpu; });
  const nlohmann::json j = tools::run_json(r, {"m.ply", "m.msh", nullptr, tools::cli_spelling("run")});
  const tools::RunReportRead back = tools::read_run_json(nlohmann::json::parse(j.dump()), "r.json");
  const pipeline::RunResult& b = back.run;
  EXPECT_EQ(b.input.path, r.input.path);
  ASSERT_TRUE(b.input.volume);
  EXPECT_EQ(b.input.volume->dims, r.input.volume->dims);
  EXPECT_DOUBLE_EQ(b.fit.eps, r.fit.eps);
  EXPECT_EQ(b.derived.tolerance.source, r.derived.tolerance.source);
  EXPECT_EQ(b.sample.particles, r.sample.particles);
  EXPECT_EQ(b.sample.off_data, r.sample.off_data);
  ASSERT_TRUE(b.spacing && r.spacing);
  EXPECT_DOUBLE_EQ(b.spacing->curved.rank_correlation, r.spacing->curved.rank_correlation);
  EXPECT_DOUBLE_EQ(b.spacing->all.ratio, r.spacing->all.ratio);
  EXPECT_EQ(b.spacing->curved_particles, r.spacing->curved_particles);
  EXPECT_EQ(b.optimization.rounds, r.optimization.rounds);
  EXPECT_EQ(b.optimization.flips, r.optimization.flips);
  EXPECT_DOUBLE_EQ(b.optimization.after.radius_ratio, r.optimization.after.radius_ratio);
  ASSERT_TRUE(b.components && r.components);
  EXPECT_EQ(b.components->kept, r.components->kept);
  EXPECT_EQ(b.derived.components.largest, 1);
  EXPECT_EQ(b.notes, r.notes);
  ASSERT_TRUE(b.volume && r.volume);
  EXPECT_EQ(b.volume->stats.quality.tets, r.volume->stats.quality.tets);
  EXPECT_EQ(b.volume->stats.quality.dihedral_histogram, r.volume->stats.quality.dihedral_histogram);
  EXPECT_DOUBLE_EQ(b.volume->stats.volume_difference_pct(), r.volume->stats.volume_difference_pct());
}

}  // namespace
}  // namespace mpumesh
