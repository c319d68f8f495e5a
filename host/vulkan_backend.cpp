#include "vulkan_backend.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>

#include "common/error.h"
#include "cpu/cpu_backend.h"
#include "kernels/chan_vese_vk.h"
#include "kernels/complex_step_vk.h"
#include "kernels/marching_cubes_vk.h"
#include "kernels/mpu_eval_vk.h"
#include "kernels/particle_step_vk.h"
#include "vk/vk_check.h"

namespace mpumesh::vk {

VulkanBackend::VulkanBackend(const ContextOptions& opt) : ctx_(opt) {}
VulkanBackend::~VulkanBackend() = default;

std::string VulkanBackend::device() const { return ctx_.info().name + " [" + ctx_.info().type + "]"; }

mc::McMesh VulkanBackend::marching_cubes(const mc::McField& field) {
  if (!mc_) mc_ = std::make_unique<McKernel>(ctx_);
  kernel_ms_.clear();
  return mc_->run(field, kernel_ms_);
}

seg::ChanVeseResult VulkanBackend::chan_vese(const seg::ChanVeseStack& stack, const seg::ChanVeseParams& p) {
  if (!cv_) cv_ = std::make_unique<ChanVeseKernel>(ctx_);
  kernel_ms_.clear();
  return cv_->run(stack, p, kernel_ms_);
}

namespace {

// Which surface is resident: a hash of every leaf's centre, radius and constant term (an
// address alone could be a new surface in an old one's place).
uint64_t fingerprint(const mpu::MpuSurface& s) {
  auto mix = [](uint64_t& h, double v) {
    uint64_t b;
    std::memcpy(&b, &v, sizeof b);
    h = (h ^ b) * 1099511628211ull;
  };
  // Chunks hashed in parallel, then combined in order (6 ms a batch on one thread for the
  // sample CT's 258,581 leaves).
  constexpr size_t kChunk = 4096;
  std::vector<uint64_t> part((s.leaves.size() + kChunk - 1) / kChunk, 1469598103934665603ull);
  tbb::parallel_for(size_t(0), part.size(), [&](size_t c) {
    for (size_t i = c * kChunk; i < std::min(s.leaves.size(), (c + 1) * kChunk); ++i) {
      const auto& l = s.leaves[i];
      mix(part[c], l.centre.x());
      mix(part[c], l.centre.y());
      mix(part[c], l.centre.z());
      mix(part[c], l.radius);
      mix(part[c], l.coeffs[0]);
    }
  });
  uint64_t h = 1469598103934665603ull ^ s.leaves.size();
  for (const uint64_t p : part) h = (h ^ p) * 1099511628211ull;
  h = (h ^ s.grid.leaf_ids.size()) * 1099511628211ull;
  h = (h ^ s.grid.offsets.size()) * 1099511628211ull;
  return h;
}

}  // namespace

const MpuDeviceSurface& VulkanBackend::resident(const mpu::MpuSurface& s) {
  const uint64_t id = fingerprint(s);
  if (!resident_ || resident_id_ != id) {
    resident_.reset();  // the old one's memory first
    resident_ = std::make_unique<MpuDeviceSurface>(ctx_, s);
    resident_id_ = id;
    kernel_ms_.clear();
  }
  return *resident_;
}

std::vector<mpu::EvalRow> VulkanBackend::mpu_eval(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& points) {
  if (!mpu_) mpu_ = std::make_unique<MpuEvalKernel>(ctx_);
  const MpuDeviceSurface& dev = resident(s);
  kernel_ms_.clear();
  return mpu_->run(dev, points, kernel_ms_);
}

std::vector<double> VulkanBackend::mpu_f(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& points) {
  if (!mpu_) mpu_ = std::make_unique<MpuEvalKernel>(ctx_);
  const MpuDeviceSurface& dev = resident(s);
  kernel_ms_.clear();
  return mpu_->run_f(dev, points, kernel_ms_);
}

// The particle calls add to the kernel times, so that a whole sampling run's show.
void VulkanBackend::particle_project(const mpu::MpuSurface& s, particles::ParticleState& st,
                                     const particles::StepParams& p, bool with_curvature) {
  if (!particles_) particles_ = std::make_unique<ParticleKernel>(ctx_);
  particles_->project(resident(s), st, p, with_curvature, kernel_ms_);
}

std::vector<double> VulkanBackend::thickness(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& x,
                                             const std::vector<Eigen::Vector3d>& n,
                                             const std::vector<double>& max_dist) {
  if (!particles_) particles_ = std::make_unique<ParticleKernel>(ctx_);
  return particles_->thickness(resident(s), x, n, max_dist, kernel_ms_);
}

void VulkanBackend::particle_iterations(const mpu::MpuSurface& s, particles::ParticleState& st,
                                        const particles::StepParams& p, int iterations) {
  if (!particles_) particles_ = std::make_unique<ParticleKernel>(ctx_);
  particles_->run(resident(s), st, p, iterations, kernel_ms_);
}

void VulkanBackend::complex_steps(const multi::MaterialField& field, multi::ComplexBatch& batch) {
  if (!complex_) complex_ = std::make_unique<ComplexStepKernel>(ctx_);
  if (!field_ || field_id_ != field.id()) {
    field_.reset();  // the old one's memory first
    field_ = std::make_unique<MaterialDeviceField>(ctx_, field);
    field_id_ = field.id();
  }
  complex_->run(*field_, batch, kernel_ms_);
}

BackendChoice make_backend(const std::string& name, int device_index) {
  BackendChoice c;
  if (name == "cpu") {
    c.backend = std::make_unique<CpuBackend>();
    return c;
  }
  if (name == "gpu") {
    ContextOptions opt;
    opt.device_index = device_index;
    c.backend = std::make_unique<VulkanBackend>(opt);
    return c;
  }
  if (name != "auto") throw InputError("--backend: '" + name + "' is not cpu, gpu or auto");
  try {
    ContextOptions opt;
    opt.device_index = device_index;
    opt.hardware_only = device_index < 0;
    c.backend = std::make_unique<VulkanBackend>(opt);
  } catch (const NoVulkanDevice& e) {
    c.backend = std::make_unique<CpuBackend>();
    c.note = std::string("no hardware Vulkan device (") + e.what() + "): using the native CPU path";
  } catch (const VulkanError& e) {
    c.backend = std::make_unique<CpuBackend>();
    c.note = std::string("Vulkan device creation failed (") + e.what() + "): using the native CPU path";
  }
  return c;
}

}  // namespace mpumesh::vk
