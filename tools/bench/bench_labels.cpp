// Benchmark: label maps against the analytic truth and on a real label map.
// Phantoms (core/phantom label_suite: each voxel holds the label where its centre lies
// inside the shape, slices 2-3 times the pixel, tilted) are written as NIfTI and meshed as
// a user meshes a label map, `mpumesh run MAP --label 1` at the defaults; CGAL Mesh_3 on
// the same label map (its labelled-image domain) with its facet size set so that it makes
// as many triangles as ours; and, for the count, ours on the grey CT-like scan of the same
// shape (`--threshold`). Every figure comes from the mesh file read back
// (core/phantom/truth_figures.h): distance to the truth, normal error, K rank correlation,
// spacing against |K|, the volume's error, and the slice-phase modulation of |H|
// (core/mesh/slice_phase.h).
// With --real MAP: `mpumesh run MAP --labels all --separate`, and for each label its triangles,
// closedness, the slice-phase modulation, and Mesh_3's on that label alone at our count.
// --grey VOLUME:THRESHOLD:LABEL adds the count that the grey-volume rule gives for the
// label's structure (the volume thresholded), and ours on the same shape: the label alone,
// the other labels taken as background (next to another label a label's surface lies a
// quarter voxel inside it, segment/label_map.h, which halves a plate one voxel thick
// between two others).
// MPUMESH_BENCH_LABELS_ARGS: options added to our label-map runs (to measure other settings).
// --no-mesh3 leaves Mesh_3 out of the real map's rows (it takes minutes per label there).
// Usage:
//   mpumesh_bench_labels [cpu|gpu|auto] [--real MAP [--grey VOLUME:THRESHOLD:LABEL] [--no-mesh3]] [PHANTOM ...]
#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "cgal_mesh3_peer.h"
#include "io/mesh_io.h"
#include "io/volume_io.h"
#include "mesh/quality.h"
#include "mesh/slice_phase.h"
#include "phantom/ct_phantom.h"
#include "phantom/truth_figures.h"
#include "segment/label_map.h"
#include "truth_rows.h"

using namespace mpumesh;
namespace fs = std::filesystem;

namespace {

constexpr const char* kExtraArgs = "MPUMESH_BENCH_LABELS_ARGS";

struct Args {
  std::string backend = "cpu";
  std::string real, grey;
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
    if (s == "--real" && i + 1 < argc) a.real = argv[++i];
    else if (s == "--grey" && i + 1 < argc) a.grey = argv[++i];
    else if (s == "--no-mesh3") a.mesh3 = false;
    else a.phantoms.push_back(s);
  }
  return a;
}

void bench_phantom(const phantom::Phantom& ph, const std::string& backend, const fs::path& root) {
  const std::string bin = MPUMESH_BIN;
  const fs::path dir = root / ph.name;
  fs::create_directories(dir);
  const Volume map = phantom::label_scan(ph.shape, ph.scan, 1);
  const std::string map_path = (dir / "labels.nii.gz").string(), grey_path = (dir / "grey.nii.gz").string();
  write_volume(map, map_path);
  write_volume(phantom::scan(ph.shape, ph.scan), grey_path);
  fmt::print("{}: {} x {} x {} voxels of {:.2f} x {:.2f} x {:.2f} mm, volume {:.0f} mm3, max |K| {:.4f} /mm2\n", ph.name,
             map.dims[0], map.dims[1], map.dims[2], map.spacing.x(), map.spacing.y(), map.spacing.z(),
             ph.shape.volume(), ph.shape.max_abs_gauss());
  const std::string ours = (dir / "ours.ply").string(), grey = (dir / "grey.ply").string();
  const double t_ours = bench::timed_system(fmt::format("{} run {} --label 1 --backend {} --quiet -o {}{}", bin, map_path,
                                                        backend, ours, bench::extra_args(kExtraArgs)));
  const double t_grey = bench::timed_system(fmt::format("{} run {} --threshold {} --backend {} --quiet -o {}", bin,
                                                        grey_path, phantom::half_level(ph.scan), backend, grey));
  const TriangleMesh our_mesh = read_mesh(ours);
  bench::Mesh3Params m3;
  m3.labels = true;
  const bench::Mesh3Result cg = bench::cgal_mesh3_matching(map, m3, our_mesh);
  const std::string m3_path = (dir / "mesh3.ply").string();
  write_mesh(cg.mesh, m3_path);
  fmt::print("  Mesh_3 facet size {:.2f} mm, distance {:.2f} mm\n", m3.facet_size, m3.facet_distance);
  bench::print_truth_header(true);
  bench::print_truth_row("ours", phantom::truth_figures(our_mesh, ph.shape, &map), t_ours, true);
  bench::print_truth_row("CGAL Mesh_3", phantom::truth_figures(read_mesh(m3_path), ph.shape, &map), cg.seconds, true);
  bench::print_truth_row("ours on grey", phantom::truth_figures(read_mesh(grey), ph.shape, &map), t_grey, true);
  std::fflush(stdout);
}

