// The Vulkan implementation of ComputeBackend, and the choice of backend that the tools
// offer: --backend cpu | gpu | auto. `auto` takes a hardware Vulkan device when there is
// one and the native CPU path otherwise (lavapipe runs shaders well below vectorised C++;
// it serves for validation, by `--backend gpu`).
#pragma once

#include <memory>
#include <string>

#include "compute/compute_backend.h"
#include "vk/context.h"

namespace mpumesh::vk {

class McKernel;
class ChanVeseKernel;
class MpuEvalKernel;
class ParticleKernel;
class ComplexStepKernel;
struct MpuDeviceSurface;
struct MaterialDeviceField;

class VulkanBackend : public ComputeBackend {
 public:
  explicit VulkanBackend(const ContextOptions& opt = {});
  ~VulkanBackend() override;
  std::string kind() const override { return "vulkan"; }
  std::string device() const override;
  mc::McMesh marching_cubes(const mc::McField& field) override;
  seg::ChanVeseResult chan_vese(const seg::ChanVeseStack& stack, const seg::ChanVeseParams& p) override;
  // The MPU kernels keep the last surface on the device (resident()): the calls of one
  // run upload it once.
  std::vector<mpu::EvalRow> mpu_eval(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& points) override;
  std::vector<double> mpu_f(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& points) override;
  void particle_project(const mpu::MpuSurface& s, particles::ParticleState& st, const particles::StepParams& p,
                        bool with_curvature) override;
  std::vector<double> thickness(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& x,
                                const std::vector<Eigen::Vector3d>& n, const std::vector<double>& max_dist) override;
  void particle_iterations(const mpu::MpuSurface& s, particles::ParticleState& st, const particles::StepParams& p,
                           int iterations) override;
  // The field stays on the device while the calls name the same one (MaterialField::id).
  void complex_steps(const multi::MaterialField& field, multi::ComplexBatch& batch) override;
  Context& context() { return ctx_; }

 private:
  // The surface on the device, uploaded when it is not the resident one (which clears the
  // kernel times).
  const MpuDeviceSurface& resident(const mpu::MpuSurface& s);

  Context ctx_;
  std::unique_ptr<McKernel> mc_;
  std::unique_ptr<ChanVeseKernel> cv_;
  std::unique_ptr<MpuEvalKernel> mpu_;
  std::unique_ptr<ParticleKernel> particles_;
  std::unique_ptr<MpuDeviceSurface> resident_;
  uint64_t resident_id_ = 0;
  std::unique_ptr<ComplexStepKernel> complex_;
  std::unique_ptr<MaterialDeviceField> field_;
  uint64_t field_id_ = 0;
};

struct BackendChoice {
  std::unique_ptr<ComputeBackend> backend;
  std::string note;  // why this one (e.g. "no hardware Vulkan device: using the CPU path")
};

// name: "cpu", "gpu" or "auto"; device_index -1 for the default device.
// "gpu" throws NoVulkanDevice when no Vulkan device can be created.
BackendChoice make_backend(const std::string& name, int device_index = -1);

}  // namespace mpumesh::vk
