// The repulsion's pair sums (core/particles/pair_sums.h): its exponential against the C
// library's; the sums against the formulas written out with std::exp; and each vector
// level against the generic code, bit for bit, on lists whose lengths are not multiples
// of eight, with pairs beyond and at a cutoff, the particle itself and a NaN.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "common/simd_level.h"
#include "particles/pair_sums.h"

namespace mpumesh {
namespace {

using particles::PairTotals;
using particles::PairView;

TEST(PairSums, ExponentialIsWithinTwoUlpOfTheLibrarys) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> wide(-700, 0), near(-5, 0);
  double worst = 0;
  for (int k = 0; k < 200000; ++k) {
    const double x = k % 2 ? wide(rng) : near(rng);
    const double want = std::exp(x), got = particles::exp_nonpositive(x);
    worst = std::max(worst, std::abs(got - want) / (std::nextafter(want, INFINITY) - want));
  }
  std::printf("largest error over 200,000 arguments: %.2f ulp\n", worst);
  EXPECT_LE(worst, 2.0);
  EXPECT_EQ(particles::exp_nonpositive(0.0), 1.0);
  EXPECT_EQ(particles::exp_nonpositive(-1000.0), particles::exp_nonpositive(-700.0));
  EXPECT_GT(particles::exp_nonpositive(-1000.0), 0.0);
  EXPECT_TRUE(std::isnan(particles::exp_nonpositive(NAN)));
}

// Random particles around particle 0, some beyond both cutoffs.
struct Cloud {
  std::vector<double> x, sigma, inv_s2;
  std::vector<uint32_t> j;
  PairView view() const { return {x.data(), sigma.data(), inv_s2.data(), 6.0, 9.0}; }
};

Cloud cloud(size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pos(-4, 4), sig(0.5, 1.5);
  Cloud c;
  for (size_t k = 0; k < n; ++k) {
    for (int d = 0; d < 3; ++d) c.x.push_back(k == 0 ? 0.0 : pos(rng));
    c.sigma.push_back(sig(rng));
    c.inv_s2.push_back(1.0 / (c.sigma.back() * c.sigma.back()));
    c.j.push_back(uint32_t(k));
  }
  // At particle 0's cutoff (r = 3 σ_0, σ_1 smaller), within rounding.
  c.sigma[1] = 0.5 * c.sigma[0];
  c.inv_s2[1] = 1.0 / (c.sigma[1] * c.sigma[1]);
  c.x[3] = 3 * c.sigma[0], c.x[4] = 0, c.x[5] = 0;
  return c;
}

TEST(PairSums, AddUpTheFormulas) {
  const Cloud c = cloud(300, 5);
  const PairView v = c.view();
  for (uint32_t m : {0u, 1u, 2u, 9u, 64u, 300u}) {
    double E = 0, dE = 0, D[3] = {0, 0, 0}, stiff = 0;
    const double si = c.sigma[0], isi = c.inv_s2[0];
    for (uint32_t t = 0; t < m; ++t) {
      const uint32_t j = c.j[t];
      double r[3], r2 = 0;
      for (int d = 0; d < 3; ++d) r[d] = c.x[d] - c.x[3 * j + d], r2 += r[d] * r[d];
      const double sj = c.sigma[j], isj = c.inv_s2[j];
      const double eij = r2 < 9 * si * si ? 6 * std::exp(-0.5 * r2 * isi) : 0;
      const double eji = r2 < 9 * sj * sj ? 6 * std::exp(-0.5 * r2 * isj) : 0;
      const double a = eij * isi + eji * isj;
      E += eij + eji;
      dE += r2 * isi / si * eij;
      for (int d = 0; d < 3; ++d) D[d] += r[d] * a;
      stiff += std::max(r2 * (eij * isi * isi + eji * isj * isj) - a, 0.0);
    }
    const PairTotals got = particles::pair_sums(v, 0, c.j.data(), m, SimdLevel::kGeneric);
    const double tol = 1e-12 * (1 + std::abs(E));
    EXPECT_NEAR(got.E, E, tol) << m;
    EXPECT_NEAR(got.dE, dE, 1e-12 * (1 + std::abs(dE))) << m;
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(got.D[d], D[d], 1e-12 * (1 + std::abs(D[d]))) << m;
    EXPECT_NEAR(got.stiff, stiff, 1e-12 * (1 + std::abs(stiff))) << m;
    if (m >= 1) EXPECT_GE(got.E, 12.0) << "the particle itself adds 2 mu";
  }
}

class PairSumsLevels : public ::testing::TestWithParam<SimdLevel> {};

TEST_P(PairSumsLevels, GiveTheGenericBytes) {
  const SimdLevel level = GetParam();
  if (!simd_level_supported(level)) GTEST_SKIP() << simd_level_name(level) << " is not supported on this CPU";
  Cloud c = cloud(257, 7);
  c.x[3 * 200] = NAN;  // a lost particle: its pair's sums are NaN on every level alike
  const PairView v = c.view();
  int compared = 0;
  for (uint32_t i : {0u, 17u, 256u})
    for (uint32_t m : {0u, 1u, 3u, 4u, 5u, 7u, 8u, 9u, 15u, 16u, 17u, 199u, 201u, 257u}) {
      const PairTotals a = particles::pair_sums(v, i, c.j.data(), m, SimdLevel::kGeneric);
      const PairTotals b = particles::pair_sums(v, i, c.j.data(), m, level);
      ASSERT_EQ(std::memcmp(&a, &b, sizeof a), 0) << "particle " << i << ", " << m << " pairs";
      ++compared;
    }
  const PairTotals lost = particles::pair_sums(v, 0, c.j.data(), 201, level);
  EXPECT_TRUE(std::isnan(lost.D[0]));
  std::printf("%s: %d lists, the generic code's bytes\n", simd_level_name(level), compared);
}

INSTANTIATE_TEST_SUITE_P(Levels, PairSumsLevels, ::testing::Values(SimdLevel::kAvx2, SimdLevel::kAvx512),
                         [](const auto& info) { return std::string(simd_level_name(info.param)); });

}  // namespace
}  // namespace mpumesh
