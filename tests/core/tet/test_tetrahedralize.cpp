// core/tet: tetrahedra inside closed surfaces (a sphere; a shell around a cavity beside a
// ball), their boundary the surface's triangles, their volume the surface's, their shapes;
// and the four volume-mesh formats written and read back (core/io/tet_io.h).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "common/error.h"
#include "io/tet_io.h"
#include "tet/tetrahedralize.h"
#include "test_support.h"

namespace mpumesh {
namespace {

TriangleMesh turned_inside_out(TriangleMesh m) {
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

TriangleMesh joined(const TriangleMesh& a, const TriangleMesh& b, const Eigen::Vector3d& shift) {
  TriangleMesh m = a;
  const uint32_t n = uint32_t(m.vertices.size());
  for (const auto& v : b.vertices) m.vertices.push_back(v + shift);
  for (auto t : b.triangles) m.triangles.push_back({t[0] + n, t[1] + n, t[2] + n});
  return m;
}

double enclosed(const TriangleMesh& m) {
  double v = 0;
  for (const auto& t : m.triangles) v += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6;
  return v;
}

std::set<std::array<uint32_t, 3>> sorted_triangles(const std::vector<std::array<uint32_t, 3>>& tris) {
  std::set<std::array<uint32_t, 3>> s;
  for (auto t : tris) {
    std::sort(t.begin(), t.end());
    s.insert(t);
  }
  return s;
}

// A run's volume mesh errors name the run's input.
TEST(Tetrahedralize, ARunsVolumeMeshErrorNamesItsInput) {
  EXPECT_STREQ(volume_mesh_error("scan.nii", InputError("tetmesh: TetGen stopped: an input error")).what(),
               "scan.nii: volume mesh: TetGen stopped: an input error");
}

TEST(Tetrahedralize, FillsASphereWithTheSurfaceAsItsBoundary) {
  const TriangleMesh sphere = test::icosphere(10, 4);  // 2,562 vertices, 1.2 mm edges
  TetStats st;
  const TetMesh m = tetrahedralize(sphere, {}, &st);
  std::printf("%lld tetrahedra, %lld nodes; dihedral %.2f-%.2f deg, %.3f%% under 15, radius ratio %.3f; %.2f s\n",
              (long long)st.quality.tets, (long long)st.quality.nodes, st.quality.min_dihedral_deg,
              st.quality.max_dihedral_deg, st.quality.pct_min_dihedral_below_15, st.quality.radius_ratio_mean, st.seconds);
  EXPECT_EQ(m.regions, 1);
  EXPECT_EQ(st.quality.inverted, 0);
  EXPECT_EQ(st.boundary_points, 0);
  EXPECT_EQ(st.cavities_removed, 0);
  EXPECT_GT(st.interior_points, 100);
  // The boundary is the surface: its vertices the first nodes, its triangles the faces.
  for (size_t i = 0; i < sphere.vertices.size(); ++i) ASSERT_EQ(m.nodes[i], sphere.vertices[i]);
  EXPECT_EQ(sorted_triangles(m.boundary), sorted_triangles(sphere.triangles));
  EXPECT_NEAR(st.quality.volume_mm3, enclosed(sphere), 1e-9 * enclosed(sphere));
  EXPECT_GE(st.quality.min_dihedral_deg, 10);
  EXPECT_LE(st.quality.pct_min_dihedral_below_15, 1.0);
  EXPECT_GE(st.quality.radius_ratio_mean, 0.7);
  // Graded: the largest edges lie deep inside, up to the size.
  double longest = 0;
  for (const auto& t : m.tets)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) longest = std::max(longest, (m.nodes[t[size_t(a)]] - m.nodes[t[size_t(b)]]).norm());
  EXPECT_GT(longest, 2.0);
}

TEST(Tetrahedralize, MendsFlatTetrahedraAcrossAThinPlate) {
  // A shell 0.4 mm thick under 1.2 mm triangles, its inner wall turned against the outer so
  // that their vertices do not face each other: tetrahedra of four surface nodes span the
  // plate flat, and a point inside each lets the refinement replace them.
  TriangleMesh inner = turned_inside_out(test::icosphere(9.6, 4));
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  for (auto& v : inner.vertices) v = turn * v;
  const TriangleMesh plate = joined(test::icosphere(10, 4), inner, Eigen::Vector3d::Zero());
  TetStats st;
  const TetMesh m = tetrahedralize(plate, {}, &st);
  std::printf("%lld tetrahedra, %lld points for flat ones; dihedral %.2f-%.2f deg, %.3f%% under 15, radius ratio %.3f\n",
              (long long)st.quality.tets, (long long)st.flat_tet_points, st.quality.min_dihedral_deg,
              st.quality.max_dihedral_deg, st.quality.pct_min_dihedral_below_15, st.quality.radius_ratio_mean);
  EXPECT_GT(st.flat_tet_points, 0);
  EXPECT_GE(st.quality.min_dihedral_deg, 10);
  EXPECT_EQ(st.boundary_points, 0);
  EXPECT_EQ(sorted_triangles(m.boundary), sorted_triangles(plate.triangles));
  EXPECT_NEAR(st.quality.volume_mm3, enclosed(plate), 1e-9 * enclosed(plate));
}

TEST(Tetrahedralize, KeepsCavitiesEmptyAndNumbersEachBody) {
  // A shell (outer radius 10, a cavity of radius 5 inside, its wall facing in) and a ball
  // of radius 4 beside it.
  const TriangleMesh outer = test::icosphere(10, 3), cavity = turned_inside_out(test::icosphere(5, 3));
  const TriangleMesh shell = joined(outer, cavity, Eigen::Vector3d::Zero());
  const TriangleMesh both = joined(shell, test::icosphere(4, 3), Eigen::Vector3d(20, 0, 0));
  TetStats st;
  const TetMesh m = tetrahedralize(both, {}, &st);
  EXPECT_EQ(m.regions, 2);
  EXPECT_EQ(st.cavities_removed, 1);
  EXPECT_NEAR(st.quality.volume_mm3, enclosed(both), 1e-9 * enclosed(both));
  // No tetrahedron in the cavity, and the ball its own region.
  std::set<int32_t> shell_regions, ball_regions;
  for (size_t t = 0; t < m.tets.size(); ++t) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (uint32_t v : m.tets[t]) c += m.nodes[v] / 4;
    if (c.x() < 12) EXPECT_GT(c.norm(), 4.5) << t;
    (c.x() < 12 ? shell_regions : ball_regions).insert(m.region[t]);
  }
  EXPECT_EQ(shell_regions.size(), 1u);
  EXPECT_EQ(ball_regions.size(), 1u);
  EXPECT_NE(*shell_regions.begin(), *ball_regions.begin());
  EXPECT_EQ(sorted_triangles(m.boundary), sorted_triangles(both.triangles));
}

TEST(Tetrahedralize, RefusesAnOpenSurfaceCountingItsBorderEdges) {
  TriangleMesh open = test::icosphere(10, 2);
  open.triangles.pop_back();
  try {
    tetrahedralize(open, {});
    FAIL() << "an open surface was filled";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("3 border edges"), std::string::npos) << e.what();
  }
  EXPECT_THROW(tetrahedralize(turned_inside_out(test::icosphere(10, 2)), {}), InputError);  // nothing inside it
}

