// The repulsion's sums over one particle's pairs (particle_step_ref.h, step 2, eq. 11 and
// 12), eight pairs at a time. Pair t of a particle's list goes to lane t mod 8; each
// lane keeps its own running sums, and the lanes are added at the end in a fixed tree
// ((l0 + l4) + (l2 + l6)) + ((l1 + l5) + (l3 + l7)). The exponentials are exp_nonpositive
// below, not the C library's: the generic code, AVX2 (two 4-lane halves) and AVX-512 then
// do the same operations in the same order, with no fused multiply-add, and every level
// gives the same bytes (common/simd_level.h).
//
// On the sample CT a particle has about 9 pairs within the cutoffs; the scalar loop spent
// most of its time in two calls of exp per pair and their branches.
#pragma once

#include <cstdint>

#include "common/simd_level.h"

namespace mpumesh::particles {

// e^x for x ≤ 0: x clamped at -700 (e^-700 is 1e-304; the repulsion's terms that far out
// are cut anyway), n = round(x / ln 2), r = x - n ln 2 in two parts (Cody and Waite),
// e^r by its Taylor polynomial of degree 13 (truncation below 1e-17 for |r| ≤ ln 2 / 2),
// times 2^n. Within 2 ulp of e^x (tests/core/particles/test_pair_sums.cpp). NaN stays NaN.
double exp_nonpositive(double x);

// The particles, as plain arrays: positions (x, y, z per particle), σ and 1 / σ².
struct PairView {
  const double* x;
  const double* sigma;
  const double* inv_s2;
  double mu, c2;  // μ and cutoff²
};

// Particle i's sums: E, ∂E/∂σ_i, D / σ_i² (x, y, z) and the radial stiffness.
struct PairTotals {
  double E = 0, dE = 0, D[3] = {0, 0, 0}, stiff = 0;
};

// Over the pairs (i, j[t]) for t < m. Each term is cut at its own particle's cutoff
// (r² < c² σ²); a pair beyond both adds zeros, and j = i adds 2μ to E (the caller takes
// it off).
PairTotals pair_sums(const PairView& v, uint32_t i, const uint32_t* j, uint32_t m, SimdLevel level);

}  // namespace mpumesh::particles
