// core/points/contours: marching squares on small fields with known answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "points/contours.h"

namespace mpumesh {
namespace {

// A padded field from a predicate on pixel centres: +1 inside, -1 outside, -1 border ring.
std::vector<float> field_from(int64_t nx, int64_t ny, auto inside) {
  std::vector<float> f(size_t(nx * ny), -1.0f);
  for (int64_t j = 1; j + 1 < ny; ++j)
    for (int64_t i = 1; i + 1 < nx; ++i) f[size_t(i + nx * j)] = inside(double(i), double(j)) ? 1.0f : -1.0f;
  return f;
}

TEST(MarchingSquares, DiskIsOneCounterClockwiseContour) {
  const int64_t n = 40;
  // A smooth field: r - |p - c|, so the contour is the circle itself.
  std::vector<float> f(size_t(n * n));
  for (int64_t j = 0; j < n; ++j)
    for (int64_t i = 0; i < n; ++i) f[size_t(i + n * j)] = float(12.0 - std::hypot(i - 19.3, j - 20.1));
  const auto cs = pts::marching_squares(f.data(), n, n);
  ASSERT_EQ(cs.size(), 1u);
  EXPECT_NEAR(cs[0].signed_area(), M_PI * 144.0, 0.01 * M_PI * 144.0);
  for (const auto& p : cs[0].points) EXPECT_NEAR(std::hypot(p.x() - 19.3, p.y() - 20.1), 12.0, 0.05);
}

TEST(MarchingSquares, HolesRunClockwiseAndSaddlesSeparateInsideCorners) {
  const int64_t n = 30;
  auto ring = field_from(n, n, [](double x, double y) {
    const double r = std::hypot(x - 15, y - 15);
    return r < 10 && r > 5;
  });
  auto cs = pts::marching_squares(ring.data(), n, n);
  ASSERT_EQ(cs.size(), 2u);
  std::sort(cs.begin(), cs.end(), [](const auto& a, const auto& b) { return a.signed_area() > b.signed_area(); });
  EXPECT_GT(cs[0].signed_area(), 0);  // outer boundary
  EXPECT_LT(cs[1].signed_area(), 0);  // hole
  // A checkerboard 2 x 2: the diagonal inside pixels are separate regions.
  auto checker = field_from(4, 4, [](double x, double y) { return (int(x) + int(y)) % 2 == 0; });
  cs = pts::marching_squares(checker.data(), 4, 4);
  ASSERT_EQ(cs.size(), 2u);
  for (const auto& c : cs) {
    EXPECT_EQ(c.points.size(), 4u);
    EXPECT_GT(c.signed_area(), 0);
  }
}

}  // namespace
}  // namespace mpumesh
