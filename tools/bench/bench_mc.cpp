// Benchmark: marching cubes on a volume (default: the sample CT at 226 HU) on every
// backend available, measured in the same run. Prints the median wall time of each, the
// GPU's own kernel timestamps, the ratio to the CPU path, and checks that the backends
// agree. Usage: mpumesh_bench_mc [VOLUME] [THRESHOLD] [REPEATS]
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "cpu/cpu_backend.h"
#include "io/volume_io.h"
#include "mc/marching_cubes.h"
#include "vk/vk_check.h"
#include "vulkan_backend.h"
#include "mc/marching_cubes_ref.h"

using namespace mpumesh;

namespace {

struct Timing {
  double median_ms = 0;
  std::map<std::string, double> kernel_ms;
  mc::McMesh mesh;
};

Timing measure(ComputeBackend& b, const mc::McField& field, int repeats) {
  Timing t;
  std::vector<double> ms;
  for (int r = 0; r < repeats; ++r) {
    auto t0 = std::chrono::steady_clock::now();
    t.mesh = b.marching_cubes(field);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(ms.begin(), ms.end());
  t.median_ms = ms[ms.size() / 2];
  t.kernel_ms = b.kernel_ms();
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : "/usr/share/doc/invesalius-examples/examples/Cranium.inv3";
  const double threshold = argc > 2 ? std::stod(argv[2]) : 226.0;
  const int repeats = argc > 3 ? std::max(1, std::atoi(argv[3])) : 5;
  try {
    const Volume vol = read_volume(path);
    const mc::McField field = mc::make_threshold_field(vol, {threshold});
    fmt::print("marching cubes: {} ({} x {} x {}), threshold {}, median of {} runs\n", path, vol.dims[0],
               vol.dims[1], vol.dims[2], threshold, repeats);
    CpuBackend cpu;
    const Timing c = measure(cpu, field, repeats);
    fmt::print("{:<44} {:>10} {:>10} {:>8}\n", "backend", "wall ms", "kernel ms", "vs cpu");
    fmt::print("{:<44} {:>10.1f} {:>10} {:>8}\n", cpu.device(), c.median_ms, "-", "1.00");
    fmt::print("  {} vertices, {} triangles\n", c.mesh.grid_vertices.size(), c.mesh.triangles.size());
    for (const auto& d : vk::list_devices()) {
      vk::ContextOptions opt;
      opt.device_index = d.index;
      try {
        vk::VulkanBackend gpu(opt);
        measure(gpu, field, 1);  // warm-up: pipelines, first allocations
        const Timing g = measure(gpu, field, repeats);
        double kernels = 0;
        for (const auto& [k, ms] : g.kernel_ms) kernels += ms;
        fmt::print("{:<44} {:>10.1f} {:>10.1f} {:>8.2f}\n", gpu.device(), g.median_ms, kernels,
                   c.median_ms / g.median_ms);
        for (const auto& [k, ms] : g.kernel_ms) fmt::print("  {:<20} {:8.1f} ms\n", k, ms);
        const bool same = g.mesh.triangles == c.mesh.triangles;
        fmt::print("  connectivity identical to the CPU path: {}\n", same ? "yes" : "NO");
        if (!same) return 1;
      } catch (const std::exception& e) {
        fmt::print("{:<44} failed: {}\n", d.name, e.what());
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_mc: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
