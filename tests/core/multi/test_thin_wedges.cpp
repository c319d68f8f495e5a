// The trimming of thin wedges on a hand-built labelled triangulation: a short edge on the z
// axis with a ring of points around it in the plane z = 0, so that every cell holds the
// edge; the cells are labelled by the angle they span around it.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "multi/thin_wedges.h"

namespace mpumesh::multi {
namespace {

using namespace labelled;

struct Ring {
  Dt dt;
  std::vector<Eigen::Vector3d> pts;
};

// The edge (0, 0, -0.3)-(0, 0, 0.3) and ring points at `deg`, radii slightly apart (no four
// points cospherical); each cell labelled by `region_at` of the angle of its centroid.
template <class RegionAt>
Ring ring(const std::vector<double>& deg, RegionAt region_at) {
  Ring r;
  r.pts = {{0, 0, -0.3}, {0, 0, 0.3}};
  for (size_t k = 0; k < deg.size(); ++k) {
    const double a = deg[k] * std::numbers::pi / 180, radius = 1 + 0.001 * double(k);
    r.pts.emplace_back(radius * std::cos(a), radius * std::sin(a), 0);
  }
  for (uint32_t i = 0; i < r.pts.size(); ++i)
    r.dt.insert(Point(r.pts[i].x(), r.pts[i].y(), r.pts[i].z()))->info() = i;
  for (auto c = r.dt.finite_cells_begin(); c != r.dt.finite_cells_end(); ++c) {
    Eigen::Vector3d m = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) m += r.pts[c->vertex(k)->info()] / 4;
    double a = std::atan2(m.y(), m.x()) * 180 / std::numbers::pi;
    c->info().region = region_at(a < 0 ? a + 360 : a);
  }
  return r;
}

// The cells of region r and the angle they span around the z axis's edge (degrees).
std::pair<int, double> span_of(const Ring& r, int region) {
  int cells = 0;
  double deg = 0;
  for (auto c = r.dt.finite_cells_begin(); c != r.dt.finite_cells_end(); ++c) {
    if (c->info().region != region) continue;
    ++cells;
    std::vector<Eigen::Vector3d> p;
    for (int k = 0; k < 4; ++k)
      if (c->vertex(k)->info() >= 2) p.push_back(r.pts[c->vertex(k)->info()]);
    deg += std::acos(p[0].normalized().dot(p[1].normalized())) * 180 / std::numbers::pi;
  }
  return {cells, deg};
}

const std::vector<double> kRingDeg = {0, 4, 8, 16, 60, 120, 180, 240, 300};

TEST(ThinWedges, RingHoldsTheEdge) {
  const Ring r = ring(kRingDeg, [](double) { return 1; });
  EXPECT_EQ(r.dt.number_of_finite_cells(), kRingDeg.size());  // each cell on the edge
}

// Tissue (2) spans 8 degrees between background (0, 8-180) and bone (1, 180-360): it
// goes to the bone, whose run is wider.
TEST(ThinWedges, ThinRunGoesToTheWiderNeighbour) {
  Ring r = ring(kRingDeg, [](double a) { return a < 8 ? 2 : a < 180 ? 0 : 1; });
  ASSERT_EQ(span_of(r, 2).first, 2);
  EXPECT_NEAR(span_of(r, 2).second, 8, 1e-9);
  const WedgeTrimStats st = trim_thin_wedges(r.dt, r.pts);
  EXPECT_EQ(st.cells, 2);
  EXPECT_EQ(st.rounds, 1);
  EXPECT_EQ(span_of(r, 2).first, 0);
  EXPECT_NEAR(span_of(r, 1).second, 188, 1e-9);
  EXPECT_NEAR(span_of(r, 0).second, 172, 1e-9);
}

// 16 degrees of tissue are kept.
TEST(ThinWedges, WideRunIsKept) {
  Ring r = ring(kRingDeg, [](double a) { return a < 16 ? 2 : a < 180 ? 0 : 1; });
  EXPECT_EQ(trim_thin_wedges(r.dt, r.pts).cells, 0);
  EXPECT_NEAR(span_of(r, 2).second, 16, 1e-9);
}

// The background is never trimmed: 8 degrees of it between two labels stay.
TEST(ThinWedges, BackgroundIsNotTrimmed) {
  Ring r = ring(kRingDeg, [](double a) { return a < 8 ? 0 : a < 180 ? 2 : 1; });
  EXPECT_EQ(trim_thin_wedges(r.dt, r.pts).cells, 0);
  EXPECT_NEAR(span_of(r, 0).second, 8, 1e-9);
}

// The least wedge is the caller's: with 5 degrees, the 8 degree run stays.
TEST(ThinWedges, LeastWedgeIsAParameter) {
  Ring r = ring(kRingDeg, [](double a) { return a < 8 ? 2 : a < 180 ? 0 : 1; });
  EXPECT_EQ(trim_thin_wedges(r.dt, r.pts, 5).cells, 0);
}

}  // namespace
}  // namespace mpumesh::multi
