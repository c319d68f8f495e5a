// The face-connected components of a mask, counted.
#include <gtest/gtest.h>

#include "segment/components.h"
#include "test_support.h"

namespace mpumesh {
namespace {

TEST(Components, CountsFaceConnectedRegions) {
  // Two voxels touching only along an edge are two components (6-connectivity).
  std::vector<uint8_t> m(27, 0);
  m[0] = 1;                  // (0,0,0)
  m[1 + 3 * 1] = 1;          // (1,1,0): edge-adjacent to (0,0,0)
  m[2 + 3 * (2 + 3 * 2)] = 1;  // (2,2,2)
  m[2 + 3 * (2 + 3 * 1)] = 1;  // (2,2,1): face-adjacent to (2,2,2)
  const auto c = seg::mask_components(m, {3, 3, 3});
  EXPECT_EQ(c.count, 3);
  EXPECT_EQ(c.sizes.front(), 2);
}

}  // namespace
}  // namespace mpumesh
