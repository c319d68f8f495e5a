// The multi-material phantoms' truth agrees with their labels: the label map holds each
// label's analytic volume, every change of label between two nearby points lies on a true
// interface between those two regions, each interface separates the two regions it names,
// and the junction curves are where three regions meet.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

#include "phantom/material_phantom.h"
#include "test_support.h"

namespace mpumesh::phantom {
namespace {

class MaterialPhantoms : public ::testing::TestWithParam<int> {
 protected:
  MaterialPhantom m = material_suite()[size_t(GetParam())];
};

// Points in the phantom's bounding cube, fixed seed.
std::vector<Eigen::Vector3d> random_points(const MaterialPhantom& m, int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-m.extent() - 1, m.extent() + 1);
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < n; ++i) out.push_back(m.centre + test::random_vector(u, rng));
  return out;
}

TEST_P(MaterialPhantoms, TheLabelMapHoldsEachLabelsVolume) {
  const Volume v = material_scan(m);
  std::map<int, int64_t> count;
  for (float x : v.voxels) ++count[int(x)];
  const double voxel = v.spacing.prod();
  for (int label : m.labels()) {
    SCOPED_TRACE(label);
    // Counting voxel centres: within 2% on these 20-40 mm shapes at 0.6-2 mm voxels.
    EXPECT_NEAR(double(count[label]) * voxel, m.label_volume(label), 0.02 * m.label_volume(label));
  }
  EXPECT_EQ(count.size(), m.labels().size() + 1);
}

TEST_P(MaterialPhantoms, EveryChangeOfLabelLiesOnTheirInterface) {
  const double step = 0.05;
  int changes = 0;
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  for (const Eigen::Vector3d& p : random_points(m, 200000, 3)) {
    const Eigen::Vector3d q = p + step * test::random_vector(g, rng).normalized();
    const int a = m.label_at(p), b = m.label_at(q);
    if (a == b) continue;
    ++changes;
    const double d = m.interface_distance(std::min(a, b), std::max(a, b), 0.5 * (p + q));
    ASSERT_LE(d, step) << a << " " << b;
  }
  EXPECT_GT(changes, 50);
}

TEST_P(MaterialPhantoms, EachInterfaceSeparatesTheRegionsItNames) {
  const double delta = 0.02;
  for (int b : m.labels())
    for (int a = 0; a < b; ++a) {
      if (!m.shares_interface(a, b)) continue;
      SCOPED_TRACE(std::to_string(a) + "-" + std::to_string(b));
      int checked = 0, agree = 0;
      for (const Eigen::Vector3d& p : random_points(m, 4000, uint32_t(10 * a + b))) {
        Eigen::Vector3d n, x;
        ASSERT_LT(m.interface_distance(a, b, p, &n, &x), 1e9);
        EXPECT_NEAR(n.norm(), 1, 1e-9);
        EXPECT_NEAR(m.interface_distance(a, b, x), 0, 1e-9);
        // Where p projects onto the interface's rim (a junction or a crease), p - x is not
        // along the normal: only the points that project inside the interface are checked.
        if ((p - x).normalized().cross(n).norm() > 1e-6 || m.junction_distance(x) < 2 * delta) continue;
        ++checked;
        agree += m.label_at(x - delta * n) == a && m.label_at(x + delta * n) == b;
      }
      EXPECT_GT(checked, 400);
      EXPECT_EQ(agree, checked);
    }
  // Regions that share no interface never touch.
  if (m.kind == MaterialPhantom::kJoint) EXPECT_FALSE(m.shares_interface(1, 2));
}

TEST_P(MaterialPhantoms, JunctionsAreWhereThreeRegionsMeet) {
  const std::vector<Eigen::Vector3d> junctions = m.junction_points(0.5);
  if (m.kind == MaterialPhantom::kNested || m.kind == MaterialPhantom::kJoint) {
    EXPECT_TRUE(junctions.empty());
    return;
  }
  ASSERT_GT(junctions.size(), 20u);
  const double r = 0.05;
  for (const Eigen::Vector3d& j : junctions) {
    EXPECT_NEAR(m.junction_distance(j), 0, 1e-9);
    std::set<int> around;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz)
          if (dx || dy || dz) around.insert(m.label_at(j + r * Eigen::Vector3d(dx, dy, dz).normalized()));
    EXPECT_GE(around.size(), 3u) << j.transpose();
  }
  // And only there: points with three regions close by are on a junction curve.
  for (const Eigen::Vector3d& p : random_points(m, 20000, 5)) {
    std::set<int> around;
    for (int d = 0; d < 3; ++d)
      for (const double s : {-r, r}) around.insert(m.label_at(p + s * Eigen::Vector3d::Unit(d)));
    around.insert(m.label_at(p));
    if (around.size() >= 3) EXPECT_LE(m.junction_distance(p), 2 * r) << p.transpose();
  }
}

// The joint's gap of one slice spacing survives in the label map: no voxel of the ball
// touches one of the cup, face to face.
TEST(MaterialPhantom, TheJointsGapLeavesNoTouchingVoxels) {
  for (const MaterialPhantom& m : material_suite()) {
    if (m.kind != MaterialPhantom::kJoint) continue;
    const Volume v = material_scan(m);
    int64_t touching = 0;
    for (int64_t k = 0; k + 1 < v.dims[2]; ++k)
      for (int64_t j = 0; j + 1 < v.dims[1]; ++j)
        for (int64_t i = 0; i + 1 < v.dims[0]; ++i) {
          const float x = v.at(i, j, k);
          for (const float y : {v.at(i + 1, j, k), v.at(i, j + 1, k), v.at(i, j, k + 1)})
            touching += (x == 1 && y == 2) || (x == 2 && y == 1);
        }
    EXPECT_EQ(touching, 0);
  }
}

std::string name_of(const ::testing::TestParamInfo<int>& info) {
  std::string n = material_suite()[size_t(info.param)].name;
  for (char& c : n)
    if (c == ' ') c = '_';
  return n;
}

INSTANTIATE_TEST_SUITE_P(Suite, MaterialPhantoms, ::testing::Range(0, 4), name_of);

}  // namespace
}  // namespace mpumesh::phantom
