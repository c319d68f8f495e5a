// Marching cubes on the GPU: marching_cubes_classify.comp, two scans (vertex and triangle offsets),
// then marching_cubes_generate.comp. Output identical in order and connectivity to
// core/mc/marching_cubes_ref.cpp; positions agree to float precision.
#pragma once

#include <map>
#include <memory>
#include <string>

#include "kernels/scan_vk.h"
#include "mc/marching_cubes_ref.h"

namespace mpumesh::vk {

class McKernel {
 public:
  explicit McKernel(Context& ctx);
  mc::McMesh run(const mc::McField& field, std::map<std::string, double>& kernel_ms);

 private:
  Context& ctx_;
  ComputePipeline classify_, generate_;
  ScanKernel scan_;
  std::unique_ptr<Buffer> table_;
};

}  // namespace mpumesh::vk
