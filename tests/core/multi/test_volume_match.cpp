// A label map's complex moved to hold its labels' voxel volumes (multi/volume_match.h), on
// a hand-built complex: a 20 x 10 x 10 mm box split at x = 10 into label 1 (x < 10) and
// label 2, the background around both, each face a grid of 4 x 4 squares.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "multi/complex_figures.h"
#include "multi/volume_match.h"

namespace mpumesh {
namespace {

class Builder {
 public:
  // The rectangle origin + s u + t v (s, t in [0, 1]) as triangles with labels (a, b), a
  // < b, whose normal u x v points from a into b.
  void rect(const Eigen::Vector3d& origin, const Eigen::Vector3d& u, const Eigen::Vector3d& v, int32_t a, int32_t b,
            int k = 4) {
    auto at = [&](int i, int j) { return vertex(origin + u * (double(i) / k) + v * (double(j) / k)); };
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < k; ++j) {
        const uint32_t p = at(i, j), q = at(i + 1, j), r = at(i + 1, j + 1), s = at(i, j + 1);
        mesh.triangles.push_back({p, q, r});
        mesh.triangles.push_back({p, r, s});
        mesh.face_labels.push_back({a, b});
        mesh.face_labels.push_back({a, b});
      }
  }
  // The triangle p q r, its normal (q - p) x (r - p) from a into b.
  void tri(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r, int32_t a, int32_t b) {
    mesh.triangles.push_back({vertex(p), vertex(q), vertex(r)});
    mesh.face_labels.push_back({a, b});
  }
  TriangleMesh mesh;

