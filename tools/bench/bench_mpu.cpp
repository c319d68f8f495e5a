// Benchmark: stage 4 (MPU fit) and stage 5 (evaluation with curvature) on the sample CT's
// points (bone at 226 HU), every backend measured in the same run. Prints the fit time
// and leaf count for both local fits, |f| at the input points, and the evaluation
// throughput (points per second with f, ∇f, the blended Hessian and curvature) for 10^6
// points near the surface: the CPU path (the widest instruction set, then the others, then
// with the Hessian of f as well), then each Vulkan device (kernel timestamps and wall time,
// with the ratio to the CPU path); the CPU path in single precision at each instruction
// set, with its largest differences from the double path. Usage:
//   mpumesh_bench_mpu [VOLUME] [THRESHOLD] [QUERY_POINTS] [REPEATS]
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>

#include "cpu/cpu_backend.h"
#include "io/volume_io.h"
#include "kernels/mpu_eval_vk.h"
#include "common/eval_precision.h"
#include "common/simd_level.h"
#include "mpu/mpu_eval_ref.h"
#include "mpu/mpu_fit.h"
#include "points/slice_points.h"
#include "segment/segmentation.h"
#include "vulkan_backend.h"

using namespace mpumesh;

namespace {

using Clock = std::chrono::steady_clock;
double sec_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, size_t(q * double(v.size())))];
}

// Both local fits, timed; returns the orthopoly fit.
mpu::MpuSurface fit_table(const PointCloud& cloud, CpuBackend& cpu, int repeats) {
  mpu::MpuSurface surface;
  fmt::print("{:<10} {:>9} {:>9} {:>9} {:>9} {:>12} {:>12}\n", "local fit", "fit s", "leaves", "gen.quad",
             "over eps", "|f| p50 mm", "|f| p95 mm");
  for (auto kind : {mpu::LocalFit::kOrthopoly, mpu::LocalFit::kQuadric}) {
    mpu::FitOptions opt;
    opt.local_fit = kind;
    std::vector<double> t;
    mpu::FitStats st;
    mpu::MpuSurface s;
    for (int r = 0; r < repeats; ++r) {
      s = mpu::fit_mpu(cloud, opt, &st);
      t.push_back(st.seconds);
    }
    const auto rows = cpu.mpu_eval(s, cloud.positions);
    std::vector<double> f;
    for (const auto& row : rows) f.push_back(std::abs(row.f));
    fmt::print("{:<10} {:>9.2f} {:>9} {:>9} {:>9} {:>12.4f} {:>12.4f}\n", mpu::local_fit_name(kind), median(t),
               st.leaves, st.general_quadric, st.over_eps, percentile(f, 0.5), percentile(f, 0.95));
    if (kind == mpu::LocalFit::kOrthopoly) surface = std::move(s);
  }
  return surface;
}

// Query points: input points moved up to ±1 mm along their normals.
std::vector<Eigen::Vector3d> query_points(const PointCloud& cloud, size_t queries) {
  std::mt19937 rng(1);
  std::uniform_int_distribution<size_t> pick(0, cloud.size() - 1);
  std::uniform_real_distribution<double> off(-1.0, 1.0);
  std::vector<Eigen::Vector3d> q(queries);
  for (auto& p : q) {
    const size_t i = pick(rng);
    p = cloud.positions[i] + off(rng) * cloud.normals[i];
  }
  return q;
}

// The CPU path at each instruction set (core/mpu/mpu_eval_simd.h), the widest first;
// returns the widest's time and its rows in `ref`.
double cpu_rows(CpuBackend& cpu, const mpu::MpuSurface& surface, const std::vector<Eigen::Vector3d>& q, int repeats,
                std::vector<mpu::EvalRow>& ref) {
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = Clock::now();
    ref = cpu.mpu_eval(surface, q);
    t.push_back(sec_since(t0));
  }
  const double cpu_s = median(t);
  fmt::print("{:<44} {:>10.3f} {:>14.3g} {:>10}\n", cpu.device() + ", " + simd_level_name(simd_level()), cpu_s,
             double(q.size()) / cpu_s, "1.00x");
  const SimdLevel chosen = simd_level();
  for (auto path : {SimdLevel::kAvx512, SimdLevel::kAvx2, SimdLevel::kGeneric}) {
    if (path == chosen || !simd_level_supported(path)) continue;
    set_simd_level(path);
    std::vector<double> tp;
    for (int r = 0; r < repeats; ++r) {
      const auto t0 = Clock::now();
      cpu.mpu_eval(surface, q);
      tp.push_back(sec_since(t0));
    }
    const double s_path = median(tp);
    fmt::print("{:<44} {:>10.3f} {:>14.3g} {:>9.2f}x\n", cpu.device() + ", " + simd_level_name(path), s_path,
               double(q.size()) / s_path, cpu_s / s_path);
  }
  set_simd_level(chosen);
  return cpu_s;
}

