// The multi-material sampling's steps on the GPU (shaders/complex_step.comp): the field
// (every fit, the regions' supports, the parts' contact rule) is uploaded once
// (MaterialDeviceField) and each step of a sampling is one dispatch over its particles.
#pragma once

#include <Eigen/Dense>
#include <map>
#include <memory>
#include <string>

#include "multi/complex_step_ref.h"
#include "shared/complex_abi.h"
#include "vk/buffer.h"
#include "vk/pipeline.h"

namespace mpumesh::vk {

struct MaterialDeviceField {
  MaterialDeviceField(Context& ctx, const multi::MaterialField& field);
  Eigen::Vector3d origin;  // subtracted from every position before it becomes float
  abi::ComplexPush push{};  // the field's part of the push block (count, row and step unset)
  std::unique_ptr<Buffer> leaves, offsets, leaf_ids, fits, regions, support;
};

class ComplexStepKernel {
 public:
  explicit ComplexStepKernel(Context& ctx);
  // multi::complex_steps_ref on the device (in float32): batch.out and batch.ok written.
  void run(const MaterialDeviceField& field, multi::ComplexBatch& batch, std::map<std::string, double>& kernel_ms);

 private:
  Context& ctx_;
  ComputePipeline step_;
};

}  // namespace mpumesh::vk
