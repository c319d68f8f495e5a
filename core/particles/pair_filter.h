// The repulsion's neighbour filter (particle_step_ref.cpp, repulsion_step): of the
// candidates in a run of grid cells, those whose pair with particle i is not beyond both
// cutoffs, !(r² >= c² max(σ_i², σ_j²)), r² summed x, y, z as the scalar code sums it.
// On the sample CT a particle has about 200 candidates of which 9 pass, so the test is
// most of the repulsion's work; the vector levels (common/simd_level.h) run it on 8
// candidates at once and keep the same candidates, in the same order, so the particles
// come out the same bytes.
#pragma once

#include <cstdint>
#include <vector>

#include "common/simd_level.h"

namespace mpumesh::particles {

// Candidates in a grid's order, coordinates and σ apart.
struct CandidateSoa {
  std::vector<double> x, y, z, sigma;
};

// Writes to `out` the indices k in [k0, k1) that pass, in increasing order, and returns
// their count; `out` must have room for k1 - k0 + 8. q is x_i, s2 = σ_i², c2 = cutoff².
uint32_t pairs_within(const CandidateSoa& a, uint32_t k0, uint32_t k1, const double q[3], double s2, double c2,
                      uint32_t* out, SimdLevel level);

}  // namespace mpumesh::particles
