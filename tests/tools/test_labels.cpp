// Label maps: `run --label L`, `run --labels all|LIST --separate` and the complex of
// `run --labels` on a synthetic label map with two touching labels, one apart, a ball in
// a nest and one too small to mesh.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <filesystem>
#include <set>

#include "cli_support.h"
#include "io/mesh_io.h"
#include "io/read_file.h"
#include "mesh/cgal_geometry.h"
#include "mesh/quality.h"
#include "mesh/topology.h"

namespace mpumesh {
namespace {

namespace fs = std::filesystem;

std::string label_phantom(const std::string& dir) {
  const std::string p = dir + "/labels.nii.gz";
  write_volume(test::LabelPhantom{}.volume(), p);
  return p;
}

// The analytic volumes (mm^3): the ellipsoid's two parts and the ball.
double ellipsoid_volume(const test::LabelPhantom& ph) { return 4.0 / 3.0 * M_PI * ph.radii.prod(); }

class Labels : public ::testing::Test {
 protected:
  // Once per process: ctest runs each test in a process of its own, two at a time.
  static void SetUpTestSuite() {
    dir_ = test::temp_dir("labels-" + std::to_string(getpid()));
    map_ = label_phantom(dir_);
    all_ = run("run " + map_ + " --labels all --separate -o " + dir_ + "/part_{label}.ply --report " + dir_ +
               "/report.json --particles 3000 --backend cpu");
  }
  static std::string dir_, map_;
  static Result all_;
};
std::string Labels::dir_, Labels::map_;
Result Labels::all_;

TEST_F(Labels, AllMeshesEveryLabelOnceAndSkipsTheOneTooSmall) {
  ASSERT_EQ(all_.code, 0) << all_.out;
  const auto j = nlohmann::json::parse(read_file(dir_ + "/report.json"));
  ASSERT_EQ(j["labels"].size(), 5u) << j.dump(1);
  const std::vector<int> meshed = {1, 2, 3, 5, 6};
  for (size_t k = 0; k < meshed.size(); ++k) {
    EXPECT_EQ(j["labels"][k]["label"], meshed[k]);
    EXPECT_TRUE(fs::exists(dir_ + "/part_" + std::to_string(meshed[k]) + ".ply")) << meshed[k];
    EXPECT_TRUE(j["labels"][k]["quality"]["closed"].get<bool>());
  }
  EXPECT_FALSE(fs::exists(dir_ + "/part_4.ply"));
  ASSERT_EQ(j["skipped"].size(), 1u);
  EXPECT_EQ(j["skipped"][0]["label"], 4);
  EXPECT_EQ(j["skipped"][0]["voxels"], 2);
  EXPECT_NE(j["skipped"][0]["reason"].get<std::string>().find("too small to mesh"), std::string::npos);
  EXPECT_NE(all_.out.find("(label 4): skipped: 2 voxels, too small to mesh"), std::string::npos) << all_.out;
  EXPECT_NE(all_.out.find("5 labels meshed, 1 skipped"), std::string::npos) << all_.out;
  // The volume is read once for all the labels.
  EXPECT_TRUE(j["stage_seconds"].contains("read volume"));
  for (const auto& l : j["labels"]) EXPECT_FALSE(l["stage_seconds"].contains("read volume"));
}

// The mean distance (mm) from the vertices of `a` within `near` of the interface to `b`.
template <class Near>
double mean_gap(const TriangleMesh& a, const TriangleMesh& b, Near near) {
  std::vector<Eigen::Vector3d> on;
  for (const auto& v : a.vertices)
    if (near(v)) on.push_back(v);
  EXPECT_GT(on.size(), 20u);
  double mean = 0;
  for (const double d : point_distances(on, b)) mean += d / double(on.size());
  return mean;
}

TEST_F(Labels, TouchingLabelsMeetWithoutCrossing) {
  ASSERT_EQ(all_.code, 0) << all_.out;
  const test::LabelPhantom ph;
  const auto j = nlohmann::json::parse(read_file(dir_ + "/report.json"));
  // Every two labels whose boxes overlap are checked: 1 with 2, 5 with 6.
  ASSERT_EQ(j["crossings"].size(), 2u) << j["crossings"].dump();
  EXPECT_EQ(j["crossings"][0]["labels"], nlohmann::json({1, 2}));
  EXPECT_EQ(j["crossings"][1]["labels"], nlohmann::json({5, 6}));
  for (const auto& c : j["crossings"]) EXPECT_EQ(c["triangle_pairs"], 0) << c.dump();
  // The same, counted here: a cut plane tilted against the slices, and a sphere.
  const TriangleMesh a = read_mesh(dir_ + "/part_1.ply"), b = read_mesh(dir_ + "/part_2.ply");
  const TriangleMesh core = read_mesh(dir_ + "/part_5.ply"), nest = read_mesh(dir_ + "/part_6.ply");
  EXPECT_EQ(count_crossings(a, b), 0);
  EXPECT_EQ(count_crossings(core, nest), 0);
  // They do touch: across the shared faces the two surfaces lie within a voxel.
  const double cut = mean_gap(a, b, [&](const Eigen::Vector3d& v) {
    return std::abs((v - ph.centre).dot(ph.cut_normal)) < 0.8 && (v - ph.centre).cwiseQuotient(ph.radii).norm() < 0.7;
  });
  const double sphere = mean_gap(core, nest, [](const Eigen::Vector3d&) { return true; });
  for (const double gap : {cut, sphere}) {
    EXPECT_GT(gap, 0.05);
    EXPECT_LT(gap, 0.8);
  }
  // The core lies in the nest's cavity: the nest is two shells, the inner one facing in.
  EXPECT_EQ(j["labels"][4]["quality"]["components"], 2);
  // Together the two parts hold the ellipsoid's volume, less the gap between them.
  const double whole = ellipsoid_volume(ph);
  EXPECT_NEAR(enclosed_volume(a) + enclosed_volume(b), whole, 0.05 * whole);
  const double ball = 4.0 / 3.0 * M_PI * std::pow(ph.ball_radius, 3);
  EXPECT_NEAR(enclosed_volume(read_mesh(dir_ + "/part_3.ply")), ball, 0.06 * ball);
  std::cout << "gap over the cut " << cut << " mm, over the sphere " << sphere << " mm; parts "
            << enclosed_volume(a) + enclosed_volume(b) << " of " << whole << " mm3\n";
}

TEST_F(Labels, OneLabelGivesTheBytesOfTheSameLabelAmongAll) {
  ASSERT_EQ(all_.code, 0) << all_.out;
  const std::string out = dir_ + "/one_3.ply";
  const Result r = run("run " + map_ + " --label 3 -o " + out + " --particles 3000 --backend cpu --quiet");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(read_file(out), read_file(dir_ + "/part_3.ply"));
}

TEST_F(Labels, ANamedLabelTooSmallOrAbsentIsRefusedAndNothingWritten) {
  const std::string out = dir_ + "/named_{label}.ply";
  expect_failure("run " + map_ + " --labels 3,4 -o " + out + " --backend cpu",
                 "(label 4): 2 voxels, too small to mesh (a label needs at least 8)", dir_ + "/named_3.ply");
  expect_failure("run " + map_ + " --label 4 -o " + dir_ + "/four.ply --backend cpu", "(label 4): 2 voxels",
                 dir_ + "/four.ply");
  expect_failure("run " + map_ + " --labels 1,9 -o " + out + " --backend cpu",
                 "no voxel holds label 9 (the labels present: 1, 2, 3, 4, 5, 6)", dir_ + "/named_1.ply");
  expect_failure("run " + map_ + " --label 9 -o " + dir_ + "/nine.ply --backend cpu", "(label 9): no voxel holds this label",
                 dir_ + "/nine.ply");
}

TEST_F(Labels, OptionsThatDoNotFitALabelMapAreRefused) {
  expect_failure("run " + map_ + " --labels all --separate -o " + dir_ + "/one.ply", "the path must hold {label}",
                 dir_ + "/one.ply");
  expect_failure("run " + map_ + " --labels all --separate -o " + dir_ + "/x_{label}.ply --html " + dir_ + "/r.html",
                 "r.html: --labels writes one file per label", dir_ + "/x_1.ply");
  expect_failure("run " + map_ + " --labels all -o " + dir_ + "/c.ply --html " + dir_ + "/r_{label}.html",
                 "r_{label}.html: the complex of --labels has one HTML report", dir_ + "/c.ply");
  expect_failure("run " + map_ + " --labels all -o " + dir_ + "/c.stl", "c.stl: the complex is written as PLY",
                 dir_ + "/c.stl");
  expect_failure("run " + map_ + " --label 3 --separate -o " + dir_ + "/s.ply", "--separate: applies to --labels and to surface meshes",
                 dir_ + "/s.ply");
  expect_failure("run " + map_ + " --label 3 --threshold 2 -o " + dir_ + "/t.ply", "--threshold, --method",
                 dir_ + "/t.ply");
  expect_failure("run " + map_ + " --labels 3,x -o " + dir_ + "/x_{label}.ply", "'x' is not a label",
                 dir_ + "/x_3.ply");
  expect_failure("run " + map_ + " --labels 3,3 -o " + dir_ + "/x_{label}.ply", "label 3 is named twice",
                 dir_ + "/x_3.ply");
  const std::string ball = ball_phantom(dir_);  // an intensity image, not a label map
  expect_failure("run " + ball + " --labels all -o " + dir_ + "/b_{label}.ply", "not a label map",
                 dir_ + "/b_1.ply");
}

// The complex: one PLY whose faces carry the pair of labels they separate, every label's
// boundary closed, the touching pairs sharing their interface, the report's figures; and
// with {label} each label's boundary cut from the same complex.
TEST_F(Labels, OneComplexWhoseTouchingLabelsShareTheirInterfaces) {
  const std::string complex = dir_ + "/complex.ply", report = dir_ + "/complex.json";
  const Result r = run("run " + map_ + " --labels all -o " + complex + " --report " + report +
                       " --particles 3000 --backend cpu");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("every label closed: yes"), std::string::npos) << r.out;
  const TriangleMesh c = read_mesh(complex);
  ASSERT_EQ(c.face_labels.size(), c.triangles.size());
  std::set<std::pair<int, int>> pairs;
  for (const auto& l : c.face_labels) {
    EXPECT_LT(l[0], l[1]);
    pairs.insert({l[0], l[1]});
  }
  // The cut ellipsoid's halves (1, 2) and the ball in its nest (5, 6) share an interface;
  // 3 stands apart; 4 is too small.
  const std::set<std::pair<int, int>> expected = {{0, 1}, {0, 2}, {0, 3}, {0, 6}, {1, 2}, {5, 6}};
  EXPECT_EQ(pairs, expected);
  const auto j = nlohmann::json::parse(read_file(report));
  const auto& cx = j["complex"];
  EXPECT_EQ(cx["crossing_pairs"], 0);
  ASSERT_EQ(cx["labels"].size(), 5u);
  for (const auto& l : cx["labels"]) {
    EXPECT_TRUE(l["closed"].get<bool>()) << l.dump();
    EXPECT_LT(std::abs(l["volume_vs_voxels"].get<double>()), 0.08) << l.dump();
  }
  EXPECT_EQ(cx["interfaces"].size(), 6u);
  EXPECT_GE(cx["junctions"]["curves"].get<int>(), 1);  // where 0, 1 and 2 meet
  EXPECT_EQ(j["skipped"][0]["label"], 4);
  // Each label's boundary cut from it: closed, and neighbours share their vertices.
  const Result cut = run("run " + map_ + " --labels 1,2 -o " + dir_ + "/cut_{label}.ply --particles 3000 --backend cpu --quiet");
  ASSERT_EQ(cut.code, 0) << cut.out;
  const TriangleMesh a = read_mesh(dir_ + "/cut_1.ply"), b = read_mesh(dir_ + "/cut_2.ply");
  EXPECT_TRUE(analyze_topology(a).oriented);
  EXPECT_TRUE(analyze_topology(b).oriented);
  std::set<std::array<double, 3>> in_a;
  for (const auto& v : a.vertices) in_a.insert({v.x(), v.y(), v.z()});
  int64_t shared = 0;
  for (const auto& v : b.vertices) shared += in_a.count({v.x(), v.y(), v.z()});
  EXPECT_GT(shared, 50);
  const test::LabelPhantom ph;
  const double whole = ellipsoid_volume(ph);
  EXPECT_NEAR(enclosed_volume(a) + enclosed_volume(b), whole, 0.03 * whole);
}

}  // namespace
}  // namespace mpumesh
