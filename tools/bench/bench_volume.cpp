// Benchmark: volume meshes against CGAL Mesh_3's, both in this run.
// - The sample CT's bone against Mesh_3's of the gray image. Ours: the pipeline `mpumesh
//   run VOLUME --threshold T --volume V.msh` runs (core/pipeline, the surface at the default
//   size, then TetGen, timed as the 'volume mesh' stage and against the surface run); CGAL:
//   Mesh_3 on the gray image (tools/bench/cgal_mesh3_peer.h) with cell criteria
//   (radius-edge ratio 3, the cell size ours used), sliver perturbation and exudation, its
//   facet size set for about our surface's triangle count (one correction after a first
//   try).
// - `--materials`: the multi-material phantoms (core/phantom/material_phantom.h) as label
//   maps. Ours: `mpumesh run MAP --labels all -o complex.ply --volume complex.vtu` as a
//   user runs it, a region per label; CGAL: Mesh_3 on the labelled image at about our
//   complex's triangle count with the same cell criteria, a subdomain per label. Both read
//   back and measured per label.
// Mesh_3 runs sequential and in its parallel mode (TBB, as many threads as ours); the
// time ratio that counts is against the faster of the two.
// For each: tetrahedra, nodes, dihedral angles (smallest, % of tetrahedra with one under
// 10° and 15°), mean radius ratio, time.
// Usage: mpumesh_bench_volume VOLUME [THRESHOLD] [PARTICLES]
//        mpumesh_bench_volume --materials [cpu|gpu|auto]
#include <fmt/format.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cmath>

#include <filesystem>
#include <map>

#include "cgal_mesh3_peer.h"
#include "cpu/cpu_backend.h"
#include "io/mesh_io.h"
#include "io/tet_io.h"
#include "io/volume_io.h"
#include "phantom/material_phantom.h"
#include "pipeline/run_pipeline.h"
#include "tet/region_quality.h"
#include "tet/tet_quality.h"
#include "tet/tetgen_steps.h"
#include "truth_rows.h"

using namespace mpumesh;

namespace {

class StageTimes : public pipeline::Observer {
 public:
  void begin(const std::string& s) override { stage_ = s, t0_ = std::chrono::steady_clock::now(); }
  void end() override { seconds[stage_] += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }
  std::map<std::string, double> seconds;

