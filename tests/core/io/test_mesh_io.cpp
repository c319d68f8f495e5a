// Mesh files: every format round-trips, foreign variants are read, and broken files are
// refused with the file named; a failed write leaves the old file untouched.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>

#include "common/error.h"
#include "io/mesh_io.h"
#include "io/read_file.h"
#include "mesh/surface_attributes.h"
#include "test_support.h"

namespace mpumesh {
namespace {

void expect_same(const TriangleMesh& a, const TriangleMesh& b, double tol) {
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  // Corner by corner (STL has no vertex list: welding renumbers vertices).
  for (size_t f = 0; f < a.triangles.size(); ++f)
    for (int c = 0; c < 3; ++c)
      ASSERT_LT((a.vertices[a.triangles[f][size_t(c)]] - b.vertices[b.triangles[f][size_t(c)]]).norm(), tol);
}

class MeshRoundTrip : public ::testing::TestWithParam<std::string> {};

TEST_P(MeshRoundTrip, WritesAndReadsBack) {
  const TriangleMesh m = test::icosphere(12.5, 2);
  const std::string path = test::temp_dir("rt") + "/mesh" + GetParam();
  write_mesh(m, path);
  expect_same(m, read_mesh(path), 1e-5);
  // Nothing but the file itself is left in the directory.
  int entries = 0;
  for (auto& e : std::filesystem::directory_iterator(std::filesystem::path(path).parent_path())) (void)e, ++entries;
  EXPECT_EQ(entries, 1);
}
INSTANTIATE_TEST_SUITE_P(Formats, MeshRoundTrip, ::testing::Values(".ply", ".stl", ".obj", ".off", ".PLY"));

TEST(MeshIo, PlyCarriesNormalsAndCurvature) {
  TriangleMesh m = test::icosphere(10, 2);
  estimate_mesh_curvature(m);
  const std::string path = test::temp_dir("attr") + "/mesh.ply";
  write_mesh(m, path);
  const TriangleMesh r = read_mesh(path);
  ASSERT_EQ(r.normals.size(), m.vertices.size());
  ASSERT_EQ(r.curvature.size(), m.vertices.size());
  for (size_t i = 0; i < m.vertices.size(); ++i) {
    EXPECT_LT((r.normals[i] - m.normals[i]).norm(), 1e-6f);
    for (size_t c = 0; c < 4; ++c) EXPECT_EQ(r.curvature[i][c], m.curvature[i][c]);
  }
  // Without them the file has neither (and other formats never carry them).
  TriangleMesh plain = m;
  plain.normals.clear();
  plain.curvature.clear();
  write_mesh(plain, path);
  const TriangleMesh r2 = read_mesh(path);
  EXPECT_TRUE(r2.normals.empty());
  EXPECT_TRUE(r2.curvature.empty());
}

TEST(MeshCurvature, IcosphereEstimateIsOneOverRSquared) {
  const double radius = 15;
  TriangleMesh m = test::icosphere(radius, 4);
  estimate_mesh_curvature(m);
  for (size_t i = 0; i < m.vertices.size(); ++i) {
    const Eigen::Vector3f out = m.vertices[i].normalized().cast<float>();
    EXPECT_GT(m.normals[i].dot(out), 0.999f);
    EXPECT_NEAR(m.curvature[i][2] * radius * radius, 1.0, 0.05) << i;  // K
    EXPECT_NEAR(m.curvature[i][3] * radius, -1.0, 0.05) << i;          // H, MPU's sign: convex < 0
    EXPECT_GE(m.curvature[i][0], m.curvature[i][1]);
  }
  // Winding reversed: the normals still point out.
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  estimate_mesh_curvature(m);
  EXPECT_GT(m.normals[0].dot(m.vertices[0].normalized().cast<float>()), 0.999f);
}

TEST(MeshIo, ReadsAsciiPlyWithQuadsAndExtraProperties) {
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar red\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0 255\n1 0 0 0\n1 1 0 0\n0 1 0 0\n4 0 1 2 3\n";
  const TriangleMesh m = parse_mesh(ply, MeshFormat::kPly, "quad.ply");
  EXPECT_EQ(m.vertices.size(), 4u);
  EXPECT_EQ(m.triangles.size(), 2u);
}

TEST(MeshIo, ReadsAsciiStlAndWelds) {
  const std::string stl =
      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
      "facet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n";
  const TriangleMesh m = parse_mesh(stl, MeshFormat::kStl, "t.stl");
  EXPECT_EQ(m.vertices.size(), 4u);
  EXPECT_EQ(m.triangles.size(), 2u);
}

TEST(MeshIo, ObjWithSlashesAndNegativeIndices) {
  const TriangleMesh m =
      parse_mesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf -3 -2 -1\n", MeshFormat::kObj, "a.obj");
  EXPECT_EQ(m.triangles.size(), 2u);
  EXPECT_EQ(m.triangles[1], (std::array<uint32_t, 3>{0, 1, 2}));
}

void expect_error(const std::string& bytes, MeshFormat f, const std::string& name, const std::string& words) {
  try {
    parse_mesh(bytes, f, name);
    FAIL() << "expected InputError for " << name;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

TEST(MeshIo, RefusesBrokenFiles) {
  expect_error("", MeshFormat::kPly, "empty.ply", "empty");
  expect_error("plx\n", MeshFormat::kPly, "magic.ply", "not a PLY");
  expect_error("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
               "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
               MeshFormat::kPly, "range.ply", "out of range");
  expect_error("ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
               "property float z\nend_header\n\x01\x02",
               MeshFormat::kPly, "cut.ply", "truncated");
  expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n", MeshFormat::kOff, "short.off", "truncated");
  expect_error("OFX\n", MeshFormat::kOff, "magic.off", "not an OFF");
  expect_error("v 0 0 0\nf 1 2 3\n", MeshFormat::kObj, "range.obj", "out of range");
  expect_error("v x 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", MeshFormat::kObj, "text.obj", "malformed OBJ vertex");
  {
    std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
                      "property float y\nproperty float z\nend_header\n";
    const float xyz[3] = {std::numeric_limits<float>::quiet_NaN(), 0, 0};
    ply.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
    expect_error(ply, MeshFormat::kPly, "nan.ply", "NaN");
  }
  expect_error(std::string(90, 'x'), MeshFormat::kStl, "junk.stl", "not an STL");
  EXPECT_THROW(mesh_format_from_path("mesh.vtk"), InputError);
  EXPECT_THROW(read_mesh("/nonexistent/mesh.ply"), InputError);
}

TEST(MeshIo, FailedWriteKeepsTheOldFile) {
  const std::string dir = test::temp_dir("keep");
  const std::string path = dir + "/mesh.ply";
  write_mesh(test::icosahedron(1.0), path);
  const std::string before = read_file(path);
  TriangleMesh bad = test::icosahedron(1.0);
  bad.triangles.push_back({0, 1, 99});  // index out of range: a bug, refused before writing
  EXPECT_ANY_THROW(write_mesh(bad, path));
  EXPECT_EQ(read_file(path), before);
  EXPECT_THROW(write_mesh(test::icosahedron(1.0), dir + "/missing/mesh.ply"), InputError);
}

}  // namespace
}  // namespace mpumesh
