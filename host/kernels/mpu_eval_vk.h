// MPU evaluation on the GPU (shaders/mpu_eval.comp): f, ∇f and curvature at many points.
// The surface is uploaded once (MpuDeviceSurface) and stays on the device for as many
// evaluations as the caller makes; the particle kernels bind the same buffers.
#pragma once

#include <Eigen/Dense>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "mpu/mpu_eval_ref.h"
#include "shared/mpu_abi.h"
#include "vk/buffer.h"
#include "vk/pipeline.h"

namespace mpumesh::vk {

// A surface's leaves in the kernels' layout (shared/mpu_abi.h), centres relative to
// `origin`.
std::vector<abi::vec4> pack_leaves(const mpu::MpuSurface& s, const Eigen::Vector3d& origin);

struct MpuDeviceSurface {
  MpuDeviceSurface(Context& ctx, const mpu::MpuSurface& s);
  Eigen::Vector3d origin;  // subtracted from every position before it becomes float
  // A position as the kernels take it: (x - origin, w) in float.
  abi::vec4 local(const Eigen::Vector3d& x, double w = 0) const {
    const Eigen::Vector3d r = x - origin;
    return {float(r.x()), float(r.y()), float(r.z()), float(w)};
  }
  abi::MpuPush push{};     // the surface's part of the push block (count and row unset)
  std::unique_ptr<Buffer> leaves, offsets, leaf_ids;
};

class MpuEvalKernel {
 public:
  explicit MpuEvalKernel(Context& ctx);
  // Rows as mpu::evaluate_all gives them (computed in float32).
  std::vector<mpu::EvalRow> run(const MpuDeviceSurface& s, const std::vector<Eigen::Vector3d>& points,
                                std::map<std::string, double>& kernel_ms);
  // f alone (the shader's value_only mode: no Hessian, no curvature).
  std::vector<double> run_f(const MpuDeviceSurface& s, const std::vector<Eigen::Vector3d>& points,
                            std::map<std::string, double>& kernel_ms);

 private:
  Context& ctx_;
  ComputePipeline eval_;
};

}  // namespace mpumesh::vk
