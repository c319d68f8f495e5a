// Benchmark: remeshing a surface. The sample CT's marching-cubes surface (bone at 226 HU),
// written to a PLY file, remeshed by ours as `mpumesh run MC.ply --particles N --quiet`
// runs it (core/pipeline, from reading the file to the checked mesh) and by CGAL's
// isotropic remeshing at the same triangle count (tools/bench/cgal_remesh_peer.h), in the
// same run; both measured against the marching-cubes surface (tools/bench/mesh_rows.h).
// Usage:
//   mpumesh_bench_remesh VOLUME [THRESHOLD] [PARTICLES] [cpu|gpu|auto]
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include "cgal_remesh_peer.h"
#include "cpu/cpu_backend.h"
#include "io/mesh_io.h"
#include "io/volume_io.h"
#include "mc/marching_cubes.h"
#include "mesh_rows.h"
#include "pipeline/run_pipeline.h"
#include "truth_rows.h"
#include "vulkan_backend.h"

using namespace mpumesh;

namespace {

using Clock = std::chrono::steady_clock;
double sec_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// A directory removed with what it holds when the benchmark ends.
struct TempDir {
  std::filesystem::path path;
  TempDir() {
    std::string t = (std::filesystem::temp_directory_path() / "mpumesh_bench_remesh.XXXXXX").string();
    if (!mkdtemp(t.data())) throw std::runtime_error("cannot create a temporary directory");
    path = t;
  }
  ~TempDir() { std::filesystem::remove_all(path); }
};

}  // namespace

int main(int argc, char** argv) {
  bench::same_memory_for_all(argv);
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s VOLUME [THRESHOLD] [PARTICLES] [cpu|gpu|auto]\n", argv[0]);
    return 2;
  }
  const std::string path = argv[1];
  const double iso = argc > 2 ? std::stod(argv[2]) : 226;
  const int64_t particles = argc > 3 ? std::stoll(argv[3]) : 45000;
  const Volume vol = read_volume(path);
  CpuBackend cpu;
  const TriangleMesh mc_mesh = marching_cubes(vol, mc::ThresholdRange{iso}, cpu);
  const TempDir tmp;
  const std::string input = (tmp.path / "mc.ply").string();
  write_mesh(mc_mesh, input);
  std::printf("input: the marching-cubes surface of %s at %g, %zu triangles\n", path.c_str(), iso,
              mc_mesh.triangles.size());

  vk::BackendChoice choice = vk::make_backend(argc > 4 ? argv[4] : "auto");
  std::printf("ours on: %s%s\n", choice.backend->device().c_str(),
              choice.note.empty() ? "" : (" (" + choice.note + ")").c_str());
  pipeline::RunOptions ro;
  ro.sample.particles = particles;
  ro.quality.reset();  // --quiet and no report
  const auto t0 = Clock::now();
  const pipeline::RunResult run = pipeline::run_pipeline(
      input, ro, [&]() -> ComputeBackend& { return *choice.backend; }, nullptr);
  const double t_ours = sec_since(t0);
  std::printf("ours: %lld particles, %d iterations, optimisation %.2f s: %.2f s\n", (long long)run.sample.particles,
              run.sample.iterations, run.optimization.seconds, t_ours);

  const bench::RemeshResult cg = bench::cgal_isotropic_remesh(mc_mesh, int64_t(run.mesh.triangles.size()));
  std::printf("CGAL isotropic remeshing: 3 iterations, target edge length %.3f mm: %.2f s\n", cg.edge_length,
              cg.seconds);

  std::vector<bench::Row> rows(3);
  rows[0] = {"ours (" + choice.backend->kind() + ")", &run.mesh, t_ours};
  rows[1] = {"CGAL isotropic", &cg.mesh, cg.seconds};
  rows[2] = {"marching cubes", &mc_mesh, 0};
  for (size_t i = 0; i < rows.size(); ++i) bench::measure(rows[i], mc_mesh, i < 2);
  bench::print_rows(rows);
  std::printf("\ntime ours / CGAL isotropic remeshing: %.2f; triangles ours / CGAL: %.2f\n", t_ours / cg.seconds,
              double(run.mesh.triangles.size()) / double(std::max<size_t>(cg.mesh.triangles.size(), 1)));
  return 0;
}