void print_real_row(const std::string& label, const std::string& name, const TriangleMesh& m, const Volume& map,
                    double seconds) {
  const Quality q = measure_quality(m, {.self_intersections = false});
  fmt::print("  {:<7} {:<12} {:>9} {:>7} {:>9} {:>6.2f} {:>7}\n", label, name, m.triangles.size(),
             q.topo.closed ? "yes" : "no", q.topo.manifold ? "yes" : "no", slice_phase(m, map).modulation,
             seconds < 0 ? "-" : fmt::format("{:.1f}", seconds));
  std::fflush(stdout);
}

// VOLUME:THRESHOLD:LABEL: the grey-volume rule's count for the label's structure, and ours
// on the label's voxels alone, the same shape.
void bench_grey(const std::string& grey, const std::string& backend, const Volume& map, const fs::path& dir) {
  const size_t b = grey.rfind(':'), a = b == std::string::npos || b == 0 ? std::string::npos : grey.rfind(':', b - 1);
  if (a == std::string::npos) {
    std::fprintf(stderr, "bench_labels: --grey wants VOLUME:THRESHOLD:LABEL\n");
    std::exit(2);
  }
  const std::string out = (dir / "grey.ply").string(), threshold = grey.substr(a + 1, b - a - 1);
  const double t = bench::timed_system(fmt::format("{} run {} --threshold {} --backend {} --quiet -o {}", MPUMESH_BIN,
                                                   grey.substr(0, a), threshold, backend, out));
  const std::string label = grey.substr(b + 1);
  const std::string alone = (dir / "alone.nii.gz").string(), alone_out = (dir / "alone.ply").string();
  write_volume(seg::label_indicator(map, std::stoll(label), 0.0f), alone);
  const double t_alone = bench::timed_system(fmt::format("{} run {} --label 1 --backend {} --quiet -o {}{}", MPUMESH_BIN,
                                                         alone, backend, alone_out, bench::extra_args(kExtraArgs)));
  print_real_row(label, "ours, alone", read_mesh(alone_out), map, t_alone);
  print_real_row(label, "ours, grey", read_mesh(out), map, t);
  fmt::print("  (ours, alone: the label's voxels alone, the others taken as background, the shape the threshold "
             "gives; ours, grey: the grey volume at threshold {})\n",
             threshold);
}

void bench_real(const Args& args, const fs::path& root) {
  const fs::path dir = root / "real";
  fs::create_directories(dir);
  const Volume map = read_volume(args.real);
  fmt::print("{}: {} x {} x {} voxels of {:.3f} x {:.3f} x {:.3f} mm\n", args.real, map.dims[0], map.dims[1],
             map.dims[2], map.spacing.x(), map.spacing.y(), map.spacing.z());
  const double t = bench::timed_system(fmt::format("{} run {} --labels all --separate --backend {} --quiet -o {}{}", MPUMESH_BIN,
                                                   args.real, args.backend, (dir / "label_{label}.ply").string(),
                                                   bench::extra_args(kExtraArgs)));
  fmt::print("  ours: all labels in {:.1f} s\n", t);
  fmt::print("  {:<7} {:<12} {:>9} {:>7} {:>9} {:>6} {:>7}\n", "label", "mesh", "triangles", "closed", "manifold",
             "slice", "s");
  std::vector<std::pair<int64_t, TriangleMesh>> ours;
  for (const auto& [label, voxels] : seg::label_voxel_counts(map)) {
    const std::string path = (dir / fmt::format("label_{}.ply", label)).string();
    if (!fs::exists(path)) {
      fmt::print("  {:<7} skipped ({} voxels)\n", label, voxels);
      continue;
    }
    ours.emplace_back(label, read_mesh(path));
    print_real_row(std::to_string(label), "ours", ours.back().second, map, -1);  // timed together, above
  }
  if (!args.grey.empty()) bench_grey(args.grey, args.backend, map, dir);
  if (!args.mesh3) return;
  for (const auto& [label, mesh] : ours) {
    bench::Mesh3Params m3;
    m3.labels = true;
    const bench::Mesh3Result cg = bench::cgal_mesh3_matching(seg::label_indicator(map, label, 0.0f), m3, mesh);
    print_real_row(std::to_string(label), "CGAL Mesh_3", cg.mesh, map, cg.seconds);
  }
}

}  // namespace

int main(int argc, char** argv) {
  bench::same_memory_for_all(argv);
  const Args args = parse_args(argc, argv);
  const fs::path root = fs::temp_directory_path() / "mpumesh_bench_labels";
  fs::create_directories(root);
  bool header = false;
  for (const auto& ph : phantom::label_suite()) {
    if (!(args.phantoms.empty() && args.real.empty()) &&
        std::find(args.phantoms.begin(), args.phantoms.end(), ph.name) == args.phantoms.end())
      continue;
    if (!std::exchange(header, true))
      fmt::print("columns: triangles, distance to the truth mean / p99 (mm), normal error mean / p95 (deg), K rank "
                 "correlation (f: the PLY's K, d: discrete K), K median error / max|K|, spacing high/low |K| tenth, "
                 "spacing rank correlation with |K|, enclosed volume's error (%), slice-phase modulation of |H|, "
                 "seconds\n");
    bench_phantom(ph, args.backend, root);
  }
  if (!args.real.empty()) bench_real(args, root);
  return 0;
}
