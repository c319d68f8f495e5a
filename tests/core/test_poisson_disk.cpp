// The seeding's Poisson-disk subsets (core/particles/poisson_disk.h): on random points with
// random radii, every kept pair is at least the mean of its radii apart, every other point
// closer than that to a kept one (maximal), the result repeatable and different for
// another seed; visited block by block it is as dense as the plain greedy sample.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "particles/poisson_disk.h"

namespace mpumesh {
namespace {

struct Cloud {
  std::vector<Eigen::Vector3d> x;
  std::vector<double> r;
};

// n points on a sphere of radius `size` (a surface, as the candidates are), radii in [r0, r1].
Cloud sphere_cloud(size_t n, double size, double r0, double r1, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(r0, r1);
  Cloud c;
  for (size_t i = 0; i < n; ++i) {
    Eigen::Vector3d p(g(rng), g(rng), g(rng));
    c.x.push_back(size * p.normalized());
    c.r.push_back(u(rng));
  }
  return c;
}

void expect_disk_sample(const Cloud& c, const std::vector<size_t>& keep) {
  ASSERT_FALSE(keep.empty());
  EXPECT_TRUE(std::is_sorted(keep.begin(), keep.end()));
  std::vector<char> kept(c.x.size(), 0);
  for (size_t k : keep) kept[k] = 1;
  int64_t close_pairs = 0, uncovered = 0;
  for (size_t a = 0; a < keep.size(); ++a)
    for (size_t b = a + 1; b < keep.size(); ++b) {
      const size_t i = keep[a], j = keep[b];
      close_pairs += (c.x[i] - c.x[j]).norm() < 0.5 * (c.r[i] + c.r[j]);
    }
  for (size_t i = 0; i < c.x.size(); ++i) {
    if (kept[i]) continue;
    bool covered = false;
    for (size_t j : keep) covered = covered || (c.x[i] - c.x[j]).norm() < 0.5 * (c.r[i] + c.r[j]);
    uncovered += !covered;
  }
  EXPECT_EQ(close_pairs, 0);
  EXPECT_EQ(uncovered, 0);
}

TEST(PoissonDisk, KeepsAMaximalDiskSample) {
  // 40 mm sphere, radii 1-3 mm: the grid's cells are 3 mm (27 a side), its blocks of 16³
  // cells 48 mm (2 a side), so conflicts cross the blocks' borders.
  const Cloud c = sphere_cloud(6000, 40.0, 1.0, 3.0, 5);
  const std::vector<size_t> keep = particles::poisson_disk(c.x, c.r, particles::hashed_order(c.x.size(), 1));
  std::printf("%zu of %zu points kept\n", keep.size(), c.x.size());
  expect_disk_sample(c, keep);
  EXPECT_EQ(keep, particles::poisson_disk(c.x, c.r, particles::hashed_order(c.x.size(), 1)));
  EXPECT_NE(keep, particles::poisson_disk(c.x, c.r, particles::hashed_order(c.x.size(), 2)));
}

TEST(PoissonDisk, BlocksKeepTheDensity) {
  // Visited block by block, not in the hashed order alone: the sample must be as dense as
  // the plain greedy one in that order (computed here point against every kept point),
  // within 1% (0.4% measured; 1.3% with blocks of 8³ cells, 2.3% with 4³). On a 60 mm
  // sphere with 2 mm radii the grid has 61 cells and 4 blocks a side.
  const Cloud c = sphere_cloud(20000, 60.0, 2.0, 2.0, 9);
  const std::vector<uint32_t> order = particles::hashed_order(c.x.size(), 3);
  const std::vector<size_t> keep = particles::poisson_disk(c.x, c.r, order);
  std::vector<size_t> plain;
  for (uint32_t i : order) {
    bool free = true;
    for (size_t j : plain) free = free && (c.x[i] - c.x[j]).squaredNorm() >= 4.0;
    if (free) plain.push_back(i);
  }
  std::printf("%zu kept by blocks, %zu in the plain order, of %zu\n", keep.size(), plain.size(), c.x.size());
  expect_disk_sample(c, keep);
  EXPECT_NEAR(double(keep.size()) / double(plain.size()), 1.0, 0.01);
}

TEST(PoissonDisk, EmptyAndSingle) {
  EXPECT_TRUE(particles::poisson_disk({}, {}, {}).empty());
  const std::vector<size_t> one = particles::poisson_disk({Eigen::Vector3d(1, 2, 3)}, {0.5}, {0});
  EXPECT_EQ(one, std::vector<size_t>{0});
}

}  // namespace
}  // namespace mpumesh