TEST(TetIo, EveryFormatReadsBackTheSameMesh) {
  const TriangleMesh both = joined(test::icosphere(6, 2), test::icosphere(3, 2), Eigen::Vector3d(10, 0, 0));
  const TetMesh m = tetrahedralize(both, {});
  ASSERT_EQ(m.regions, 2);
  const std::string dir = test::temp_dir("tet_io");
  for (const char* ext : {".msh", ".vtu", ".mesh", ".inp"}) {
    const std::string path = dir + "/m" + ext;
    write_tet_mesh(m, path);
    const TetMesh back = read_tet_mesh(path);
    ASSERT_EQ(back.nodes.size(), m.nodes.size()) << ext;
    EXPECT_EQ(back.regions, 2) << ext;
    // The nodes to the written digits, the tetrahedra as written (a .msh groups them by region).
    for (size_t i = 0; i < m.nodes.size(); ++i) EXPECT_LT((back.nodes[i] - m.nodes[i]).norm(), 1e-12) << ext;
    std::multiset<std::pair<std::array<uint32_t, 4>, int32_t>> a, b;
    for (size_t t = 0; t < m.tets.size(); ++t) a.insert({m.tets[t], m.region[t]});
    for (size_t t = 0; t < back.tets.size(); ++t) b.insert({back.tets[t], back.region[t]});
    EXPECT_EQ(a, b) << ext;
  }
  EXPECT_THROW(write_tet_mesh(m, dir + "/m.stl"), InputError);
}

// CalculiX reads a number from its field's first 20 characters: a coordinate near zero,
// which 17 significant digits and an exponent make 23 characters long, is written in 20
// (15 digits), the others with 17; every one reads back.
TEST(TetIo, AbaqusNodesFitCalculixFields) {
  TetMesh m;
  m.nodes = {{-3.048349639045326, -9.6402416196669782e-06, 17.544060037033461},
             {1e-300, -123456.78901234567, 0.1},
             {0, 1, 0},
             {0, 0, 1}};
  m.tets = {{0, 1, 2, 3}};
  m.region = {1};
  m.regions = 1;
  const std::string path = test::temp_dir("inp_fields") + "/m.inp";
  write_tet_mesh(m, path);
  std::ifstream in(path);
  bool in_nodes = false;
  int lines = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("*", 0) == 0) in_nodes = line.rfind("*NODE", 0) == 0;
    if (!in_nodes || line[0] == '*') continue;
    ++lines;
    std::stringstream fields(line);
    for (std::string f; std::getline(fields, f, ',');) EXPECT_LE(f.size() - (f[0] == ' ' ? 1 : 0), 20u) << line;
  }
  EXPECT_EQ(lines, 4);
  const TetMesh back = read_tet_mesh(path);
  ASSERT_EQ(back.nodes.size(), 4u);
  for (size_t i = 0; i < 4; ++i)
    for (int d = 0; d < 3; ++d)
      EXPECT_NEAR(back.nodes[i][d], m.nodes[i][d], 1e-14 * std::max(1.0, std::abs(m.nodes[i][d]))) << i << " " << d;
}

}  // namespace
}  // namespace mpumesh
