// Bit-for-bit comparison of MPU evaluations, for the tests of the evaluation's paths.
#pragma once

#include <cstring>

#include "mpu/mpu_eval_ref.h"

namespace mpumesh::test {

inline bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// f, ∇f, both Hessians and the leaf count, bit for bit.
inline bool same_sample(const mpu::Sample& a, const mpu::Sample& b) {
  bool ok = same_bits(a.f, b.f) && a.leaves == b.leaves;
  for (int i = 0; i < 3; ++i) ok = ok && same_bits(a.g[i], b.g[i]);
  for (int i = 0; i < 9; ++i) ok = ok && same_bits(a.Hb.data()[i], b.Hb.data()[i]) && same_bits(a.H.data()[i], b.H.data()[i]);
  return ok;
}

}  // namespace mpumesh::test
