#include "compute/cpu_backend.h"

#include <tbb/info.h>

#include <chrono>

namespace mpumesh {

std::string CpuBackend::device() const {
  return "CPU (" + std::to_string(tbb::info::default_concurrency()) + " threads)";
}

mc::McMesh CpuBackend::marching_cubes(const mc::McField& field) {
  auto t0 = std::chrono::steady_clock::now();
  mc::McMesh m = mc::marching_cubes_ref(field);
  kernel_ms_.clear();
  kernel_ms_["marching_cubes"] = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return m;
}

}  // namespace mpumesh
