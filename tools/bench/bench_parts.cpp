// Benchmark: a surface mesh of several closed parts remeshed part by part into one
// complex. The parts phantom (core/phantom/parts_phantom.h: five closed parts, two that
// share a disc, two `gap` mm from their neighbour, one well apart) is written as PLY and
// remeshed as a user remeshes it, `mpumesh run PARTS.ply -o complex.ply`; CGAL's
// isotropic remeshing (tools/bench/cgal_remesh_peer.h) remeshes the same mesh at our
// triangle count. Both are read back as complexes (CGAL's components tagged as labels
// against the background, largest first) and measured from their triangles: the parts
// (labels whose boundary is one closed component), whether the touching pair shares an
// interface, the triangle pairs that cross, the distance of each mesh's surface to the
// parts' smooth surfaces that the input's facets are chords of (the truth; mean, p99) and
// to the input (mean, p99; points over its triangles weighted by area), and of the
// input's to it (p99), the worst part volume error against
// the input's, the smallest angle, the mean radius ratio, and the time.
// MPUMESH_BENCH_PARTS_ARGS: options added to our runs.
// Usage:
//   mpumesh_bench_parts [cpu|gpu|auto] [GAP_MM] [EDGE_MM]
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "cgal_remesh_peer.h"
#include "io/mesh_io.h"
#include "mesh/cgal_geometry.h"
#include "mesh/component_filter.h"
#include "mesh/topology.h"
#include "multi/complex_figures.h"
#include "phantom/parts_phantom.h"
#include "phantom/truth_figures.h"
#include "truth_rows.h"

using namespace mpumesh;
namespace fs = std::filesystem;

namespace {

struct Args {
  std::string backend = "cpu";
  double gap = 0.2, edge = 1.0;
};

Args parse_args(int argc, char** argv) {
  Args a;
  int i = 1;
  if (i < argc && bench::is_backend(argv[i]))
    a.backend = argv[i++];
  if (i < argc) a.gap = std::stod(argv[i++]);
  if (i < argc) a.edge = std::stod(argv[i++]);
  return a;
}

// A mesh's connected components as the labels of a complex against the background, by
// enclosed volume, largest first.
TriangleMesh components_as_complex(const TriangleMesh& m) {
  const std::vector<MeshPart> parts = split_parts(m);
  TriangleMesh c;
  for (size_t k = 0; k < parts.size(); ++k) {
    const uint32_t base = uint32_t(c.vertices.size());
    c.vertices.insert(c.vertices.end(), parts[k].mesh.vertices.begin(), parts[k].mesh.vertices.end());
    for (const auto& t : parts[k].mesh.triangles) {
      // Oriented from the background (0) into the part.
      c.triangles.push_back({t[0] + base, t[2] + base, t[1] + base});
      c.face_labels.push_back({0, int32_t(k + 1)});
    }
  }
  return c;
}

void print_header() {
  fmt::print("  {:<22} {:>7} {:>5} {:>6} {:>6} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>6} {:>6}\n", "mesh",
             "tris", "parts", "shared", "cross", "t mean", "t p99", "d mean", "d p99", "in p99", "vol %", "min ang", "rr",
             "s");
}

void print_row(const std::string& name, const TriangleMesh& c, const phantom::PartsPhantom& p, double seconds) {
  const multi::ComplexFigures f = multi::measure_complex(c);
  int64_t whole = 0, shared = 0;
  double worst = 0;
  for (const multi::RegionFigures& r : f.regions) {
    whole += r.defects == 0 && r.components == 1;
    if (r.label >= 1 && size_t(r.label) <= p.part_volumes.size())
      worst = std::max(worst, std::abs(r.volume_mm3 / p.part_volumes[size_t(r.label - 1)] - 1));
  }
  for (const multi::InterfaceFigures& i : f.interfaces)
    for (const auto& [a, b] : p.touching)
      if (i.label_a == a && i.label_b == b) shared += i.triangles;
  const DistanceSamples d = sample_distances(c, p.mesh), back = sample_distances(p.mesh, c);
  double mean = 0, area = 0;
  for (size_t k = 0; k < d.distance.size(); ++k) mean += d.distance[k] * d.weight[k], area += d.weight[k];
  mean /= area;
  const phantom::PartsPhantom::Distances t = p.distance_to_truth(c);
  fmt::print("  {:<22} {:>7} {:>2}/{:<2} {:>6} {:>6} {:>7.4f} {:>7.4f} {:>7.4f} {:>7.4f} {:>7.4f} {:>7.3f} {:>7.1f} "
             "{:>6.3f} {:>6.2f}\n",
             name, c.triangles.size(), whole, f.regions.size(), shared, f.crossing_pairs, t.mean, t.p99, mean,
             phantom::weighted_quantile(d.distance, d.weight, 0.99),
             phantom::weighted_quantile(back.distance, back.weight, 0.99),
             100 * worst, f.min_angle_deg, f.mean_radius_ratio, seconds);
}

}  // namespace

int main(int argc, char** argv) {
  bench::same_memory_for_all(argv);
  const Args args = parse_args(argc, argv);
  const fs::path dir = fs::temp_directory_path() / "mpumesh_bench_parts";
  fs::create_directories(dir);
  const phantom::PartsPhantom p = phantom::parts_phantom(args.edge, args.gap);
  const std::string input = (dir / "parts.ply").string(), ours = (dir / "complex.ply").string();
  write_mesh(p.mesh, input);
  fmt::print("parts phantom: {} parts, {} triangles, edges about {:.2f} mm, gaps {:.2f} mm, parts 1 and 2 share a "
             "disc\n",
             p.part_volumes.size(), p.mesh.triangles.size(), args.edge, args.gap);
  fmt::print("columns: triangles, parts closed as one component / labels, triangles of the touching pair's shared "
             "interface, crossing triangle pairs, distance of the surface to the parts' smooth surfaces mean/p99 "
             "(mm), to the input mean/p99 (mm), of the "
             "input's surface to the mesh p99 (mm), worst part volume error against the input's (%), smallest "
             "angle (deg), mean radius ratio, seconds\n");
  const double t_ours =
      bench::timed_system(fmt::format("{} run {} --backend {} --quiet -o {}{}", MPUMESH_BIN, input, args.backend, ours,
                                      bench::extra_args("MPUMESH_BENCH_PARTS_ARGS")));
  const TriangleMesh our = read_mesh(ours);
  const bench::RemeshResult cg = bench::cgal_isotropic_remesh(p.mesh, int64_t(our.triangles.size()));
  print_header();
  print_row("ours", our, p, t_ours);
  print_row("CGAL isotropic remesh", components_as_complex(cg.mesh), p, cg.seconds);
  fmt::print("  CGAL target edge {:.3f} mm\n", cg.edge_length);
  return 0;
}
