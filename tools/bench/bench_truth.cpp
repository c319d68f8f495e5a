// Benchmark: accuracy against analytic truth on the CT-like phantoms (core/phantom).
// Each phantom is scanned (partial volume, noise, thick slices, tilt), written as NIfTI
// and meshed as a user meshes it: `mpumesh run VOLUME --threshold T` at the defaults
// (ours; it also writes its fitted surface), `mpumesh mc` (marching cubes), `mpumesh
// polygonize` of our surface (the original MPU mesh), and CGAL Mesh_3 on the gray image
// with its facet size set so that it makes as many triangles as ours. Every figure is
// computed from the mesh file read back and the shape's closed form
// (core/phantom/truth_figures.h): distance to the true surface (mean, p99), normal error
// (area-weighted mean, p95), curvature against the true K (rank correlation, median
// error over the largest |K|; ours from the K its PLY carries, the others from their
// discrete K), and spacing against the true |K| (median spacing of the highest tenth of
// |K| over the lowest tenth, rank correlation).
// Usage:
//   mpumesh_bench_truth [cpu|gpu|auto] [PHANTOM ...]
// MPUMESH_BENCH_TRUTH_ARGS: options added to our run (to measure other settings), where
// "{px}" stands for the in-plane pixel size and "{2.5px}" for 2.5 times it.
#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>

#include "cgal_mesh3_peer.h"
#include "truth_rows.h"
#include "io/mesh_io.h"
#include "io/read_file.h"
#include "io/volume_io.h"
#include "phantom/ct_phantom.h"
#include "phantom/truth_figures.h"

using namespace mpumesh;

int main(int argc, char** argv) {
  bench::same_memory_for_all(argv);
  const std::string backend = argc > 1 ? argv[1] : "cpu";
  std::vector<std::string> only(argv + std::min(argc, 2), argv + argc);
  const std::string bin = MPUMESH_BIN;
  const std::filesystem::path root = std::filesystem::temp_directory_path() / "mpumesh_bench_truth";
  std::filesystem::create_directories(root);
  fmt::print("columns: triangles, distance to the truth mean / p99 (mm), normal error mean / p95 (deg), K rank "
             "correlation (f: the PLY's K, d: discrete K), K median error / max|K|, spacing high/low |K| tenth, "
             "spacing rank correlation with |K|, seconds; 'ours on truth': our triangles with their vertices moved onto the "
             "true surface\n");
  for (const auto& ph : phantom::suite()) {
    if (!only.empty() && std::find(only.begin(), only.end(), ph.name) == only.end()) continue;
    const std::filesystem::path dir = root / ph.name;
    std::filesystem::create_directories(dir);
    const Volume vol = phantom::scan(ph.shape, ph.scan);
    const std::string nii = (dir / "scan.nii.gz").string();
    write_volume(vol, nii);
    const double iso = phantom::half_level(ph.scan);
    fmt::print("{}: {} x {} x {} voxels of {:.2f} x {:.2f} x {:.2f} mm, noise {:.0f} HU, max |K| {:.4f} /mm2\n",
               ph.name, vol.dims[0], vol.dims[1], vol.dims[2], vol.spacing.x(), vol.spacing.y(), vol.spacing.z(),
               ph.scan.noise_hu, ph.shape.max_abs_gauss());
    const std::string ours = (dir / "ours.ply").string(), mc = (dir / "mc.ply").string();
    const std::string surf = (dir / "ours.mpu").string(), mpu = (dir / "mpu.ply").string();
    std::string extra = std::getenv("MPUMESH_BENCH_TRUTH_ARGS") ? std::getenv("MPUMESH_BENCH_TRUTH_ARGS") : "";
    for (std::smatch m; std::regex_search(extra, m, std::regex(R"(\{([0-9.]*)px\})"));)
      extra.replace(size_t(m.position(0)), size_t(m.length(0)),
                    fmt::format("{:.3f}", (m[1].length() ? std::stod(m[1]) : 1.0) * vol.in_plane_spacing()));
    const double t_ours = bench::timed_system(fmt::format("{} run {} --threshold {} --backend {} --quiet -o {} --surface {} "
                                                   "--report {} {}",
                                                   bin, nii, iso, backend, ours, surf, (dir / "ours.json").string(),
                                                   extra));
    const double t_mc = bench::timed_system(fmt::format("{} mc {} --threshold {} --backend {} --quiet -o {}", bin, nii, iso,
                                                 backend, mc));
    const double t_mpu = bench::timed_system(fmt::format("{} polygonize {} --backend {} --quiet -o {}", bin, surf, backend, mpu));
    const TriangleMesh our_mesh = read_mesh(ours);
    const phantom::TruthFigures f_ours = phantom::truth_figures(our_mesh, ph.shape);
    bench::Mesh3Params m3;
    m3.iso = iso;
    const bench::Mesh3Result cg = bench::cgal_mesh3_matching(vol, m3, our_mesh);
    const std::string m3_path = (dir / "mesh3.ply").string();
    write_mesh(cg.mesh, m3_path);
    const auto report = nlohmann::json::parse(read_file((dir / "ours.json").string()));
    fmt::print("  ours: fit tolerance {:.3f} mm ({}); Mesh_3 facet size {:.2f} mm, distance {:.2f} mm\n",
               report["fit"].value("eps_mm", 0.0), report["fit"].value("eps_source", std::string("-")), m3.facet_size,
               m3.facet_distance);
    bench::print_truth_header(false);
    bench::print_truth_row("ours", f_ours, t_ours, false);
    // Our triangles with their vertices moved onto the true surface: the normal error that
    // the triangle count and shape leave with a perfect fit.
    TriangleMesh on_truth = our_mesh;
    for (auto& v : on_truth.vertices) v = ph.shape.closest_point(v);
    const phantom::TruthFigures f_floor = phantom::truth_figures(on_truth, ph.shape);
    fmt::print("  {:<16} {:>7} {:>7} {:>6} {:>7.2f} {:>6.2f}\n", "ours on truth", f_floor.triangles, "", "",
               f_floor.normal_mean_deg, f_floor.normal_p95_deg);
    bench::print_truth_row("marching cubes", phantom::truth_figures(read_mesh(mc), ph.shape), t_mc, false);
    bench::print_truth_row("CGAL Mesh_3", phantom::truth_figures(read_mesh(m3_path), ph.shape), cg.seconds, false);
    bench::print_truth_row("original MPU", phantom::truth_figures(read_mesh(mpu), ph.shape), t_mpu, false);
    std::fflush(stdout);
  }
  return 0;
}
