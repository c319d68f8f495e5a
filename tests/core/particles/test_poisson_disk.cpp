// The seeding's Poisson-disk subsets (core/particles/poisson_disk.h): on random points with
// random radii, every kept pair is at least the mean of its radii apart, every other point
// closer than that to a kept one (maximal), the result repeatable and different for
// another seed; visited block by block it is as dense as the plain greedy sample, and the
// blocks run in parallel give the subset of their row order.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "particles/poisson_disk.h"
#include "test_support.h"

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
    Eigen::Vector3d p = test::random_vector(g, rng);
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

// The header's rule one point at a time: blocks in row order, each block's points in
// `order`, each kept unless it conflicts with a point kept before it.
std::vector<size_t> in_row_order(const Cloud& c, const std::vector<uint32_t>& order) {
  Eigen::Vector3d lo = c.x[0], hi = lo;
  for (const auto& p : c.x) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double cell = std::max(*std::max_element(c.r.begin(), c.r.end()), (hi - lo).maxCoeff() / 96.0);
  int64_t blocks[3];
  for (int d = 0; d < 3; ++d) blocks[d] = int64_t((hi[d] - lo[d]) / cell) / 16 + 1;
  auto block_of = [&](uint32_t i) {
    int64_t b[3];
    for (int d = 0; d < 3; ++d) b[d] = int64_t((c.x[i][d] - lo[d]) / cell) / 16;
    return b[0] + blocks[0] * (b[1] + blocks[1] * b[2]);
  };
  std::vector<uint32_t> visit(order);
  std::stable_sort(visit.begin(), visit.end(), [&](uint32_t a, uint32_t b) { return block_of(a) < block_of(b); });
  std::vector<size_t> kept;
  for (uint32_t i : visit) {
    bool free = true;
    for (size_t j : kept) {
      const double r = 0.5 * (c.r[i] + c.r[j]);
      free = free && (c.x[i] - c.x[j]).squaredNorm() >= r * r;
    }
    if (free) kept.push_back(i);
  }
  std::sort(kept.begin(), kept.end());
  return kept;
}

TEST(PoissonDisk, ParallelBlocksGiveTheRowOrdersSubset) {
  // 60 mm sphere, radii 0.8-1.6 mm: cells of 1.25 mm (a 96th of the extent), 7 blocks a
  // side, run in parallel where they do not touch; the subset must be the one of the
  // blocks visited in row order, whatever the thread count.
  const Cloud c = sphere_cloud(12000, 60.0, 0.8, 1.6, 11);
  const std::vector<uint32_t> order = particles::hashed_order(c.x.size(), 4);
  const std::vector<size_t> want = in_row_order(c, order);
  for (const int threads : {1, 2, 4}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    std::vector<size_t> got;
    for (int run = 0; run < 3; ++run) {
      got = particles::poisson_disk(c.x, c.r, order);
      EXPECT_EQ(got, want) << threads << " threads, run " << run;
    }
  }
  std::printf("%zu of %zu points kept\n", want.size(), c.x.size());
  expect_disk_sample(c, want);
}

TEST(PoissonDisk, EmptyAndSingle) {
  EXPECT_TRUE(particles::poisson_disk({}, {}, {}).empty());
  const std::vector<size_t> one = particles::poisson_disk({Eigen::Vector3d(1, 2, 3)}, {0.5}, {0});
  EXPECT_EQ(one, std::vector<size_t>{0});
}

}  // namespace
}  // namespace mpumesh
