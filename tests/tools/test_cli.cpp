// The mpumesh program as a user runs it: exit codes, one-line errors naming the file and
// the problem, no output left behind by a failed run, --help everywhere, JSON output.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "io/mesh_io.h"
#include "io/point_io.h"
#include "io/read_file.h"
#include "io/volume_io.h"
#include "test_support.h"

namespace mpumesh {
namespace {

struct Result {
  int code = -1;
  std::string out;  // stdout and stderr
};

Result run(const std::string& args) {
  Result r;
  const std::string cmd = std::string(MPUMESH_BIN) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string phantom(const std::string& dir) {
  const std::string p = dir + "/ball.mha";
  write_volume(test::sphere_volume({30, 28, 12}, {0.6, 0.6, 2.0}, {9, 8, 12}, 6.0), p);
  return p;
}

TEST(Cli, HelpForEverySubcommand) {
  for (const char* sub : {"", "run", "segment", "points", "mc", "quality", "convert", "devices"}) {
    const Result r = run(std::string(sub) + " --help");
    EXPECT_EQ(r.code, 0) << sub;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << sub;
  }
  EXPECT_NE(run("").code, 0);
  EXPECT_NE(run("mc").code, 0);  // missing arguments
}

TEST(Cli, McWritesAClosedMeshAndJson) {
  const std::string dir = test::temp_dir("mc");
  const Result r = run("mc " + phantom(dir) + " --threshold 0 -o " + dir + "/ball.stl --backend cpu --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["closed"].get<bool>());
  EXPECT_TRUE(j["manifold"].get<bool>());
  EXPECT_EQ(j["components"], 1);
  EXPECT_EQ(j["backend"]["kind"], "cpu");
  EXPECT_EQ(read_mesh(dir + "/ball.stl").triangles.size(), j["triangles"].get<size_t>());
  const Result q = run("quality " + dir + "/ball.stl --json");
  ASSERT_EQ(q.code, 0) << q.out;
  const auto qj = nlohmann::json::parse(q.out);
  EXPECT_EQ(qj["genus"], 0);
  EXPECT_EQ(qj["self_intersections"], 0);
  EXPECT_GT(qj["volume_mm3"].get<double>(), 0);
}

TEST(Cli, RunWritesMeshAndReport) {
  const std::string dir = test::temp_dir("run");
  const Result r = run("run " + phantom(dir) + " --threshold 0 -o " + dir + "/m.ply --report " + dir +
                       "/report.json --backend auto --quiet");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(read_file(dir + "/report.json"));
  EXPECT_TRUE(j["quality"]["closed"].get<bool>());
  EXPECT_TRUE(j["stage_seconds"].contains("marching cubes"));
  EXPECT_FALSE(j["backend"]["device"].get<std::string>().empty());
}

TEST(Cli, ErrorsNameTheFileAndLeaveNothing) {
  const std::string dir = test::temp_dir("errors");
  const std::string ball = phantom(dir);
  auto expect_fail = [&](const std::string& args, const std::string& words) {
    const Result r = run(args);
    EXPECT_EQ(r.code, 1) << args << "\n" << r.out;
    EXPECT_NE(r.out.find("mpumesh: error:"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(words), std::string::npos) << "want '" << words << "' in: " << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir + "/out.ply")) << args;
    for (auto& e : std::filesystem::directory_iterator(dir))
      EXPECT_EQ(e.path().filename().string().find(".partial"), std::string::npos) << e.path();
  };
  expect_fail("mc " + dir + "/missing.nii -o " + dir + "/out.ply", "missing.nii: file or directory not found");
  expect_fail("mc " + ball + " --threshold 5000 -o " + dir + "/out.ply --backend cpu", "selects no voxel");
  expect_fail("mc " + ball + " --threshold 5000:10 -o " + dir + "/out.ply", "LO is above HI");
  expect_fail("mc " + ball + " -o " + dir + "/nodir/out.ply", "does not exist");
  expect_fail("mc " + ball + " -o " + dir + "/out.vtk", "unknown mesh format");
  expect_fail("quality " + dir + "/missing.ply", "missing.ply");
  {
    std::ofstream(dir + "/junk.nii") << "definitely not nifti";
  }
  expect_fail("mc " + dir + "/junk.nii -o " + dir + "/out.ply", "junk.nii");
  // A failed run does not replace a good file.
  ASSERT_EQ(run("mc " + ball + " --threshold 0 -o " + dir + "/good.ply --quiet").code, 0);
  const std::string before = read_file(dir + "/good.ply");
  EXPECT_EQ(run("mc " + ball + " --threshold 9000 -o " + dir + "/good.ply --quiet").code, 1);
  EXPECT_EQ(read_file(dir + "/good.ply"), before);
}

TEST(Cli, SegmentWritesAMaskWithTheInputGeometry) {
  const std::string dir = test::temp_dir("segment");
  test::ShellPhantom ph;
  ph.radii = {8, 7, 6};
  ph.noise_hu = 60;
  write_volume(ph.volume(), dir + "/shell.nrrd");
  for (const char* method : {"threshold", "chan-vese"}) {
    const std::string out = dir + "/" + method + ".nii.gz";
    const Result r = run("segment " + dir + "/shell.nrrd -o " + out + " --method " + method + " --backend cpu --json");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["method"], method);
    EXPECT_GT(j["components_threshold"].get<int>(), 1) << "the noise should leave specks at 226 HU";
    if (std::string(method) == "chan-vese") EXPECT_EQ(j["components"], 1);
    const Volume in = read_volume(dir + "/shell.nrrd"), mask = read_volume(out);
    EXPECT_EQ(mask.dims, in.dims);
    EXPECT_LT((mask.spacing - in.spacing).norm(), 1e-6);
    EXPECT_LT((mask.origin - in.origin).norm(), 1e-4);
    int64_t inside = 0;
    for (float v : mask.voxels) {
      ASSERT_TRUE(v == 0.0f || v == 1.0f);
      inside += v == 1.0f;
    }
    EXPECT_EQ(inside, j["inside_voxels"].get<int64_t>());
  }
  // --threshold alone means the threshold method.
  const Result r = run("segment " + dir + "/shell.nrrd -o " + dir + "/t.mha --threshold 500 --backend cpu --json");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(nlohmann::json::parse(r.out)["method"], "threshold");
}

TEST(Cli, PointsWritesOrientedPointsAndASummary) {
  const std::string dir = test::temp_dir("points");
  test::ShellPhantom ph;
  ph.radii = {8, 7, 6};
  write_volume(ph.volume(), dir + "/shell.nii.gz");
  const Result r = run("points " + dir + "/shell.nii.gz -o " + dir + "/p.ply --threshold 500 --backend cpu --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  const auto cloud = read_point_cloud(dir + "/p.ply");
  EXPECT_EQ(cloud.size(), j["points"]["points"].get<size_t>());
  EXPECT_GT(j["points"]["cap_points"].get<int>(), 0);
  EXPECT_TRUE(j["stage_seconds"].contains("points"));
  EXPECT_TRUE(j["backend"].contains("device"));
  for (size_t i = 0; i < cloud.size(); ++i) {
    Eigen::Vector3d n;
    EXPECT_LT(ph.distance(cloud.positions[i], &n), 1.2);  // within a cap's half slice and a pixel
    EXPECT_GT(cloud.normals[i].dot(n), 0.5) << i;
  }
}

TEST(Cli, SegmentationErrorsNameTheProblem) {
  const std::string dir = test::temp_dir("segment_errors");
  const std::string ball = phantom(dir);
  auto expect_fail = [&](const std::string& args, const std::string& words) {
    const Result r = run(args);
    EXPECT_EQ(r.code, 1) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(words), std::string::npos) << "want '" << words << "' in: " << r.out;
    for (auto& e : std::filesystem::directory_iterator(dir))
      EXPECT_EQ(e.path().filename().string(), "ball.mha") << "left behind: " << e.path();
  };
  expect_fail("segment " + ball + " -o " + dir + "/m.nii --window 5:1", "--window");
  expect_fail("segment " + ball + " -o " + dir + "/m.nii --dt 0", "--dt");
  expect_fail("segment " + ball + " -o " + dir + "/m.nii --threshold 5000", "no voxel");
  expect_fail("segment " + ball + " -o " + dir + "/m.vtk", "m.vtk");
  expect_fail("points " + ball + " -o " + dir + "/p.obj", "p.obj");
}

TEST(Cli, GpuBackendAndDevices) {
  MPUMESH_VULKAN_OR_SKIP(gpu);
  const Result d = run("devices --json");
  ASSERT_EQ(d.code, 0) << d.out;
  EXPECT_FALSE(nlohmann::json::parse(d.out)["devices"].empty());
  const std::string dir = test::temp_dir("gpu");
  const Result r = run("mc " + phantom(dir) + " --threshold 0 -o " + dir + "/g.off --backend gpu --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["backend"]["kind"], "vulkan");
  EXPECT_TRUE(j["kernel_ms"].contains("mc_classify"));
  EXPECT_TRUE(j["manifold"].get<bool>());
}

}  // namespace
}  // namespace mpumesh
