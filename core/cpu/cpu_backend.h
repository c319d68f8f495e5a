// The native CPU path: the reference kernels, threaded with TBB. It is what a machine
// without a GPU runs, so its loops are kept vectorisable; it is also the oracle that the
// shaders are tested against.
#pragma once

#include "compute/compute_backend.h"

namespace mpumesh {

class CpuBackend : public ComputeBackend {
 public:
  std::string kind() const override { return "cpu"; }
  std::string device() const override;
  mc::McMesh marching_cubes(const mc::McField& field) override;
  seg::ChanVeseResult chan_vese(const seg::ChanVeseStack& stack, const seg::ChanVeseParams& p) override;
  std::vector<mpu::EvalRow> mpu_eval(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& points) override;
  std::vector<double> mpu_f(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& points) override;
  void particle_project(const mpu::MpuSurface& s, particles::ParticleState& st, const particles::StepParams& p,
                        bool with_curvature) override;
  std::vector<double> thickness(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& x,
                                const std::vector<Eigen::Vector3d>& n, const std::vector<double>& max_dist) override;
  void particle_iterations(const mpu::MpuSurface& s, particles::ParticleState& st, const particles::StepParams& p,
                           int iterations) override;
  void complex_steps(const multi::MaterialField& field, multi::ComplexBatch& batch) override;
};

}  // namespace mpumesh
