// Benchmark: stages 2 and 3 (segmentation, contours, caps, normals) on a volume (default:
// the sample CT, bone at 226 HU) on every backend available, measured in the same run.
// Prints the median time of each stage, the GPU's kernel timestamps, the ratio to the CPU
// path, and the agreement of the Chan-Vese masks. Usage:
//   mpumesh_bench_points [VOLUME] [THRESHOLD] [REPEATS]
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>

#include "cpu/cpu_backend.h"
#include "io/volume_io.h"
#include "points/slice_points.h"
#include "segment/segmentation.h"
#include "vulkan_backend.h"

using namespace mpumesh;

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct Row {
  std::map<std::string, double> ms;  // stage -> median ms
  std::map<std::string, double> kernel_ms;
  std::vector<float> cv_phi;
  size_t points = 0;
};

Row measure(ComputeBackend& b, const Volume& vol, double threshold, int repeats, bool chan_vese) {
  std::map<std::string, std::vector<double>> t;
  Row row;
  for (int r = 0; r < repeats; ++r) {
    seg::SegmentOptions opt;
    opt.threshold = {threshold};
    opt.method = seg::Method::kThreshold;
    auto t0 = Clock::now();
    const seg::Segmentation s = seg::segment(vol, opt, b);
    t["threshold segmentation"].push_back(ms_since(t0));
    t0 = Clock::now();
    const pts::SlicePoints p = pts::extract_points(s, vol);
    t["points (all)"].push_back(ms_since(t0));
    t["  contours"].push_back(1e3 * p.stats.contour_seconds);
    t["  caps"].push_back(1e3 * p.stats.cap_seconds);
    t["  normals"].push_back(1e3 * p.stats.normal_seconds);
    t["threshold + points"].push_back(t["threshold segmentation"].back() + t["points (all)"].back());
    row.points = p.cloud.size();
  }
  if (chan_vese) {
    const seg::ChanVeseStack stack =
        seg::chan_vese_stack(vol, seg::Window{}, seg::threshold_mask(vol, {threshold}));
    for (int r = 0; r < std::max(1, repeats / 2); ++r) {
      auto t0 = Clock::now();
      row.cv_phi = b.chan_vese(stack, seg::ChanVeseParams{}).phi;
      t["chan-vese (100 iterations)"].push_back(ms_since(t0));
      row.kernel_ms = b.kernel_ms();
    }
  }
  for (auto& [k, v] : t) row.ms[k] = median(v);
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : "/usr/share/doc/invesalius-examples/examples/Cranium.inv3";
  const double threshold = argc > 2 ? std::stod(argv[2]) : 226.0;
  const int repeats = argc > 3 ? std::max(1, std::atoi(argv[3])) : 5;
  try {
    const Volume vol = read_volume(path);
    fmt::print("segmentation and points: {} ({} x {} x {}), threshold {}, median of {} runs (Chan-Vese {})\n", path,
               vol.dims[0], vol.dims[1], vol.dims[2], threshold, repeats, std::max(1, repeats / 2));
    CpuBackend cpu;
    const Row c = measure(cpu, vol, threshold, repeats, true);
    fmt::print("{} points\n", c.points);
    std::vector<std::pair<std::string, Row>> rows = {{cpu.device(), c}};
    for (const auto& d : vk::list_devices()) {
      vk::ContextOptions opt;
      opt.device_index = d.index;
      try {
        vk::VulkanBackend gpu(opt);
        // Only Chan-Vese runs on the device; the other stages are the CPU path's.
        rows.emplace_back(gpu.device(), measure(gpu, vol, threshold, 1, true));
      } catch (const std::exception& e) {
        fmt::print("{}: failed: {}\n", d.name, e.what());
      }
    }
    fmt::print("\n{:<30}", "stage (ms)");
    for (const auto& [name, r] : rows) fmt::print(" {:>28.28}", name);
    fmt::print("\n");
    for (const auto& [stage, ms] : c.ms) {
      if (stage != "chan-vese (100 iterations)" && rows.size() > 1) {
        fmt::print("{:<30} {:>28.1f}\n", stage, ms);
        continue;
      }
      fmt::print("{:<30} {:>28.1f}", stage, ms);
      for (size_t i = 1; i < rows.size(); ++i) {
        const double g = rows[i].second.ms.at(stage);
        fmt::print(" {:>18.1f} ({:5.2f}x)", g, ms / g);
      }
      fmt::print("\n");
    }
    for (size_t i = 1; i < rows.size(); ++i) {
      const Row& g = rows[i].second;
      fmt::print("\n{}: kernel timestamps", rows[i].first);
      for (const auto& [k, ms] : g.kernel_ms) fmt::print("  {} {:.1f} ms", k, ms);
      int64_t agree = 0;
      double max_diff = 0;
      for (size_t p = 0; p < c.cv_phi.size(); ++p) {
        agree += (c.cv_phi[p] >= 0) == (g.cv_phi[p] >= 0);
        max_diff = std::max(max_diff, double(std::abs(c.cv_phi[p] - g.cv_phi[p])));
      }
      fmt::print("\n  Chan-Vese masks agree on {:.4f}% of voxels; max |phi_gpu - phi_cpu| = {:.3g}\n",
                 100.0 * double(agree) / double(c.cv_phi.size()), max_diff);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_points: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
