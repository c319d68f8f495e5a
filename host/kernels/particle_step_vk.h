// The particle iterations on the GPU: per iteration the neighbour grid
// (particle_step_grid_count.comp, the scan, particle_step_grid_scatter.comp), then
// particle_step_repulsion.comp and particle_step_project.comp, all recorded into one command buffer
// for a batch of iterations; the state is uploaded before and read back after (the
// population is decided on the CPU between batches, see core/particles/particle_system.h).
#pragma once

#include <map>
#include <string>

#include "kernels/mpu_eval_vk.h"
#include "kernels/scan_vk.h"
#include "particles/particle_step_ref.h"

namespace mpumesh::vk {

class ParticleKernel {
 public:
  explicit ParticleKernel(Context& ctx);
  void run(const MpuDeviceSurface& s, particles::ParticleState& st, const particles::StepParams& p, int iterations,
           std::map<std::string, double>& kernel_ms);
  // particle_step_project.comp alone, with the curvature when asked: particles::project_step.
  void project(const MpuDeviceSurface& s, particles::ParticleState& st, const particles::StepParams& p,
               bool with_curvature, std::map<std::string, double>& kernel_ms);
  // particle_step_thickness.comp: particles::local_thickness for every point.
  std::vector<double> thickness(const MpuDeviceSurface& s, const std::vector<Eigen::Vector3d>& x,
                                const std::vector<Eigen::Vector3d>& n, const std::vector<double>& max_dist,
                                std::map<std::string, double>& kernel_ms);

 private:
  Context& ctx_;
  ComputePipeline count_, scatter_, repulsion_, project_, thickness_;
  ScanKernel scan_;
};

}  // namespace mpumesh::vk
