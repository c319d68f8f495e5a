#include "cpu/cpu_backend.h"

#include <tbb/info.h>
#include <tbb/parallel_for.h>

#include <chrono>

#include "mc/marching_cubes_ref.h"
#include "mpu/mpu_eval_ref.h"
#include "multi/complex_step_ref.h"
#include "particles/particle_step_ref.h"
#include "segment/chan_vese_ref.h"

namespace mpumesh {

std::string CpuBackend::device() const {
  return "CPU (" + std::to_string(tbb::info::default_concurrency()) + " threads)";
}

namespace {
double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

mc::McMesh CpuBackend::marching_cubes(const mc::McField& field) {
  auto t0 = std::chrono::steady_clock::now();
  mc::McMesh m = mc::marching_cubes_ref(field);
  kernel_ms_.clear();
  kernel_ms_["marching_cubes"] = ms_since(t0);
  return m;
}

seg::ChanVeseResult CpuBackend::chan_vese(const seg::ChanVeseStack& stack, const seg::ChanVeseParams& p) {
  auto t0 = std::chrono::steady_clock::now();
  seg::ChanVeseResult r = seg::chan_vese_ref(stack, p);
  kernel_ms_.clear();
  kernel_ms_["chan_vese"] = ms_since(t0);
  return r;
}

std::vector<mpu::EvalRow> CpuBackend::mpu_eval(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& points) {
  auto t0 = std::chrono::steady_clock::now();
  std::vector<mpu::EvalRow> rows = mpu::evaluate_all(s, points);
  kernel_ms_.clear();
  kernel_ms_["mpu_eval"] = ms_since(t0);
  return rows;
}

std::vector<double> CpuBackend::mpu_f(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& points) {
  std::vector<double> f(points.size());
  // In cache order: the triangulation asks for f at Voronoi vertices in the order of
  // CGAL's cells.
  const std::vector<size_t> order = mpu::cache_order(s, points);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t o = r.begin(); o != r.end(); ++o) f[order[o]] = mpu::evaluate_f(s, points[order[o]]);
  });
  return f;
}

void CpuBackend::particle_project(const mpu::MpuSurface& s, particles::ParticleState& st,
                                  const particles::StepParams& p, bool with_curvature) {
  particles::project_step(s, st, p, with_curvature);
}

std::vector<double> CpuBackend::thickness(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& x,
                                          const std::vector<Eigen::Vector3d>& n, const std::vector<double>& max_dist) {
  return particles::thickness_step(s, x, n, max_dist);
}

void CpuBackend::particle_iterations(const mpu::MpuSurface& s, particles::ParticleState& st,
                                     const particles::StepParams& p, int iterations) {
  // Accumulated over calls, so a whole run's time shows.
  auto t0 = std::chrono::steady_clock::now();
  particles::particle_iterations(s, st, p, iterations);
  kernel_ms_["particles"] += ms_since(t0);
}

void CpuBackend::complex_steps(const multi::MaterialField& field, multi::ComplexBatch& batch) {
  auto t0 = std::chrono::steady_clock::now();
  multi::complex_steps_ref(field, batch);
  kernel_ms_["complex_step"] += ms_since(t0);
}

}  // namespace mpumesh