// The single-precision path (common/eval_precision.h) at each instruction set, against
// the double path's time `cpu_s` and rows `ref`: the worst |Δf|, normal angle and |ΔK|.
void float_rows(CpuBackend& cpu, const mpu::MpuSurface& surface, const std::vector<Eigen::Vector3d>& q, int repeats,
                double cpu_s, const std::vector<mpu::EvalRow>& ref) {
  const EvalPrecision saved = eval_precision();
  set_eval_precision(EvalPrecision::kFloat);
  mpu::MpuSurface single = surface;
  mpu::index_spheres(single);
  const SimdLevel chosen = simd_level();
  for (auto path : {SimdLevel::kAvx512, SimdLevel::kAvx2, SimdLevel::kGeneric}) {
    if (!simd_level_supported(path)) continue;
    set_simd_level(path);
    std::vector<double> tp;
    std::vector<mpu::EvalRow> rows;
    for (int r = 0; r < repeats; ++r) {
      const auto t0 = Clock::now();
      rows = cpu.mpu_eval(single, q);
      tp.push_back(sec_since(t0));
    }
    // Over all points, and over those within 0.1 mm of f = 0 (where a mesh's vertices lie).
    double df = 0, dn[2] = {0, 0}, dK[2] = {0, 0}, maxK = 0;
    for (size_t i = 0; i < rows.size(); ++i) {
      df = std::max(df, std::abs(rows[i].f - ref[i].f));
      const Eigen::Vector3d a(ref[i].g), b(rows[i].g);
      const double n = a.norm() > 0 && b.norm() > 0 ? std::atan2(a.cross(b).norm(), a.dot(b)) * 180 / M_PI : 0;
      const double k = std::abs(rows[i].gauss - ref[i].gauss);
      maxK = std::max(maxK, std::abs(ref[i].gauss));
      for (int at = 0; at < 2; ++at)
        if (at == 0 || std::abs(ref[i].f) < 0.1) dn[at] = std::max(dn[at], n), dK[at] = std::max(dK[at], k);
    }
    const double s_path = median(tp);
    fmt::print("{:<44} {:>10.3f} {:>14.3g} {:>9.2f}x   (max |df| {:.1e} mm; normal {:.1e} deg, |dK| {:.1e} of max |K|; "
               "within 0.1 mm {:.1e} deg, {:.1e})\n",
               cpu.device() + ", float32, " + simd_level_name(path), s_path, double(q.size()) / s_path, cpu_s / s_path,
               df, dn[0], dK[0] / maxK, dn[1], dK[1] / maxK);
  }
  set_simd_level(chosen);
  set_eval_precision(saved);
}

// The same points with the Hessian of f as well (mpu::evaluate_hessian: the exact second
// derivative, which the curvature does not take; mpu_eval_ref.h), as evaluate_all does
// it: in cache order, into a new array of rows.
void hessian_row(CpuBackend& cpu, const mpu::MpuSurface& surface, const std::vector<Eigen::Vector3d>& q, int repeats,
                 double cpu_s) {
  std::vector<double> th;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = Clock::now();
    const std::vector<size_t> order = mpu::cache_order(surface, q);
    std::vector<mpu::EvalRow> rows(q.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, q.size(), 1024), [&](const tbb::blocked_range<size_t>& b) {
      for (size_t o = b.begin(); o != b.end(); ++o) {
        const size_t i = order[o];
        const mpu::Sample e = mpu::evaluate_hessian(surface, q[i]);
        const mpu::Curvature c = mpu::curvature(e);
        rows[i] = {{q[i].x(), q[i].y(), q[i].z()}, e.f, {e.g.x(), e.g.y(), e.g.z()}, c.k1, c.k2, c.gauss, c.mean};
      }
    });
    th.push_back(sec_since(t0));
  }
  const double s_h = median(th);
  fmt::print("{:<44} {:>10.3f} {:>14.3g} {:>9.2f}x\n",
             cpu.device() + ", " + simd_level_name(simd_level()) + ", + Hessian of f", s_h, double(q.size()) / s_h,
             cpu_s / s_h);
}