 private:
  std::string stage_;
  std::chrono::steady_clock::time_point t0_;
};

void row(const char* name, int64_t triangles, const TetQuality& q, double seconds) {
  fmt::print("{:<14} {:>9} {:>9} {:>8} {:>8.2f} {:>7.3f} {:>7.3f} {:>6.3f} {:>8.2f}\n", name, triangles, q.tets, q.nodes,
             q.min_dihedral_deg, q.pct_min_dihedral_below_10, q.pct_min_dihedral_below_15, q.radius_ratio_mean, seconds);
}

void label_rows(const char* name, int64_t triangles, const TetMesh& m, double seconds) {
  row(name, triangles, measure_tet_quality(m), seconds);
  for (const auto& [label, q] : quality_by_region(m))
    fmt::print("  label {:<6} {:>9} {:>9} {:>8} {:>8.2f} {:>7.3f} {:>7.3f} {:>6.3f}\n", label, "", q.tets, "",
               q.min_dihedral_deg, q.pct_min_dihedral_below_10, q.pct_min_dihedral_below_15, q.radius_ratio_mean);
}

int materials(const std::string& backend) {
  const std::filesystem::path root = std::filesystem::temp_directory_path() / "mpumesh_bench_volume";
  std::filesystem::create_directories(root);
  double ours_total = 0, mesh3_total = 0;
  for (const phantom::MaterialPhantom& m : phantom::material_suite()) {
    const Volume map = phantom::material_scan(m);
    std::string name = m.name;
    std::replace(name.begin(), name.end(), ' ', '_');
    const std::string map_path = (root / (name + ".nii.gz")).string(), complex = (root / (name + ".ply")).string(),
                      volume = (root / (name + ".vtu")).string();
    write_volume(map, map_path);
    const double t_ours = bench::timed_system(fmt::format("{} run {} --labels all --backend {} --quiet -o {} --volume {}",
                                                          MPUMESH_BIN, map_path, backend, complex, volume));
    const TriangleMesh ours_surface = read_mesh(complex);
    const TetMesh ours = read_tet_mesh(volume);
    bench::Mesh3Params p;
    p.labels = true;
    p.manifold = false;  // a complex is non-manifold along its junctions
    p.cell_size = tetgen_steps::interior_size(mean_edge_lengths(ours_surface), 0);  // the size ours used
    const bench::Mesh3Result cg = bench::cgal_mesh3_matching(map, p, ours_surface);
    const bench::Mesh3Result cgp = bench::cgal_mesh3_parallel(map, p);
    fmt::print("\n{}: {} x {} x {} voxels of {:.2f} x {:.2f} x {:.2f} mm; Mesh_3 facet size {:.2f} mm, distance "
               "{:.2f} mm, cell size {:.2f} mm\n",
               m.name, map.dims[0], map.dims[1], map.dims[2], map.spacing.x(), map.spacing.y(), map.spacing.z(),
               p.facet_size, p.facet_distance, p.cell_size);
    fmt::print("{:<14} {:>9} {:>9} {:>8} {:>8} {:>7} {:>7} {:>6} {:>8}\n", "mesh", "surface", "tets", "nodes", "min dih",
               "%<10", "%<15", "RR", "time s");
    label_rows("ours", int64_t(ours_surface.triangles.size()), ours, t_ours);
    label_rows("Mesh_3 seq.", int64_t(cg.mesh.triangles.size()), cg.volume, cg.seconds);
    label_rows("Mesh_3 par.", int64_t(cgp.mesh.triangles.size()), cgp.volume, cgp.seconds);
    const double faster = std::min(cg.seconds, cgp.seconds);
    fmt::print("time ours / CGAL Mesh_3 sequential: {:.2f}, / parallel ({} threads): {:.2f}, / the faster: {:.2f}\n",
               t_ours / cg.seconds, tbb::this_task_arena::max_concurrency(), t_ours / cgp.seconds, t_ours / faster);
    ours_total += t_ours, mesh3_total += faster;
    std::fflush(stdout);
  }
  fmt::print("\n(surface: the complex's triangles; min dih: smallest dihedral angle, degrees; %<10, %<15: % of "
             "tetrahedra with a dihedral angle under 10, 15 degrees; RR: mean radius ratio 3 r_in / r_circ; time: ours "
             "the whole `run` from the label map, a process as a user starts it; CGAL's Mesh_3 run)\n");
  fmt::print("all phantoms, time ours / the faster CGAL Mesh_3 (sequential or parallel): {:.2f}\n",
             ours_total / mesh3_total);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  bench::same_memory_for_all(argv);
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s VOLUME [THRESHOLD] [PARTICLES]\n       %s --materials [cpu|gpu|auto]\n", argv[0],
                 argv[0]);
    return 2;
  }
  if (std::string(argv[1]) == "--materials") return materials(argc > 2 ? argv[2] : "cpu");
  const std::string path = argv[1];
  const double iso = argc > 2 ? std::stod(argv[2]) : 226;
  const Volume vol = read_volume(path);
  CpuBackend cpu;
  pipeline::RunOptions ro;
  ro.segment.method = seg::Method::kThreshold;
  ro.segment.threshold = mc::ThresholdRange{iso};
  ro.sample.particles = argc > 3 ? std::stoll(argv[3]) : 0;
  ro.quality.reset();
  ro.volume_mesh = TetOptions{};
  StageTimes times;
  const auto t0 = std::chrono::steady_clock::now();
  const pipeline::RunResult r = pipeline::run_pipeline(path, ro, [&]() -> ComputeBackend& { return cpu; }, &times);
  const double t_all = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double t_volume = times.seconds["volume mesh"], t_surface = t_all - t_volume;
  fmt::print("volume {}: threshold {}; ours on {}\n", path, iso, cpu.device());
  fmt::print("ours: surface run {:.2f} s ({} triangles), volume mesh {:.2f} s ({:.2f} times the surface run); size "
             "{:.2f} mm\n",
             t_surface, r.mesh.triangles.size(), t_volume, t_volume / t_surface, r.volume->stats.size);
  // CGAL at about our surface's triangle count: on the sample CT facet size 3.4 mm (distance
  // 0.72) gives about 96,500 triangles, and the count goes as 1 / size².
  bench::Mesh3Params m3;
  m3.iso = iso;
  m3.facet_size = 3.4 * std::sqrt(96500.0 / double(r.mesh.triangles.size()));
  m3.facet_distance = 0.72 * m3.facet_size / 3.4;
  m3.cell_size = r.volume->stats.size;
  const bench::Mesh3Result cg = bench::cgal_mesh3(vol, m3);
  const bench::Mesh3Result cgp = bench::cgal_mesh3_parallel(vol, m3);
  fmt::print("CGAL Mesh_3: facet size {:.2f} mm, distance {:.2f} mm, cell size {:.2f} mm, radius-edge 3, perturb and "
             "exude\n",
             m3.facet_size, m3.facet_distance, m3.cell_size);
  fmt::print("\n{:<14} {:>9} {:>9} {:>8} {:>8} {:>7} {:>7} {:>6} {:>8}\n", "mesh", "surface", "tets", "nodes",
             "min dih", "%<10", "%<15", "RR", "time s");
  row("ours", int64_t(r.mesh.triangles.size()), r.volume->stats.quality, t_all);
  row("Mesh_3 seq.", int64_t(cg.mesh.triangles.size()), measure_tet_quality(cg.volume), cg.seconds);
  row("Mesh_3 par.", int64_t(cgp.mesh.triangles.size()), measure_tet_quality(cgp.volume), cgp.seconds);
  fmt::print("(surface: triangles of the boundary; min dih: smallest dihedral angle, degrees; %<10, %<15: % of "
             "tetrahedra with a dihedral angle under 10, 15 degrees; RR: mean radius ratio 3 r_in / r_circ; time: ours "
             "from reading the file to the volume mesh, CGAL's Mesh_3 run)\n");
  fmt::print("time ours / CGAL Mesh_3 sequential: {:.2f}, / parallel ({} threads): {:.2f}, / the faster: {:.2f}\n",
             t_all / cg.seconds, tbb::this_task_arena::max_concurrency(), t_all / cgp.seconds,
             t_all / std::min(cg.seconds, cgp.seconds));
  return 0;
}
