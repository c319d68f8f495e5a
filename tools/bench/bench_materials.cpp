// Benchmark: label maps of touching structures meshed into one multi-material complex,
// against the analytic truth. Each material phantom (core/phantom/material_phantom.h: a
// split ball, nested balls, three sectors meeting along an axis, a ball in a cup with a
// one-slice gap; every voxel holds the label at its centre, slices 2-3 times the pixel,
// tilted) is written as NIfTI and meshed as a user meshes it, `mpumesh run MAP --labels
// all -o complex.ply`; CGAL Mesh_3 meshes the same labelled image (its labelled-image
// domain, facets tagged by their two subdomains) with its facet size set for about our
// triangle count. Every figure comes from the complexes as written and read back
// (core/phantom/complex_truth.h, core/multi/complex_figures.h): per interface the
// distance to its true surface (mean, p99) and the normal error (mean, p95; and away
// from the junction curves and sharp rims), the junction edges' distance to the true curves (p95) and
// the true curves' to ours, each label's volume error, the smallest angle overall and
// away from junctions, the mean radius ratio, every label's boundary closed, the
// crossing pairs, and the time.
// MPUMESH_BENCH_MATERIALS_ARGS: options added to our runs. --no-mesh3 leaves Mesh_3 out.
// Usage:
//   mpumesh_bench_materials [cpu|gpu|auto] [--no-mesh3] [PHANTOM ...]
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "cgal_mesh3_peer.h"
#include "io/mesh_io.h"
#include "io/volume_io.h"
#include "multi/complex_figures.h"
#include "phantom/complex_truth.h"
#include "phantom/material_phantom.h"
#include "truth_rows.h"

using namespace mpumesh;
namespace fs = std::filesystem;