// Each Vulkan device: kernel timestamps and wall time, with the ratio to the CPU path.
void gpu_rows(const mpu::MpuSurface& surface, const std::vector<Eigen::Vector3d>& q, int repeats, double cpu_s,
              const std::vector<mpu::EvalRow>& ref) {
  for (const auto& d : vk::list_devices()) {
    vk::ContextOptions opt;
    opt.device_index = d.index;
    try {
      vk::VulkanBackend gpu(opt);
      const vk::MpuDeviceSurface dev(gpu.context(), surface);
      vk::MpuEvalKernel kernel(gpu.context());
      std::vector<double> wall, kern;
      std::vector<mpu::EvalRow> rows;
      for (int r = 0; r < std::max(1, repeats); ++r) {
        std::map<std::string, double> ms;
        const auto t0 = Clock::now();
        rows = kernel.run(dev, q, ms);
        wall.push_back(sec_since(t0));
        kern.push_back(ms["mpu_eval"] / 1e3);
      }
      double df = 0;
      for (size_t i = 0; i < rows.size(); ++i) df = std::max(df, std::abs(rows[i].f - ref[i].f));
      const double w = median(wall), k = median(kern);
      fmt::print("{:<44.44} {:>10.3f} {:>14.3g} {:>9.2f}x   (kernel {:.3f} s: {:.3g} points/s, {:.2f}x; max |df| "
                 "{:.2g} mm)\n",
                 gpu.device(), w, double(q.size()) / w, cpu_s / w, k, double(q.size()) / k, cpu_s / k, df);
    } catch (const std::exception& e) {
      fmt::print("{}: failed: {}\n", d.name, e.what());
    }
  }
}

// Leaves per query: listed in its grid cell (candidates) and holding it (support).
void leaf_figures(const mpu::MpuSurface& surface, const std::vector<Eigen::Vector3d>& q) {
  double candidates = 0, support = 0;
  const size_t sample = std::min<size_t>(q.size(), 100000);
  for (size_t i = 0; i < sample; ++i) {
    const Eigen::Vector3d rel = (q[i] - surface.box_min) / surface.cell_size();
    const auto& dims = surface.grid.dims;
    const size_t cell = size_t(int64_t(rel.x()) + dims[0] * (int64_t(rel.y()) + dims[1] * int64_t(rel.z())));
    candidates += surface.grid.offsets[cell + 1] - surface.grid.offsets[cell];
    support += mpu::evaluate(surface, q[i]).leaves;
  }
  fmt::print("\n{} leaves, lookup grid {}^3 with {} entries; per query {:.1f} candidate leaves, {:.1f} holding it\n",
             surface.leaves.size(), surface.grid.dims[0], surface.grid.leaf_ids.size(), candidates / double(sample),
             support / double(sample));
}

}  // namespace

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : "/usr/share/doc/invesalius-examples/examples/Cranium.inv3";
  const double threshold = argc > 2 ? std::stod(argv[2]) : 226.0;
  const size_t queries = argc > 3 ? size_t(std::stoll(argv[3])) : 1000000;
  const int repeats = argc > 4 ? std::max(1, std::atoi(argv[4])) : 3;
  try {
    const Volume vol = read_volume(path);
    CpuBackend cpu;
    seg::SegmentOptions so;
    so.method = seg::Method::kThreshold;
    so.threshold = {threshold};
    const pts::SlicePoints sp = pts::extract_points(seg::segment(vol, so, cpu), vol);
    const PointCloud& cloud = sp.cloud;
    fmt::print("MPU fit and evaluation: {} ({} x {} x {}), threshold {}, {} points; median of {} runs\n\n", path,
               vol.dims[0], vol.dims[1], vol.dims[2], threshold, cloud.size(), repeats);
    const mpu::MpuSurface surface = fit_table(cloud, cpu, repeats);
    const std::vector<Eigen::Vector3d> q = query_points(cloud, queries);
    fmt::print("\nevaluation of {} points within 1 mm of the surface (f, grad f, blended Hessian, curvature)\n",
               queries);
    fmt::print("{:<44} {:>10} {:>14} {:>10}\n", "device", "wall s", "points/s", "vs CPU");
    std::vector<mpu::EvalRow> ref;
    const double cpu_s = cpu_rows(cpu, surface, q, repeats, ref);
    float_rows(cpu, surface, q, repeats, cpu_s, ref);
    hessian_row(cpu, surface, q, repeats, cpu_s);
    gpu_rows(surface, q, repeats, cpu_s, ref);
    leaf_figures(surface, q);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_mpu: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
