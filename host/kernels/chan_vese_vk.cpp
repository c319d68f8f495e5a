#include "kernels/chan_vese_vk.h"

#include <stdexcept>

#include "common/error.h"
#include "chan_vese_means.spv.h"
#include "chan_vese_update.spv.h"
#include "shared/chan_vese_abi.h"
#include "vk/buffer.h"
#include "vk/command.h"

namespace mpumesh::vk {
namespace {

const std::vector<Binding> kMeansBindings = {{CV_BIND_U, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                                             {CV_BIND_PHI_IN, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                                             {CV_BIND_MEANS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}};
const std::vector<Binding> kUpdateBindings = {{CV_BIND_U, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                                              {CV_BIND_PHI_IN, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                                              {CV_BIND_PHI_OUT, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                                              {CV_BIND_MEANS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}};

// Iterations recorded per command buffer: each dispatch takes a descriptor set from its
// pipeline's pool (64 sets) and two timestamps (256 per recorder).
constexpr int kIterationsPerSubmit = 32;

}  // namespace

ChanVeseKernel::ChanVeseKernel(Context& ctx)
    : ctx_(ctx),
      means_(ctx, kSpv_chan_vese_means, kMeansBindings, sizeof(abi::CvPush), default_workgroup_size(ctx)),
      update_(ctx, kSpv_chan_vese_update, kUpdateBindings, sizeof(abi::CvPush), default_workgroup_size(ctx)) {}

seg::ChanVeseResult ChanVeseKernel::run(const seg::ChanVeseStack& s, const seg::ChanVeseParams& p,
                                        std::map<std::string, double>& kernel_ms) {
  seg::validate(p);
  const uint64_t n = uint64_t(s.slice_pixels()) * uint64_t(s.nz);
  MPUMESH_ASSERT(s.u.size() == n && s.phi.size() == n, "Chan-Vese stack sizes");
  if (n >= (uint64_t(1) << 32)) throw std::length_error("stack too large for the GPU Chan-Vese (2^32 pixels)");
  if (uint64_t(s.nz) > ctx_.limits().maxComputeWorkGroupCount[0])
    throw std::length_error("too many slices for one Chan-Vese dispatch");
  seg::ChanVeseResult r;
  r.c1.assign(size_t(s.nz), CV_EMPTY_C1);
  r.c2.assign(size_t(s.nz), CV_EMPTY_C2);
  if (n == 0) return r;
  Buffer u(ctx_, n * 4, kStorage), a(ctx_, n * 4, kStorage), b(ctx_, n * 4, kStorage),
      means(ctx_, uint64_t(s.nz) * sizeof(abi::vec4), kStorage);
  u.upload(s.u.data(), n * 4);
  a.upload(s.phi.data(), n * 4);
  const Grid pixels = grid_for(ctx_, n, update_.workgroup_size());
  abi::CvPush push{};
  push.nx = uint32_t(s.nx);
  push.ny = uint32_t(s.ny);
  push.nz = uint32_t(s.nz);
  push.row = pixels.row;
  push.lambda1 = float(p.lambda1);
  push.lambda2 = float(p.lambda2);
  push.mu = float(p.mu);
  push.nu = float(p.nu);
  push.dt = float(p.dt);
  push.epsilon = float(p.epsilon);
  push.eta = float(p.eta);
  Grid slices;
  slices.groups_x = uint32_t(s.nz);
  Buffer* cur = &a;
  Buffer* next = &b;
  for (int done = 0; done < p.iterations;) {
    Recorder rec(ctx_);
    for (int it = 0; it < kIterationsPerSubmit && done < p.iterations; ++it, ++done) {
      const Buffer* mb[] = {&u, cur, &means};
      rec.dispatch(means_, mb, &push, slices, "chan_vese_means");
      rec.barrier();
      const Buffer* ub[] = {&u, cur, next, &means};
      rec.dispatch(update_, ub, &push, pixels, "chan_vese_update");
      rec.barrier();
      std::swap(cur, next);
    }
    rec.submit_and_wait(kernel_ms);
  }
  r.phi.resize(n);
  cur->download(r.phi.data(), n * 4);
  if (p.iterations > 0) {
    const auto m = means.read<abi::vec4>(size_t(s.nz));
    for (size_t k = 0; k < m.size(); ++k) {
      r.c1[k] = m[k].x;
      r.c2[k] = m[k].y;
    }
  }
  return r;
}

}  // namespace mpumesh::vk
