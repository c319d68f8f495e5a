// One interface, one method per kernel, for the CPU path (core/cpu/cpu_backend) and the
// Vulkan path (host/vulkan_backend). Stage drivers take a ComputeBackend& and never know
// which one they hold. The kernels' data types belong to their stages and are only
// declared here: a caller includes the stage's reference header (named below) for them.
#pragma once

#include <Eigen/Dense>
#include <map>
#include <string>
#include <vector>

namespace mpumesh {

namespace mc {
struct McField;  // mc/mc_field.h
struct McMesh;   // mc/marching_cubes_ref.h
}  // namespace mc
namespace seg {
struct ChanVeseParams;  // segment/chan_vese_ref.h
struct ChanVeseStack;
struct ChanVeseResult;
}  // namespace seg
namespace mpu {
struct MpuSurface;  // mpu/mpu_surface.h
struct EvalRow;     // mpu/mpu_eval_ref.h
}  // namespace mpu
namespace particles {
struct StepParams;  // particles/particle_step_ref.h
struct ParticleState;
}  // namespace particles
namespace multi {
class MaterialField;  // multi/material_field.h
struct ComplexBatch;  // multi/complex_step_ref.h
}  // namespace multi

class ComputeBackend {
 public:
  virtual ~ComputeBackend() = default;
  // "cpu" or "vulkan".
  virtual std::string kind() const = 0;
  // Human-readable device, e.g. "CPU (2 threads)" or "llvmpipe (LLVM 15.0.6, 256 bits) [cpu]".
  virtual std::string device() const = 0;

  // Marching cubes on a padded field; see core/mc/marching_cubes_ref.h for the output.
  virtual mc::McMesh marching_cubes(const mc::McField& field) = 0;

  // Chan-Vese on every slice; see core/segment/chan_vese_ref.h.
  virtual seg::ChanVeseResult chan_vese(const seg::ChanVeseStack& stack, const seg::ChanVeseParams& p) = 0;

  // f, ∇f and curvature of an MPU surface at each point; see core/mpu/mpu_eval_ref.h.
  virtual std::vector<mpu::EvalRow> mpu_eval(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& points) = 0;

  // f alone at each point (mpu::evaluate_f; computed in float32 on a GPU).
  virtual std::vector<double> mpu_f(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& points) = 0;

  // Each particle moved onto f = 0 by p.newton_steps Newton steps, with its normal and
  // distance there, and its curvature when with_curvature (else zeros):
  // particles::project_step.
  virtual void particle_project(const mpu::MpuSurface& s, particles::ParticleState& st,
                                const particles::StepParams& p, bool with_curvature) = 0;

  // particles::local_thickness(s, x[i], n[i], max_dist[i]) for every i.
  virtual std::vector<double> thickness(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& x,
                                        const std::vector<Eigen::Vector3d>& n,
                                        const std::vector<double>& max_dist) = 0;

  // `iterations` steps of the particle system on the surface; see
  // core/particles/particle_step_ref.h.
  virtual void particle_iterations(const mpu::MpuSurface& s, particles::ParticleState& st,
                                   const particles::StepParams& p, int iterations) = 0;

  // One step of a multi-material complex's sampling for every particle of the batch,
  // written to its `out` and `ok`: multi::complex_steps_ref.
  virtual void complex_steps(const multi::MaterialField& field, multi::ComplexBatch& batch) = 0;

  // Time per kernel (ms) of the last call, measured on the device; may be empty.
  // particle_iterations and complex_steps add to it instead, so that the batches of one
  // run sum up (the Vulkan backend starts over when it uploads another surface).
  const std::map<std::string, double>& kernel_ms() const { return kernel_ms_; }

 protected:
  std::map<std::string, double> kernel_ms_;
};

}  // namespace mpumesh