namespace {

struct Args {
  std::string backend = "cpu";
  bool mesh3 = true;
  std::vector<std::string> phantoms;
};

Args parse_args(int argc, char** argv) {
  Args a;
  int i = 1;
  if (i < argc && bench::is_backend(argv[i]))
    a.backend = argv[i++];
  for (; i < argc; ++i) {
    const std::string s = argv[i];
    if (s == "--no-mesh3") a.mesh3 = false;
    else a.phantoms.push_back(s);
  }
  return a;
}

void print_header() {
  fmt::print("  {:<12} {:>7} {:>7} {:>7} {:>6} {:>6} {:>6} {:>6} {:>6} {:>6} {:>6} {:>7} {:>6} {:>6} {:>5} {:>6} {:>5} {:>6}\n",
             "mesh", "tris", "d mean", "d p99", "n mean", "n p95", "away", "p95", "j p95", "j cov", "vol %", "min ang",
             "off j", "rr", "open", "cross", "alien", "s");
}

void print_row(const std::string& name, const TriangleMesh& c, const phantom::ComplexTruth& t, double seconds) {
  const multi::ComplexFigures f = multi::measure_complex(c);
  int64_t open = 0;
  for (const auto& r : f.regions) open += r.defects;
  fmt::print(
      "  {:<12} {:>7} {:>7.3f} {:>7.3f} {:>6.2f} {:>6.2f} {:>6.2f} {:>6.2f} {:>6.3f} {:>6.3f} {:>6.2f} {:>7.1f} "
      "{:>6.1f} {:>6.3f} {:>5} {:>6} {:>5} {:>6.2f}\n",
      name, c.triangles.size(), t.distance_mean, t.distance_p99, t.normal_mean_deg, t.normal_p95_deg,
      t.normal_mean_away_deg, t.normal_p95_away_deg, t.junction_p95, t.junction_cover_p95, 100 * t.worst_volume_error,
      f.min_angle_deg, f.min_angle_off_junction_deg, f.mean_radius_ratio, open, f.crossing_pairs, t.foreign_triangles,
      seconds);
}

void print_interfaces(const phantom::ComplexTruth& t) {
  for (const auto& i : t.interfaces)
    fmt::print("    ({}, {}): {} triangles, distance {:.3f} / {:.3f} mm, normals {:.2f} / {:.2f} deg, away from "
               "rims {:.2f} / {:.2f}\n",
               i.a, i.b, i.triangles, i.distance_mean, i.distance_p99, i.normal_mean_deg, i.normal_p95_deg,
               i.normal_mean_away_deg, i.normal_p95_away_deg);
  for (const auto& l : t.labels) fmt::print("    label {}: volume error {:+.2f}%\n", l.label, 100 * l.volume_error);
}

void bench_phantom(const phantom::MaterialPhantom& m, const Args& args, const fs::path& root) {
  std::string folder = m.name;
  std::replace(folder.begin(), folder.end(), ' ', '_');
  const fs::path dir = root / folder;
  fs::create_directories(dir);
  const Volume map = phantom::material_scan(m);
  const std::string map_path = (dir / "labels.nii.gz").string(), ours = (dir / "complex.ply").string();
  write_volume(map, map_path);
  fmt::print("{}: {} x {} x {} voxels of {:.2f} x {:.2f} x {:.2f} mm\n", m.name, map.dims[0], map.dims[1], map.dims[2],
             map.spacing.x(), map.spacing.y(), map.spacing.z());
  const double t_ours =
      bench::timed_system(fmt::format("{} run {} --labels all --backend {} --quiet -o {}{}", MPUMESH_BIN, map_path,
                                      args.backend, ours, bench::extra_args("MPUMESH_BENCH_MATERIALS_ARGS")));
  const TriangleMesh our = read_mesh(ours);
  // Faces farther than two in-plane voxels from a junction or a sharp rim count as away.
  const double rim = 2 * map.in_plane_spacing();
  const phantom::ComplexTruth t_our = phantom::complex_truth(m, our, rim);
  print_header();
  print_row("ours", our, t_our, t_ours);
  if (args.mesh3) {
    bench::Mesh3Params p;
    p.labels = true;
    p.manifold = false;  // a complex is non-manifold along its junctions
    bench::Mesh3Result cg = bench::cgal_mesh3_matching(map, p, our);
    for (auto& t : cg.mesh.triangles) std::swap(t[1], t[2]);  // from the lower label into the higher
    const std::string m3_path = (dir / "mesh3.ply").string();
    write_mesh(cg.mesh, m3_path);
    const TriangleMesh m3 = read_mesh(m3_path);
    const phantom::ComplexTruth t_m3 = phantom::complex_truth(m, m3, rim);
    print_row("CGAL Mesh_3", m3, t_m3, cg.seconds);
    fmt::print("  Mesh_3 facet size {:.2f} mm, distance {:.2f} mm\n", p.facet_size, p.facet_distance);
    fmt::print("  ours:\n");
    print_interfaces(t_our);
    fmt::print("  CGAL Mesh_3:\n");
    print_interfaces(t_m3);
  } else {
    print_interfaces(t_our);
  }
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  bench::same_memory_for_all(argv);
  const Args args = parse_args(argc, argv);
  const fs::path root = fs::temp_directory_path() / "mpumesh_bench_materials";
  fmt::print("columns: interface distance to the truth mean/p99 (mm), normal error mean/p95 and mean/p95 away "
             "from junctions and sharp rims (deg), junction edges' p95 distance to the true curves and the true curves' p95 to ours "
             "(mm), worst label volume error (%), smallest angle overall and off junctions (deg), mean radius "
             "ratio, open edges of the labels' boundaries, crossing triangle pairs, triangles on no true interface, "
             "seconds\n");
  for (const phantom::MaterialPhantom& m : phantom::material_suite()) {
    if (!args.phantoms.empty() && std::find(args.phantoms.begin(), args.phantoms.end(), m.name) == args.phantoms.end())
      continue;
    bench_phantom(m, args, root);
  }
  return 0;
}
