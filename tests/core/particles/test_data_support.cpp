// The data support: which points lie within reach of the data.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "particles/data_support.h"
#include "test_support.h"

namespace mpumesh {
namespace {

// The data support: exactly the points within the reach of some candidate are near.
TEST(DataSupport, HoldsThePointsWithinTheReach) {
  std::vector<Eigen::Vector3d> c;
  for (int k = 0; k < 500; ++k) c.push_back(10.0 * test::fibonacci_direction(k, 500));
  const double reach = 2.0;
  // Cells of the reach (2 mm), and cells of 5 mm (at most 4 along the 20 mm box).
  for (const int max_cells : {128, 4}) {
    const particles::DataSupport ds(c, reach, max_cells);
    int64_t near_tried = 0, near_missed = 0, far_held = 0, far_tried = 0;
    for (int k = 0; k < 20000; ++k) {
      const Eigen::Vector3d q = Eigen::Vector3d(particles::hash01(uint32_t(k), 0, 7, 0),
                                                particles::hash01(uint32_t(k), 0, 7, 1),
                                                particles::hash01(uint32_t(k), 0, 7, 2)) * 32.0 -
                                Eigen::Vector3d::Constant(16);
      double d = INFINITY;
      for (const auto& p : c) d = std::min(d, (p - q).norm());
      (d <= reach ? near_tried : far_tried) += 1;
      (d <= reach ? near_missed : far_held) += d <= reach ? !ds.near(q) : ds.near(q);
    }
    std::printf("reach %.1f mm, at most %d cells a side: %lld of %lld points within it missed, %lld of %lld "
                "farther held\n",
                reach, max_cells, (long long)near_missed, (long long)near_tried, (long long)far_held,
                (long long)far_tried);
    EXPECT_GT(near_tried, 2000);
    EXPECT_GT(far_tried, 5000);
    EXPECT_EQ(near_missed, 0);
    EXPECT_EQ(far_held, 0);
    EXPECT_FALSE(ds.near(Eigen::Vector3d(0, 0, 0)));    // the sphere's centre, 10 mm from all
    EXPECT_FALSE(ds.near(Eigen::Vector3d(100, 0, 0)));  // outside the grid
  }
}

}  // namespace
}  // namespace mpumesh
