// The repulsion's neighbour filter (core/particles/pair_filter.h) on each vector level
// against the generic one: the same indices in the same order, on random candidates
// with pairs exactly at a cutoff, NaN coordinates and σ, and run lengths that are not
// multiples of the vector width; and whole particle runs on a fitted ellipsoid that come
// out the same bytes on every level.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "common/simd_level.h"
#include "cpu/cpu_backend.h"
#include "mpu/mpu_fit.h"
#include "particles/pair_filter.h"
#include "particles/particle_system.h"
#include "test_support.h"

namespace mpumesh {
namespace {

struct LevelGuard {
  SimdLevel saved = simd_level();
  ~LevelGuard() { set_simd_level(saved); }
};

class PairFilterLevels : public ::testing::TestWithParam<SimdLevel> {};

TEST_P(PairFilterLevels, KeepsWhatTheScalarTestKeeps) {
  const SimdLevel level = GetParam();
  if (!simd_level_supported(level)) GTEST_SKIP() << simd_level_name(level) << " is not supported on this CPU";
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> pos(-3, 3), sig(0.2, 1.2);
  particles::CandidateSoa a;
  const size_t m = 1001;
  for (size_t k = 0; k < m; ++k) {
    a.x.push_back(pos(rng));
    a.y.push_back(pos(rng));
    a.z.push_back(pos(rng));
    a.sigma.push_back(sig(rng));
  }
  const double q[3] = {0.0, -0.25, 0.5}, s2 = 0.49, c2 = 9;
  // Exactly on a cutoff (r² = c² σ_j² with σ_j² the larger); NaN in a coordinate (the
  // scalar test keeps the pair: !(NaN >= t) holds); NaN in σ_j 2.5 away (std::max(σ_i²,
  // NaN) is σ_i², so the bound is c² σ_i² = 4.41 < 6.25 and the pair is dropped, where a
  // maxpd would have made the bound NaN and kept it).
  a.x[5] = q[0] + 3.0, a.y[5] = q[1], a.z[5] = q[2], a.sigma[5] = 1.0;
  a.x[17] = NAN;
  a.x[40] = q[0] + 2.5, a.y[40] = q[1], a.z[40] = q[2], a.sigma[40] = NAN;
  size_t total = 0;
  for (uint32_t k0 : {0u, 3u, 8u, 500u})
    for (uint32_t len : {0u, 1u, 7u, 8u, 9u, 31u, 200u}) {
      const uint32_t k1 = std::min<uint32_t>(k0 + len, uint32_t(m));
      std::vector<uint32_t> ref(k1 - k0 + 8), got(k1 - k0 + 8);
      const uint32_t nr = particles::pairs_within(a, k0, k1, q, s2, c2, ref.data(), SimdLevel::kGeneric);
      const uint32_t ng = particles::pairs_within(a, k0, k1, q, s2, c2, got.data(), level);
      ASSERT_EQ(nr, ng) << k0 << " + " << len;
      for (uint32_t t = 0; t < nr; ++t) EXPECT_EQ(ref[t], got[t]);
      total += nr;
    }
  EXPECT_GT(total, 20u);
  // The cutoff case and the NaN σ are dropped, the NaN coordinate kept.
  std::vector<uint32_t> out(m + 8);
  const uint32_t n = particles::pairs_within(a, 0, uint32_t(m), q, s2, c2, out.data(), level);
  const std::vector<uint32_t> kept(out.begin(), out.begin() + n);
  EXPECT_EQ(std::count(kept.begin(), kept.end(), 5u), 0);
  EXPECT_EQ(std::count(kept.begin(), kept.end(), 17u), 1);
  EXPECT_EQ(std::count(kept.begin(), kept.end(), 40u), 0);
}

TEST_P(PairFilterLevels, ParticlesComeOutTheSameBytes) {
  const SimdLevel level = GetParam();
  if (!simd_level_supported(level)) GTEST_SKIP() << simd_level_name(level) << " is not supported on this CPU";
  LevelGuard guard;
  test::AnalyticShape ellipsoid{test::AnalyticShape::kEllipsoid, 30, 20, 10};
  const PointCloud cloud = test::sample_shape(ellipsoid, 0.5, 2.0, false);
  const mpu::MpuSurface s = mpu::fit_mpu(cloud, {});
  particles::SampleOptions o;
  o.particles = 1500;
  o.iterations = 30;
  CpuBackend cpu;
  set_simd_level(SimdLevel::kGeneric);
  const particles::ParticleState ref = particles::sample_surface(s, cloud.positions, o, cpu);
  set_simd_level(level);
  const particles::ParticleState got = particles::sample_surface(s, cloud.positions, o, cpu);
  ASSERT_EQ(ref.size(), got.size());
  for (size_t i = 0; i < ref.size(); ++i) {
    ASSERT_EQ(std::memcmp(ref.x[i].data(), got.x[i].data(), 3 * sizeof(double)), 0) << "particle " << i;
    ASSERT_EQ(std::memcmp(&ref.sigma[i], &got.sigma[i], sizeof(double)), 0) << "particle " << i;
  }
  std::printf("%s: %zu particles, the same bytes as the generic code\n", simd_level_name(level), got.size());
}

INSTANTIATE_TEST_SUITE_P(Levels, PairFilterLevels, ::testing::Values(SimdLevel::kAvx2, SimdLevel::kAvx512),
                         [](const auto& info) { return std::string(simd_level_name(info.param)); });

}  // namespace
}  // namespace mpumesh
