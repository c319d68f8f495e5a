// Chan-Vese on the GPU: per iteration chan_vese_means.comp (one workgroup per slice) then
// chan_vese_update.comp (one invocation per pixel, all slices), ping-ponging two level-set
// buffers. Same scheme as core/segment/chan_vese_ref.cpp, in float32.
#pragma once

#include <map>
#include <string>

#include "segment/chan_vese_ref.h"
#include "vk/pipeline.h"

namespace mpumesh::vk {

class ChanVeseKernel {
 public:
  explicit ChanVeseKernel(Context& ctx);
  seg::ChanVeseResult run(const seg::ChanVeseStack& stack, const seg::ChanVeseParams& p,
                          std::map<std::string, double>& kernel_ms);

 private:
  Context& ctx_;
  ComputePipeline means_, update_;
};

}  // namespace mpumesh::vk
