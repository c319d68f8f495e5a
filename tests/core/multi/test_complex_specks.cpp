// A complex's specks (multi/complex_specks.h) on a hand-built complex: a tetrahedron of
// label 1 with a flat one of label 2 (0.167 mm³) on its bottom face, the background
// around both.
#include <gtest/gtest.h>

#include "multi/complex_figures.h"
#include "multi/complex_specks.h"

namespace mpumesh {
namespace {

// Vertices a, b, c, d (label 1's tetrahedron) and e, 0.01 mm under the middle of abc;
// each triangle oriented from its lower label into its higher.
TriangleMesh tetrahedron_with_speck() {
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 10}, {10.0 / 3, 10.0 / 3, -0.01}};
  const uint32_t a = 0, b = 1, c = 2, d = 3, e = 4;
  m.triangles = {{a, d, b}, {a, c, d}, {b, d, c},  // (0, 1): into label 1, inward
                 {a, c, b},                        // (1, 2): from 1 down into 2
                 {a, b, e}, {b, c, e}, {c, a, e}}; // (0, 2): into label 2, inward
  m.face_labels = {{0, 1}, {0, 1}, {0, 1}, {1, 2}, {0, 2}, {0, 2}, {0, 2}};
  return m;
}

TEST(ComplexSpecks, FigureOfTheHandBuiltComplex) {
  const multi::ComplexFigures f = multi::measure_complex(tetrahedron_with_speck(), false);
  ASSERT_EQ(f.regions.size(), 2u);
  EXPECT_EQ(f.regions[0].defects, 0);
  EXPECT_EQ(f.regions[1].defects, 0);
  EXPECT_NEAR(f.regions[0].volume_mm3, 1000.0 / 6, 1e-9);
  EXPECT_NEAR(f.regions[1].volume_mm3, 50 * 0.01 / 3, 1e-9);
  // The wedges at the junction edges ab, bc, ca: label 1's the corner tetrahedron's
  // dihedral angles (90, acos(1/sqrt 3) = 54.74, 90 degrees), the speck's the slope of its
  // faces, atan(0.01 / 3.333) = 0.172 at ab and ca and atan(0.01 / 2.357) = 0.243 at bc.
  EXPECT_NEAR(f.regions[0].min_wedge_deg, 54.7356, 1e-3);
  EXPECT_EQ(f.regions[0].wedges_under_10, 0);
  EXPECT_NEAR(f.regions[1].min_wedge_deg, 0.17189, 1e-4);
  EXPECT_EQ(f.regions[1].wedges_under_10, 3);
}

// The speck shares 50 mm² with label 1 and a little more with the background, so it goes
// to the background: its three faces against it removed, the face against label 1 turned
// into label 1's own bottom face (0, 1), oriented into it, and its apex dropped.
TEST(ComplexSpecks, SpeckGoesToTheRegionItSharesMostWith) {
  TriangleMesh m = tetrahedron_with_speck();
  const multi::SpeckStats st = multi::merge_specks(m, 0.2);
  EXPECT_EQ(st.merged, 1);
  EXPECT_NEAR(st.volume_mm3, 50 * 0.01 / 3, 1e-9);
  ASSERT_EQ(m.triangles.size(), 4u);
  EXPECT_EQ(m.vertices.size(), 4u);
  for (const auto& l : m.face_labels) EXPECT_EQ(l, (std::array<int32_t, 2>{0, 1}));
  const multi::ComplexFigures f = multi::measure_complex(m, false);
  ASSERT_EQ(f.regions.size(), 1u);
  EXPECT_EQ(f.regions[0].defects, 0);
  EXPECT_NEAR(f.regions[0].volume_mm3, 1000.0 / 6, 1e-9);
  EXPECT_EQ(f.regions[0].min_wedge_deg, 360);  // no junction left
}

// A piece at or above the bound, and a bound of 0, leave the complex as it is.
TEST(ComplexSpecks, PiecesAboveTheBoundStay) {
  for (const double bound : {0.0, 0.1}) {
    TriangleMesh m = tetrahedron_with_speck();
    EXPECT_EQ(multi::merge_specks(m, bound).merged, 0);
    EXPECT_EQ(m.triangles, tetrahedron_with_speck().triangles);
    EXPECT_EQ(m.face_labels, tetrahedron_with_speck().face_labels);
  }
}

}  // namespace
}  // namespace mpumesh
