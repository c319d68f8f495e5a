#include "run_cli.h"

#include <fmt/format.h>

#include "common/error.h"
#include "common/memory.h"
#include "io/atomic_file.h"
#include "io/mesh_io.h"
#include "io/read_file.h"
#include "io/tet_io.h"
#include "mpu_cli.h"
#include "option_spelling.h"
#include "sample_cli.h"
#include "component_cli.h"
#include "segment/label_map.h"
#include "tet_cli.h"

namespace mpumesh::tools {

void add_run_paths(CLI::App* cmd, RunCli& o) {
  cmd->add_option("input", o.input,
                  "volume (DICOM directory, .dcm, .nii[.gz], .nrrd, .mha/.mhd, .inv3) or mesh (.stl, .ply, .obj, .off)")
      ->required();
  cmd->add_option("-o,--output", o.output, "mesh: .ply, .stl, .obj or .off")->required();
  cmd->add_option("--report", o.report, "write the JSON report here");
  cmd->add_option("--surface", o.surface, "write the fitted implicit surface here (.mpu), e.g. for `polygonize`");
  cmd->add_option("--html", o.html,
                  "write the HTML report here: renders, the comparison with marching cubes and the original MPU, "
                  "histograms, stage times; for a complex its labels, interfaces and junction curves, rendered "
                  "by label");
  cmd->add_option("--volume", o.volume,
                  "also fill the mesh with tetrahedra for finite elements (its triangles their boundary) and write "
                  "them here: .msh (gmsh 4.1), .vtu (VTK), .mesh (medit) or .inp (Abaqus/CalculiX, mesh only); a "
                  "complex of labels or parts gives one volume mesh, a region per label, with a group per label "
                  "and per interface");
}

void add_run_parameters(CLI::App* cmd, RunCli& o) {
  cmd->add_flag("!--no-self-intersections", o.self_intersections, "skip the self-intersection test of the report");
  add_segment_options(cmd, o.seg);
  auto* label = cmd->add_option("--label", o.label,
                                "the input is a label map (whole numbers, 0 the background): mesh the voxels of "
                                "this label")
                    ->check(CLI::PositiveNumber);
  cmd->add_option("--labels", o.labels,
                  "the input is a label map: mesh each label, 'all' (those present; one too small to mesh is "
                  "skipped with a note) or a list such as 3,7,12 (one too small is refused; the labels not named "
                  "count as background), as one multi-material complex whose interfaces the labels share: -o "
                  "without {label} writes the complex as one PLY whose faces carry label_a < label_b (0 the "
                  "background), with {label} each label's closed boundary cut from it; --surface must hold "
                  "{label}; --report gets the complex's figures")
      ->excludes(label);
  cmd->add_flag("--separate", o.separate,
                "with --labels: mesh each label's own surface instead of one complex (a label's mesh kept out of "
                "those of the labels before it); -o, --html and --surface must hold {label}, and --report gets a "
                "section per label. With a surface mesh of several closed parts (by default remeshed as one "
                "complex of them, numbered by volume, largest first; a marching-cubes surface always as one "
                "surface): remesh it as one surface, whose parts may fuse where they come closer than the fit "
                "resolves");
  cmd->add_flag("--ruled-caps", o.ruled_caps,
                "cap points' heights from the contours alone (a ruled surface between two slices' contours), not "
                "from the grey of the two slabs the surface crosses");
  add_fit_options(cmd, o.fit, o.local_fit);
  add_sample_options(cmd, o.sample, "--particle-iterations");
  cmd->add_option("--count-retries", o.count_retries,
                  fmt::format("when the triangulation needs repair points for more than a tenth of the particles "
                              "(too sparse a sample for the surface's thin plates), sample again with {} times the "
                              "particles, up to this many times; default 2 when neither --particles nor --spacing "
                              "is given, 0 when one is",
                              pipeline::kRaise))
      ->check(CLI::Range(0, 8));
  cmd->add_option("--optimize-rounds", o.optimize_rounds,
                  "rounds of mesh optimisation after the triangulation (Delaunay flips, collapses of short edges and "
                  "centroidal relaxation on the surface); 0: none")
      ->check(CLI::Range(0, 50))
      ->capture_default_str();
  add_tet_options(cmd, o.tet, "volume-");
  add_component_options(cmd, o.components);
  cmd->add_flag("--keep-specks", o.keep_specks,
                "keep the structures that enclose less than a tenth of a voxel (from a volume they are dropped: below "
                "what the scan resolves)");
  add_backend_options(cmd, o.backend);
  cmd->add_option("--threads", o.threads, "use at most this many threads (default: every core)")
      ->check(CLI::PositiveNumber);
}

// `path` with its "{label}" replaced by the label.
std::string with_label(std::string path, int64_t label) {
  for (size_t at; (at = path.find(kLabelField)) != std::string::npos;)
    path.replace(at, kLabelField.size(), std::to_string(label));
  return path;
}

namespace {

// A label map's options: a volume, no segmentation options (its labels are the
// segmentation), and with --labels one path per label for the mesh and the per-label files.
void check_label_options(const RunCli& o) {
  const bool many = !o.labels.empty();
  if (o.separate && !many && !pipeline::is_mesh_path(o.input))
    throw InputError("--separate: applies to --labels and to surface meshes");
  if (o.label == 0 && !many) return;
  const char* flag = many ? "--labels" : "--label";
  if (pipeline::is_mesh_path(o.input))
    throw InputError(fmt::format("{}: {} needs a label map (a volume), not a mesh", o.input, flag));
  if (o.seg.threshold_given || !o.seg.method.empty() || !o.seg.window.empty())
    throw InputError(fmt::format("{}: a label map is segmented by its labels: --threshold, --method and --window do "
                                 "not apply",
                                 flag));
  if (!many) return;
  if (!o.volume.empty() && o.separate)
    throw InputError("--volume: one volume mesh of the labels, a region each, comes from their complex (without "
                     "--separate)");
  seg::parse_label_list(o.labels);  // its errors now, before the volume is read
  if (!o.separate) check_complex_outputs(o, "--labels");
  if (o.separate) check_label_paths({&o.output, &o.html, &o.surface}, "--labels");
}

}  // namespace

void check_label_paths(const std::vector<const std::string*>& paths, const std::string& what) {
  for (const std::string* path : paths)
    if (!path->empty() && path->find(kLabelField) == std::string::npos)
      throw InputError(fmt::format("{}: {} writes one file per label: the path must hold {} (for example "
                                   "out/bone_{}.ply)",
                                   *path, what, kLabelField, kLabelField));
}

void check_complex_outputs(const RunCli& o, const std::string& what) {
  if (o.html.find(kLabelField) != std::string::npos)
    throw InputError(fmt::format("{}: the complex of {} has one HTML report: the path must not hold {}", o.html, what,
                                 kLabelField));
  if (o.output.find(kLabelField) == std::string::npos && mesh_format_from_path(o.output) != MeshFormat::kPly)
    throw InputError(o.output + ": the complex is written as PLY, whose faces carry label_a and label_b (or "
                                "put {label} in the path for one closed surface per label)");
  check_label_paths({&o.surface}, what);
}

void check_run_outputs(const RunCli& o) {
  check_label_options(o);
  check_writable(with_label(o.output, 0));
  mesh_format_from_path(o.output);
  if (!o.report.empty()) check_writable(o.report);
  if (!o.surface.empty()) check_writable(with_label(o.surface, 0));
  if (o.tet.background && o.volume.empty()) throw InputError("--volume-background: applies to --volume");
  if (!o.volume.empty()) {
    tet_format_from_path(o.volume);
    check_writable(o.volume);
  }
  if (!o.html.empty()) {
    check_writable(with_label(o.html, 0));
    if (lower_extension(o.html) != ".html") throw InputError(o.html + ": the HTML report must be a .html file");
  }
}

pipeline::RunOptions run_options(RunCli& o, const CommonOptions& common, const std::string& command) {
  check_label_options(o);
  o.fit.local_fit = o.local_fit == "quadric" ? mpu::LocalFit::kQuadric : mpu::LocalFit::kOrthopoly;
  mpu::validate(o.fit);
  as_command(command, [&] {
    particles::validate(o.sample);
    validate(o.tet);
  });
  pipeline::RunOptions r;
  if (!pipeline::is_mesh_path(o.input)) r.segment = resolve(o.seg);
  r.label = o.label;
  r.points.partial_volume_caps = !o.ruled_caps;
  r.fit = o.fit;
  r.sample = o.sample;
  r.count_retries = o.count_retries;
  r.optimize.rounds = o.optimize_rounds;
  if (!o.volume.empty()) r.volume_mesh = o.tet;
  r.components = o.components;
  if (o.keep_specks) r.speck_voxels = 0;
  if (!o.report.empty() || common.json || !common.quiet) r.quality->self_intersections = o.self_intersections;
  else r.quality.reset();
  r.spacing_figures = !o.report.empty() || !o.html.empty() || common.json;
  r.baselines = !o.html.empty();
  return r;
}

}  // namespace mpumesh::tools
