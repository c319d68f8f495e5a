// Exclusive prefix sum of a uint buffer on the GPU (shaders/scan_blocks.comp,
// shaders/scan_add.comp): blocks of 4 * workgroup elements, their totals scanned
// recursively, then added back. CPU reference: std::exclusive_scan.
#pragma once

#include <memory>
#include <vector>

#include "vk/buffer.h"
#include "vk/command.h"
#include "vk/pipeline.h"

namespace mpumesh::vk {

class ScanKernel {
 public:
  explicit ScanKernel(Context& ctx);
  // Records the scan of data[0, count) in place. Temporary buffers go into `scratch` and
  // must outlive the submission.
  void record(Recorder& rec, Buffer& data, uint32_t count, std::vector<std::unique_ptr<Buffer>>& scratch);

 private:
  Context& ctx_;
  ComputePipeline blocks_, add_;
};

}  // namespace mpumesh::vk
