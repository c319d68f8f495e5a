// The arithmetic of the CPU path's MPU evaluation (core/mpu/mpu_eval_ref.h): double
// precision (the reference, and the default), or single precision, whose kernels
// (core/mpu/mpu_eval_simd.h) take 16 leaves a step where the double ones take 8 and read
// leaf records half as long. The support test, which decides the leaves that hold a
// point, stays in double precision, so both sum the same leaves; the float path's f,
// normal and curvature differ from the reference's by the amounts
// tests/core/mpu/test_mpu_eval_f32.cpp states. Every vector level (common/simd_level.h)
// gives the same bytes within one precision. MPUMESH_EVAL=float32 or float64 sets the
// starting value; `run --cpu-eval` sets it for a run.
#pragma once

#include <optional>
#include <string>

namespace mpumesh {

enum class EvalPrecision { kDouble, kFloat };

const char* eval_precision_name(EvalPrecision p);  // "float64", "float32"
std::optional<EvalPrecision> parse_eval_precision(const std::string& name);
EvalPrecision eval_precision();
// Surfaces indexed before a change keep their leaf records: index them again
// (mpu::index_spheres) before evaluating them in the other precision.
void set_eval_precision(EvalPrecision p);

}  // namespace mpumesh
