// The mpumesh program as a user runs it: exit codes, one-line errors naming the file and
// the problem, no output left behind by a failed run, --help everywhere, JSON output.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <nlohmann/json.hpp>

#include "io/mesh_io.h"
#include "io/point_io.h"
#include "io/read_file.h"
#include "io/volume_io.h"
#include "mesh/topology.h"
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

// A run that must fail: exit 1, one "mpumesh: error:" line containing `words`, `out` not
// created, and no temporary (.partial) file left beside it.
void expect_failure(const std::string& args, const std::string& words, const std::string& out) {
  const Result r = run(args);
  EXPECT_EQ(r.code, 1) << args << "\n" << r.out;
  EXPECT_NE(r.out.find("mpumesh: error:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(words), std::string::npos) << "want '" << words << "' in: " << r.out;
  EXPECT_FALSE(std::filesystem::exists(out)) << args;
  const auto dir = std::filesystem::path(out).parent_path();
  if (std::filesystem::is_directory(dir))
    for (auto& e : std::filesystem::directory_iterator(dir))
      EXPECT_EQ(e.path().filename().string().find(".partial"), std::string::npos) << e.path();
}

TEST(Cli, HelpForEverySubcommand) {
  for (const char* sub : {"", "run", "segment", "points", "fit", "eval", "polygonize", "mc", "quality", "convert",
                          "devices"}) {
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
  const Result r = run("run " + phantom(dir) + " --threshold 0 --particles 1500 -o " + dir + "/m.ply --report " + dir +
                       "/report.json --backend auto --quiet");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(read_file(dir + "/report.json"));
  EXPECT_TRUE(j["quality"]["closed"].get<bool>());
  EXPECT_TRUE(j["quality"]["oriented"].get<bool>());
  for (const char* stage : {"read volume", "segment", "points", "fit", "particles", "triangulate", "write mesh"})
    EXPECT_TRUE(j["stage_seconds"].contains(stage)) << stage;
  EXPECT_NEAR(j["particles"]["particles"].get<double>(), 1500, 300);
  EXPECT_EQ(j["triangles"].get<int64_t>(), read_mesh(dir + "/m.ply").triangles.size());
  EXPECT_FALSE(j["backend"]["device"].get<std::string>().empty());
}

// The whole job on the real head CT (bone at 226 HU): a closed, oriented manifold without
// self-intersections, every stage timed.
TEST(Cli, RunOnTheSampleCt) {
  MPUMESH_SAMPLE_CT_OR_SKIP(ct);
  const std::string dir = test::temp_dir("run-ct");
  const Result r = run("run " + ct + " --threshold 226 --particles 20000 -o " + dir + "/skull.ply --report " + dir +
                       "/report.json --backend auto --quiet");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(read_file(dir + "/report.json"));
  const auto& q = j["quality"];
  EXPECT_TRUE(q["closed"].get<bool>());
  EXPECT_TRUE(q["oriented"].get<bool>());
  EXPECT_EQ(q["self_intersections"].get<int64_t>(), 0);
  EXPECT_GT(j["triangles"].get<int64_t>(), 30000);
  EXPECT_GT(q["components"].get<int64_t>(), 10);  // the skull's separate bones
  const auto& tr = j["triangulation"];
  EXPECT_EQ(j["particles"]["particles"].get<int64_t>() + tr["repair_points"].get<int64_t>() -
                tr["unused_particles"].get<int64_t>() - tr["edge_collapses"].get<int64_t>(),
            j["vertices"].get<int64_t>());
}

// Remeshing: a marching-cubes-like mesh of a sphere (an icosphere) in, an adaptive closed
// mesh on the same sphere out; and the same job through sample + triangulate.
TEST(Cli, RunRemeshesASurfaceMesh) {
  const std::string dir = test::temp_dir("remesh");
  write_mesh(test::icosphere(10.0, 5), dir + "/in.stl");
  const Result r = run("run " + dir + "/in.stl --spacing 1.0 -o " + dir + "/out.off --report " + dir +
                       "/r.json --backend cpu --quiet");
  ASSERT_EQ(r.code, 0) << r.out;
  const TriangleMesh m = read_mesh(dir + "/out.off");
  const Topology t = analyze_topology(m);
  EXPECT_TRUE(t.closed);
  EXPECT_TRUE(t.oriented);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.genus, 0);
  double worst = 0;
  for (const auto& v : m.vertices) worst = std::max(worst, std::abs(v.norm() - 10.0));
  EXPECT_LT(worst, 0.02);  // the icosphere's own chords deviate up to 0.005 mm
  const auto j = nlohmann::json::parse(read_file(dir + "/r.json"));
  EXPECT_EQ(j["input"]["kind"], "mesh");
  EXPECT_GT(j["quality"]["volume_mm3"].get<double>(), 0);

  ASSERT_EQ(run("points " + phantom(dir) + " --threshold 0 -o " + dir + "/p.ply --quiet").code, 0);
  ASSERT_EQ(run("fit " + dir + "/p.ply -o " + dir + "/s.mpu --quiet").code, 0);
  ASSERT_EQ(run("sample " + dir + "/s.mpu --points " + dir + "/p.ply --particles 800 -o " + dir +
                "/particles.ply --backend cpu --quiet").code, 0);
  const Result tr = run("triangulate " + dir + "/s.mpu " + dir + "/particles.ply -o " + dir + "/t.ply --json");
  ASSERT_EQ(tr.code, 0) << tr.out;
  const auto tj = nlohmann::json::parse(tr.out);
  EXPECT_TRUE(tj["closed"].get<bool>());
  EXPECT_TRUE(tj["oriented_manifold"].get<bool>());
  EXPECT_EQ(tj["particles"].get<int64_t>(), read_point_cloud(dir + "/particles.ply").size());
  // Without --points the particles are seeded from the surface's own leaf centres.
  const Result sr = run("sample " + dir + "/s.mpu --particles 800 -o " + dir + "/p2.xyz --backend cpu --json");
  ASSERT_EQ(sr.code, 0) << sr.out;
  const auto sj = nlohmann::json::parse(sr.out);
  EXPECT_NEAR(sj["particles"].get<double>(), 800, 200);
  EXPECT_EQ(sj["particles"].get<int64_t>(), read_point_cloud(dir + "/p2.xyz").size());
  // Absurd parameters and missing inputs fail before any work, leaving nothing.
  expect_failure("sample " + dir + "/s.mpu --particles -5 -o " + dir + "/bad.ply", "--particles must be",
                 dir + "/bad.ply");
  expect_failure("run " + dir + "/in.stl --curvature-scale 9 -o " + dir + "/bad.ply", "--curvature-scale must be",
                 dir + "/bad.ply");
  expect_failure("triangulate " + dir + "/s.mpu " + dir + "/missing.ply -o " + dir + "/bad.ply", "missing.ply",
                 dir + "/bad.ply");
}

TEST(Cli, ErrorsNameTheFileAndLeaveNothing) {
  const std::string dir = test::temp_dir("errors");
  const std::string ball = phantom(dir);
  auto expect_fail = [&](const std::string& args, const std::string& words) {
    expect_failure(args, words, dir + "/out.ply");
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
    expect_failure(args, words, dir + "/no-output");
    for (auto& e : std::filesystem::directory_iterator(dir))
      EXPECT_EQ(e.path().filename().string(), "ball.mha") << "left behind: " << e.path();
  };
  expect_fail("segment " + ball + " -o " + dir + "/m.nii --window 5:1", "--window");
  expect_fail("segment " + ball + " -o " + dir + "/m.nii --dt 0", "--dt");
  expect_fail("segment " + ball + " -o " + dir + "/m.nii --threshold 5000", "no voxel");
  expect_fail("segment " + ball + " -o " + dir + "/m.vtk", "m.vtk");
  expect_fail("points " + ball + " -o " + dir + "/p.obj", "p.obj");
}

// fit -> eval -> polygonize on a sphere of radius 10 mm sampled as a slice stack.
TEST(Cli, FitEvalAndPolygonizeASphere) {
  const std::string dir = test::temp_dir("mpu");
  const test::AnalyticShape sphere{test::AnalyticShape::kSphere, 10, 10, 10};
  write_point_cloud(test::sample_shape(sphere, 0.5, 1.0, false), dir + "/p.ply");
  const Result f = run("fit " + dir + "/p.ply -o " + dir + "/s.mpu --json");
  ASSERT_EQ(f.code, 0) << f.out;
  const auto fj = nlohmann::json::parse(f.out);
  EXPECT_GT(fj["leaves"].get<int>(), 8);
  EXPECT_EQ(fj["local_fit"], "orthopoly");
  {
    std::ofstream q(dir + "/q.xyz");
    q << "# x y z\n10 0 0\n0 0 -10\n0 0 0\n0 0 10.5 0 0 1\n0 0 40\n";
  }
  const Result e = run("eval " + dir + "/s.mpu " + dir + "/q.xyz --backend cpu -o " + dir + "/e.txt");
  ASSERT_EQ(e.code, 0) << e.out;
  std::istringstream in(read_file(dir + "/e.txt"));
  std::vector<std::array<double, 11>> rows;
  std::array<double, 11> row;
  while (in >> row[0]) {
    for (int k = 1; k < 11; ++k) in >> row[size_t(k)];
    rows.push_back(row);
  }
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_NEAR(rows[0][3], 0.0, 0.01);   // on the surface
  EXPECT_GT(rows[0][4], 0.9);           // gradient along +x
  EXPECT_NEAR(rows[0][5] / rows[0][4], 0.0, 0.01);
  EXPECT_NEAR(rows[0][6] / rows[0][4], 0.0, 0.01);
  EXPECT_NEAR(rows[0][9], 0.01, 5e-4);  // K = 1/r²
  EXPECT_NEAR(rows[0][10], -0.1, 5e-3); // mean curvature -1/r (outward normal convention)
  EXPECT_NEAR(rows[1][3], 0.0, 0.01);
  EXPECT_LT(rows[2][3], -5.0);          // the centre is inside
  EXPECT_NEAR(rows[3][3], 0.5, 0.1);    // 0.5 mm outside; the extra columns are ignored
  EXPECT_GT(rows[4][3], 20.0);          // beyond the bounding cube: f = the cube's size
  // The same through stdout, and on the GPU when there is one.
  const Result e2 = run("eval " + dir + "/s.mpu " + dir + "/q.xyz --backend cpu");
  EXPECT_EQ(e2.out, read_file(dir + "/e.txt"));
  const Result p = run("polygonize " + dir + "/s.mpu -o " + dir + "/m.ply --cell 0.5 --backend cpu --json");
  ASSERT_EQ(p.code, 0) << p.out;
  const TriangleMesh m = read_mesh(dir + "/m.ply");
  EXPECT_EQ(m.triangles.size(), nlohmann::json::parse(p.out)["triangles"].get<size_t>());
  const Result q = run("quality " + dir + "/m.ply --json");
  ASSERT_EQ(q.code, 0) << q.out;
  const auto qj = nlohmann::json::parse(q.out);
  EXPECT_TRUE(qj["closed"].get<bool>());
  EXPECT_EQ(qj["genus"], 0);
  EXPECT_NEAR(qj["volume_mm3"].get<double>(), 4.0 / 3.0 * M_PI * 1000, 0.01 * 4.0 / 3.0 * M_PI * 1000);
  for (const auto& v : m.vertices) EXPECT_NEAR(v.norm(), 10.0, 0.05);
}

TEST(Cli, MpuErrorsNameTheFileAndLeaveNothing) {
  const std::string dir = test::temp_dir("mpu_errors");
  {
    std::ofstream(dir + "/few.xyz") << "0 0 0 0 0 1\n1 0 0 0 0 1\n";
    std::ofstream(dir + "/bad.mpu") << "not an mpu file at all";
    std::ofstream(dir + "/q.xyz") << "1 2\n";
  }
  expect_failure("fit " + dir + "/few.xyz -o " + dir + "/s.mpu", "fewer than --nmin", dir + "/s.mpu");
  expect_failure("fit " + dir + "/missing.ply -o " + dir + "/s.mpu", "missing.ply", dir + "/s.mpu");
  expect_failure("fit " + dir + "/few.xyz -o " + dir + "/s.mpu --alpha 0", "alpha", dir + "/s.mpu");
  expect_failure("polygonize " + dir + "/bad.mpu -o " + dir + "/m.ply", "bad.mpu: not a valid .mpu file", dir + "/m.ply");
  expect_failure("eval " + dir + "/bad.mpu " + dir + "/q.xyz -o " + dir + "/e.txt", "bad.mpu", dir + "/e.txt");
  const test::AnalyticShape sphere{test::AnalyticShape::kSphere, 5, 5, 5};
  write_point_cloud(test::sample_shape(sphere, 0.5, 1.0, false), dir + "/p.ply");
  ASSERT_EQ(run("fit " + dir + "/p.ply -o " + dir + "/s.mpu -q").code, 0);
  expect_failure("eval " + dir + "/s.mpu " + dir + "/q.xyz -o " + dir + "/e.txt", "q.xyz: line 1", dir + "/e.txt");
  expect_failure("polygonize " + dir + "/s.mpu -o " + dir + "/m.ply --cell 0.0001", "limit 2^30", dir + "/m.ply");
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
  // eval on the GPU agrees with the CPU to float precision.
  const test::AnalyticShape sphere{test::AnalyticShape::kSphere, 6, 6, 6};
  write_point_cloud(test::sample_shape(sphere, 0.5, 1.0, false), dir + "/p.xyz");
  ASSERT_EQ(run("fit " + dir + "/p.xyz -o " + dir + "/s.mpu -q").code, 0);
  const Result c = run("eval " + dir + "/s.mpu " + dir + "/p.xyz --backend cpu");
  const Result g = run("eval " + dir + "/s.mpu " + dir + "/p.xyz --backend gpu");
  ASSERT_EQ(g.code, 0) << g.out;
  std::istringstream ci(c.out), gi(g.out);
  double a, b;
  int n = 0;
  while (ci >> a && gi >> b) {
    EXPECT_NEAR(a, b, 1e-4) << "value " << n;
    ++n;
  }
  EXPECT_GT(n, 1000);
}

}  // namespace
}  // namespace mpumesh
