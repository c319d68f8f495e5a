// `run MESH` on a surface mesh of several closed parts (the parts phantom,
// core/phantom/parts_phantom.h): one complex whose faces carry the pair of parts they
// separate, numbered by volume; each part's boundary cut from it with {label}; the one
// remeshed surface with --separate, and for a marching-cubes surface; the outputs a
// complex cannot have refused.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <filesystem>
#include <set>

#include "cli_support.h"
#include "io/mesh_io.h"
#include "io/read_file.h"
#include "io/tet_io.h"
#include "mesh/topology.h"
#include "phantom/parts_phantom.h"

namespace mpumesh {
namespace {

namespace fs = std::filesystem;

class Parts : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = test::temp_dir("parts-" + std::to_string(getpid()));
    mesh_ = dir_ + "/parts.ply";
    phantom_ = phantom::parts_phantom();
    write_mesh(phantom_.mesh, mesh_);
  }
  static std::string dir_, mesh_;
  static phantom::PartsPhantom phantom_;
};
std::string Parts::dir_, Parts::mesh_;
phantom::PartsPhantom Parts::phantom_;

TEST_F(Parts, AMeshOfFivePartsGivesOneComplexOfFiveParts) {
  const std::string complex = dir_ + "/complex.ply", report = dir_ + "/complex.json";
  const std::string volume = dir_ + "/parts.vtu";
  const Result r = run("run " + mesh_ + " -o " + complex + " --report " + report + " --volume " + volume +
                       " --particles 6000 --backend cpu");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("5 parts"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("every part closed: yes"), std::string::npos) << r.out;
  const TriangleMesh c = read_mesh(complex);
  ASSERT_EQ(c.face_labels.size(), c.triangles.size());
  std::set<std::pair<int, int>> pairs;
  for (const auto& l : c.face_labels) pairs.insert({l[0], l[1]});
  const std::set<std::pair<int, int>> expected = {{0, 1}, {0, 2}, {0, 3}, {0, 4}, {0, 5}, {1, 2}};
  EXPECT_EQ(pairs, expected) << "the touching pair shares its disc; the others stay apart";
  const auto j = nlohmann::json::parse(read_file(report));
  const auto& cx = j["complex"];
  EXPECT_EQ(cx["crossing_pairs"], 0);
  EXPECT_EQ(cx["shells_removed"], 0);
  ASSERT_EQ(cx["labels"].size(), 5u);
  for (size_t k = 0; k < 5; ++k) {
    const auto& l = cx["labels"][k];
    EXPECT_EQ(l["label"], int(k) + 1);
    EXPECT_TRUE(l["closed"].get<bool>()) << l.dump();
    EXPECT_EQ(l["components"], 1) << l.dump();
    EXPECT_NEAR(l["input_volume_mm3"].get<double>(), phantom_.part_volumes[k], 1e-6 * phantom_.part_volumes[k]);
    EXPECT_LT(std::abs(l["volume_vs_input"].get<double>()), 0.01) << l.dump();
    EXPECT_FALSE(l.contains("voxels"));
    // Its tetrahedra fill its boundary in the complex.
    EXPECT_NEAR(l["tetrahedra_volume_mm3"].get<double>(), l["volume_mm3"].get<double>(),
                1e-6 * l["volume_mm3"].get<double>());
  }
  // One volume mesh, a region per part; the touching pair's disc its only shared faces.
  const TetMesh v = read_tet_mesh(volume);
  EXPECT_EQ(std::set<int32_t>(v.region.begin(), v.region.end()), (std::set<int32_t>{1, 2, 3, 4, 5}));
  std::set<std::pair<int, int>> volume_pairs;
  for (const auto& l : v.boundary_labels) volume_pairs.insert({l[0], l[1]});
  EXPECT_EQ(volume_pairs, expected);
  EXPECT_EQ(j["volume_mesh"]["labels"].size(), 5u);
  EXPECT_EQ(j["volume_mesh"]["inverted"], 0);
  EXPECT_EQ(j["volume_mesh"]["output"], volume);
}

TEST_F(Parts, EachPartCutFromTheComplexAndTheOneSurfaceWithSeparate) {
  const Result cut = run("run " + mesh_ + " -o " + dir_ + "/part_{label}.ply --particles 6000 --backend cpu --quiet");
  ASSERT_EQ(cut.code, 0) << cut.out;
  for (int k = 1; k <= 5; ++k) {
    const TriangleMesh m = read_mesh(dir_ + "/part_" + std::to_string(k) + ".ply");
    const Topology t = analyze_topology(m);
    EXPECT_TRUE(t.oriented) << k;
    EXPECT_EQ(t.components, 1) << k;
  }
  const TriangleMesh a = read_mesh(dir_ + "/part_1.ply"), b = read_mesh(dir_ + "/part_2.ply");
  std::set<std::array<double, 3>> in_a;
  for (const auto& v : a.vertices) in_a.insert({v.x(), v.y(), v.z()});
  int64_t shared = 0;
  for (const auto& v : b.vertices) shared += in_a.count({v.x(), v.y(), v.z()});
  EXPECT_GT(shared, 100) << "the touching parts share their interface's vertices";
  const Result one = run("run " + mesh_ + " -o " + dir_ + "/one.ply --separate --particles 6000 --backend cpu --quiet");
  ASSERT_EQ(one.code, 0) << one.out;
  const TriangleMesh s = read_mesh(dir_ + "/one.ply");
  EXPECT_TRUE(s.face_labels.empty());
  EXPECT_TRUE(analyze_topology(s).oriented);
}

// A marching-cubes surface's components are a scan's structures: remeshed as one surface.
TEST_F(Parts, AMarchingCubesSurfaceOfSeveralPartsIsRemeshedAsOneSurface) {
  const std::string labels = dir_ + "/labels.nii.gz", mc = dir_ + "/mc.ply", out = dir_ + "/mc_remeshed.ply";
  write_volume(test::LabelPhantom{}.volume(), labels);
  const Result m = run("mc " + labels + " --threshold 0.5 -o " + mc + " --quiet --backend cpu");
  ASSERT_EQ(m.code, 0) << m.out;
  ASSERT_GE(analyze_topology(read_mesh(mc)).components, 2);
  const Result r = run("run " + mc + " -o " + out + " --particles 3000 --backend cpu --quiet");
  ASSERT_EQ(r.code, 0) << r.out;
  const TriangleMesh s = read_mesh(out);
  EXPECT_TRUE(s.face_labels.empty());
  EXPECT_TRUE(analyze_topology(s).oriented);
}

TEST_F(Parts, OutputsAComplexCannotHaveAreRefusedAndNothingWritten) {
  expect_failure("run " + mesh_ + " -o " + dir_ + "/c.stl", "c.stl: the complex is written as PLY", dir_ + "/c.stl");
  expect_failure("run " + mesh_ + " -o " + dir_ + "/h.ply --html " + dir_ + "/h_{label}.html",
                 "h_{label}.html: the complex of " + mesh_ + " (5 parts) has one HTML report", dir_ + "/h.ply");
  expect_failure("run " + mesh_ + " -o " + dir_ + "/s.ply --surface " + dir_ + "/s_{label}.mpu",
                 "--surface: the parts' fits of the complex of " + mesh_ + " (5 parts) are not written",
                 dir_ + "/s.ply");
}

}  // namespace
}  // namespace mpumesh