 private:
  uint32_t vertex(const Eigen::Vector3d& p) {
    const std::array<long, 3> key{std::lround(p.x() * 1e6), std::lround(p.y() * 1e6), std::lround(p.z() * 1e6)};
    const auto [it, added] = index_.try_emplace(key, uint32_t(mesh.vertices.size()));
    if (added) mesh.vertices.push_back(p);
    return it->second;
  }
  std::map<std::array<long, 3>, uint32_t> index_;
};

// Boxes [10 (l - 1), 10 l] x [0, 10] x [0, 10] of labels l = 1, 2, their outer faces
// oriented into them (from the background), the face at x = 10 from label 1 into label 2.
TriangleMesh split_box() {
  Builder b;
  const Eigen::Vector3d X(10, 0, 0), Y(0, 10, 0), Z(0, 0, 10);
  for (const int32_t l : {1, 2}) {
    const Eigen::Vector3d o = (l - 1) * X;
    b.rect(o, Z, X, 0, l);      // y = 0, normal +y
    b.rect(o + Y, X, Z, 0, l);  // y = 1, normal -y
    b.rect(o, X, Y, 0, l);      // z = 0, normal +z
    b.rect(o + Z, Y, X, 0, l);  // z = 1, normal -z
  }
  b.rect({0, 0, 0}, Y, Z, 0, 1);   // x = 0, normal +x
  b.rect(2 * X, Z, Y, 0, 2);       // x = 20, normal -x
  b.rect(X, Y, Z, 1, 2);           // x = 10, normal +x: from 1 into 2
  return b.mesh;
}

double label_volume(const TriangleMesh& c, int64_t label) { return enclosed_volume(multi::label_boundary(c, label)); }

TEST(VolumeMatch, HandBuiltBoxesHoldAThousandCubicMillimetresEach) {
  const TriangleMesh c = split_box();
  const multi::ComplexFigures f = multi::measure_complex(c, false);
  ASSERT_EQ(f.regions.size(), 2u);
  for (const multi::RegionFigures& r : f.regions) EXPECT_EQ(r.defects, 0) << r.label;
  EXPECT_NEAR(label_volume(c, 1), 1000.0, 1e-9);
  EXPECT_NEAR(label_volume(c, 2), 1000.0, 1e-9);
}

// Label 1 asked for 1,010 mm³ and label 2 for 990: the interfaces move by s_ab = c_a - c_b
// with (A_10 + A_12) c_1 - A_12 c_2 = 10 and -A_12 c_1 + (A_20 + A_12) c_2 = -10 (A_10 =
// A_20 = 500 mm², A_12 = 100 mm²): c_1 = -c_2 = 1 / 70, so the shared face moves 1 / 35 mm
// into label 2 and label 1's end face 1 / 70 mm out of it.
TEST(VolumeMatch, InterfacesMoveByTheLeastWeightedShift) {
  TriangleMesh c = split_box();
  const multi::VolumeMatchStats st = multi::match_label_volumes(c, {{1, 1010.0}, {2, 990.0}}, 1.0);
  EXPECT_NEAR(st.worst_before, 10.0 / 990, 1e-12);
  EXPECT_LT(st.worst_after, 1e-4);
  EXPECT_FALSE(st.reverted);
  EXPECT_EQ(st.frozen, 0);
  // The middle of the shared face and of label 1's end face (each face's grid is 4 x 4,
  // so both middles are vertices), to first order within a fifth: the walls' vertices
  // where the boxes meet are asked to move out of label 1 and into label 2 by the same
  // amount, and stay, so the later rounds move the faces further than first order.
  int seen = 0;
  for (const Eigen::Vector3d& p : c.vertices) {
    if (std::abs(p.y() - 5) > 1e-6 || std::abs(p.z() - 5) > 1e-9) continue;
    if (std::abs(p.x() - 10) < 1) {
      EXPECT_NEAR(p.x() - 10, 1.0 / 35, 0.2 / 35);
      ++seen;
    }
    if (std::abs(p.x()) < 1) {
      EXPECT_NEAR(p.x(), -1.0 / 70, 0.2 / 70);
      ++seen;
    }
  }
  EXPECT_EQ(seen, 2);
  const multi::ComplexFigures f = multi::measure_complex(c, false);
  for (const multi::RegionFigures& r : f.regions) EXPECT_EQ(r.defects, 0) << r.label;
}

// No interface moves further than the bound; a label not named keeps its place.
TEST(VolumeMatch, ShiftsHeldToTheBound) {
  TriangleMesh c = split_box();
  const TriangleMesh before = c;
  const multi::VolumeMatchStats st = multi::match_label_volumes(c, {{1, 2000.0}}, 0.1);
  EXPECT_NEAR(st.largest_shift_mm, 0.1, 1e-12);
  double moved = 0;
  for (size_t v = 0; v < c.vertices.size(); ++v) moved = std::max(moved, (c.vertices[v] - before.vertices[v]).norm());
  // Three rounds of at most 0.1 mm each.
  EXPECT_LE(moved, 3 * 0.1 + 1e-9);
  EXPECT_GT(label_volume(c, 1), 1000.0);
  EXPECT_LT(st.worst_after, st.worst_before);
}

// Moves that would make triangles cross are not kept: a slab of label 1, 10 x 10 x 0.1 mm,
// asked to hold a tenth of its volume. Its faces move 0.045 mm towards each other in a
// round, so they would cross in the second; the vertices of the triangles that would
// are held.
TEST(VolumeMatch, MovesThatCrossAreNotKept) {
  Builder b;
  const Eigen::Vector3d X(10, 0, 0), Y(0, 10, 0), Z(0, 0, 0.1);
  b.rect({0, 0, 0}, X, Y, 0, 1);  // z = 0, normal +z
  b.rect(Z, Y, X, 0, 1);          // z = 0.1, normal -z
  b.rect({0, 0, 0}, Y, Z, 0, 1);  // x = 0, normal +x
  b.rect(X, Z, Y, 0, 1);          // x = 10, normal -x
  b.rect({0, 0, 0}, Z, X, 0, 1);  // y = 0, normal +y
  b.rect(Y, X, Z, 0, 1);          // y = 10, normal -y
  TriangleMesh c = b.mesh;
  EXPECT_NEAR(label_volume(c, 1), 10.0, 1e-9);
  const multi::VolumeMatchStats st = multi::match_label_volumes(c, {{1, 1.0}}, 1.0);
  EXPECT_GT(st.frozen, 0);
  EXPECT_EQ(multi::measure_complex(c).crossing_pairs, 0);
  EXPECT_GT(label_volume(c, 1), 0.0);
}

// A thin wedge kept: label 1 a prism 20 mm long whose sloping top meets label 2's top
// face at 15.5 degrees along the edge x = 0 (a junction of the background, 1 and 2),
// label 2 a box under it, each face one square of two triangles. Label 1 asked to hold
// half its volume: its faces would move in and narrow the wedge under 15 degrees (a
// tetrahedron there would be no better). The prism's end triangles have the wedge's
// angle at that edge, so here the triangles' guard holds the moves (every vertex stays).
TEST(VolumeMatch, ThinWedgeKeepsItsAngle) {
  const double h = 20 * std::tan(15.5 * M_PI / 180);
  Builder b;
  const Eigen::Vector3d X(20, 0, 0), Y(0, 10, 0), S(20, 0, h), H(0, 0, h), Z(0, 0, 10), O(0, 0, 0);
  b.rect(O, Y, X, 1, 2, 1);                    // z = 0, normal -z: from 1 into 2
  b.rect(O, Y, S, 0, 1, 1);                    // the slope, normal down into 1
  b.rect(X, H, Y, 0, 1, 1);                    // x = 20, normal -x
  b.tri(O, X + H, X, 0, 1);                    // y = 0, normal +y
  b.tri(Y, Y + X, Y + X + H, 0, 1);            // y = 10, normal -y
  b.rect(-Z, X, Y, 0, 2, 1);                   // z = -10, normal +z
  b.rect(-Z, Y, Z, 0, 2, 1);                   // x = 0, normal +x
  b.rect(X - Z, Z, Y, 0, 2, 1);                // x = 20, normal -x
  b.rect(-Z, Z, X, 0, 2, 1);                   // y = 0, normal +y
  b.rect(Y - Z, X, Z, 0, 2, 1);                // y = 10, normal -y
  TriangleMesh c = b.mesh;
  const multi::ComplexFigures before = multi::measure_complex(c);
  ASSERT_EQ(before.regions.size(), 2u);
  for (const multi::RegionFigures& r : before.regions) ASSERT_EQ(r.defects, 0) << r.label;
  ASSERT_NEAR(before.regions[0].min_wedge_deg, 15.5, 1e-9);
  ASSERT_NEAR(label_volume(c, 1), 100 * h, 1e-9);
  const multi::VolumeMatchStats st = multi::match_label_volumes(c, {{1, 50 * h}, {2, 2000.0}}, 1.0);
  EXPECT_EQ(st.frozen, int64_t(c.vertices.size()));
  const multi::ComplexFigures after = multi::measure_complex(c);
  EXPECT_GE(after.regions[0].min_wedge_deg, 15 - 1e-9);
  EXPECT_EQ(after.crossing_pairs, 0);
}

}  // namespace
}  // namespace mpumesh
