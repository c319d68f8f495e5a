// mpumesh run: the whole job (core/pipeline) from the command line. The command parses
// and checks its options and outputs, runs the pipeline, writes the mesh (and the surface),
// and turns the result into text, the JSON report and the HTML report.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <string_view>

#include "cli_util.h"
#include "component_cli.h"
#include "commands.h"
#include "common/error.h"
#include "common/memory.h"
#include "io/atomic_file.h"
#include "io/mesh_io.h"
#include "io/volume_io.h"
#include "mesh/cgal_geometry.h"
#include "mesh/mesh_separation.h"
#include "io/read_file.h"
#include "mpu/mpu_io.h"
#include "mpu_cli.h"
#include "pipeline/run_pipeline.h"
#include "report_builder.h"
#include "sample_cli.h"
#include "seg_cli.h"
#include "segment/label_map.h"

namespace mpumesh::tools {
namespace {

constexpr std::string_view kLabelField = "{label}";

struct RunCli {
  std::string input, output, report, html, surface, local_fit = "orthopoly";
  SegmentCli seg;
  mpu::FitOptions fit;
  particles::SampleOptions sample;
  BackendOptions backend;
  bool self_intersections = true, partial_volume_caps = false;
  int count_retries = -1;  // -1: 2 when neither --particles nor --spacing is given, else 0
  ComponentFilter components;
  int64_t label = 0;   // --label
  std::string labels;  // --labels: "all" or a list
};

void add_run_options(CLI::App* cmd, RunCli& o) {
  cmd->add_option("input", o.input,
                  "volume (DICOM directory, .dcm, .nii[.gz], .nrrd, .mha/.mhd, .inv3) or mesh (.stl, .ply, .obj, .off)")
      ->required();
  cmd->add_option("-o,--output", o.output, "mesh: .ply, .stl, .obj or .off")->required();
  cmd->add_option("--report", o.report, "write the JSON report here");
  cmd->add_option("--surface", o.surface, "write the fitted implicit surface here (.mpu), e.g. for `polygonize`");
  cmd->add_option("--html", o.html,
                  "write the HTML report here: renders, the comparison with marching cubes and the original MPU, "
                  "histograms, stage times");
  cmd->add_flag("!--no-self-intersections", o.self_intersections, "skip the self-intersection test of the report");
  add_segment_options(cmd, o.seg);
  auto* label = cmd->add_option("--label", o.label,
                                "the input is a label map (whole numbers, 0 the background): mesh the voxels of "
                                "this label")
                    ->check(CLI::PositiveNumber);
  cmd->add_option("--labels", o.labels,
                  "the input is a label map: mesh each label, 'all' (those present; one too small to mesh is "
                  "skipped with a note) or a list such as 3,7,12 (one too small is refused), in that order, reading "
                  "the volume once; a label's mesh is kept out of those of the labels before it; -o, --html and "
                  "--surface must hold {label}, and --report gets a section per label")
      ->excludes(label);
  cmd->add_flag("--partial-volume-caps", o.partial_volume_caps,
                "cap points' heights from the grey of the two slabs the surface crosses, not the contours alone");
  add_fit_options(cmd, o.fit, o.local_fit);
  add_sample_options(cmd, o.sample, "--particle-iterations");
  cmd->add_option("--count-retries", o.count_retries,
                  fmt::format("when the triangulation needs repair points for more than a tenth of the particles "
                              "(too sparse a sample for the surface's thin plates), sample again with {} times the "
                              "particles, up to this many times; default 2 when neither --particles nor --spacing "
                              "is given, 0 when one is",
                              pipeline::kRaise))
      ->check(CLI::Range(0, 8));
  add_component_options(cmd, o.components);
  add_backend_options(cmd, o.backend);
}

// `path` with its "{label}" replaced by the label.
std::string with_label(std::string path, int64_t label) {
  for (size_t at; (at = path.find(kLabelField)) != std::string::npos;)
    path.replace(at, kLabelField.size(), std::to_string(label));
  return path;
}

// A label map's options: a volume, no segmentation options (its labels are the
// segmentation), and with --labels one path per label for the mesh and the per-label files.
void check_label_options(const RunCli& o) {
  const bool many = !o.labels.empty();
  if (o.label == 0 && !many) return;
  const char* flag = many ? "--labels" : "--label";
  if (pipeline::is_mesh_path(o.input))
    throw InputError(fmt::format("{}: {} needs a label map (a volume), not a mesh", o.input, flag));
  if (o.seg.threshold_given || !o.seg.method.empty() || !o.seg.window.empty() || o.partial_volume_caps)
    throw InputError(fmt::format("{}: a label map is segmented by its labels: --threshold, --method, --window and "
                                 "--partial-volume-caps do not apply",
                                 flag));
  if (!many) return;
  seg::parse_label_list(o.labels);  // its errors now, before the volume is read
  for (const std::string* path : {&o.output, &o.html, &o.surface})
    if (!path->empty() && path->find(kLabelField) == std::string::npos)
      throw InputError(fmt::format("{}: --labels writes one file per label: the path must hold {} (for example "
                                   "out/bone_{}.ply)",
                                   *path, kLabelField, kLabelField));
}

// Every output and parameter, checked before the long work starts; the pipeline's options.
pipeline::RunOptions checked_options(RunCli& o, const CommonOptions& common) {
  check_label_options(o);
  check_writable(with_label(o.output, 0));
  mesh_format_from_path(o.output);
  if (!o.report.empty()) check_writable(o.report);
  if (!o.surface.empty()) check_writable(with_label(o.surface, 0));
  if (!o.html.empty()) {
    check_writable(with_label(o.html, 0));
    if (lower_extension(o.html) != ".html") throw InputError(o.html + ": the HTML report must be a .html file");
  }
  o.fit.local_fit = o.local_fit == "quadric" ? mpu::LocalFit::kQuadric : mpu::LocalFit::kOrthopoly;
  mpu::validate(o.fit);
  particles::validate(o.sample, "run", "particle-iterations");
  pipeline::RunOptions r;
  if (!pipeline::is_mesh_path(o.input)) r.segment = resolve(o.seg);
  r.label = o.label;
  r.points.partial_volume_caps = o.partial_volume_caps;
  r.fit = o.fit;
  r.sample = o.sample;
  r.count_retries = o.count_retries;
  r.components = o.components;
  r.quality = !o.report.empty() || common.json || !common.quiet;
  r.quality_options.self_intersections = o.self_intersections;
  r.baselines = !o.html.empty();
  return r;
}

// The stages' times go to the progress lines and the report; the pipeline's notes go to
// standard output unless quiet or --json.
class RunObserver : public pipeline::Observer {
 public:
  RunObserver(Progress& progress, bool print_notes) : progress_(progress), print_notes_(print_notes) {}
  void begin(const std::string& stage) override { progress_.begin(stage); }
  void end() override { progress_.end(); }
  void note(const std::string& line) override {
    if (print_notes_) std::cout << line << "\n";
  }

 private:
  Progress& progress_;
  bool print_notes_;
};

nlohmann::json input_json(const pipeline::InputInfo& in) {
  if (in.mesh)
    return {{"path", in.path}, {"kind", "mesh"}, {"vertices", in.vertices}, {"triangles", in.triangles}};
  return {{"path", in.path},
          {"kind", "volume"},
          {"dims", in.dims},
          {"spacing_mm", {in.spacing.x(), in.spacing.y(), in.spacing.z()}},
          {"modality", in.modality},
          {"read_notes", in.read_notes}};
}

// The JSON report (without the stage times, the HTML path and the memory peak, which
// come last).
nlohmann::json run_json(const RunCli& o, const std::string& output, const pipeline::RunResult& r,
                        const vk::BackendChoice& choice) {
  nlohmann::json j;
  j["input"] = input_json(r.input);
  if (!r.input.mesh) j["segmentation"] = segment_json(r.segment_options, r.segmentation);
  j["points"] = r.points;
  j["fit"] = fit_json(r.fit_options, r.fit);
  j["fit"]["eps_source"] = r.tolerance.source.empty()
                               ? (r.eps_given ? "--eps" : "a quarter of the points' median spacing")
                               : r.tolerance.source;
  if (r.tolerance.noise > 0) j["fit"]["point_noise_mm"] = r.tolerance.noise;
  j["particles"] = sample_json(r.sample_options, r.sample, r.particles);
  j["particles"]["kernel_ms"] = r.particle_kernel_ms;
  nlohmann::json raises = nlohmann::json::array();
  for (const pipeline::CountRaise& c : r.raises)
    raises.push_back({{"requested_particles", c.requested_particles},
                      {"requested_spacing_mm", c.requested_spacing_mm},
                      {"asked_particles", c.asked_particles},
                      {"particles", c.particles},
                      {"repair_points", c.repair_points},
                      {"next_requested_particles", c.next_requested_particles},
                      {"next_requested_spacing_mm", c.next_requested_spacing_mm}});
  j["particles"]["count_raises"] = raises;
  j["triangulation"] = triangulation_json(r.triangulation);
  j["backend"] = backend_json(choice);
  j["kernel_ms"] = choice.backend->kernel_ms();
  j["output"] = output;
  j["vertices"] = r.mesh.vertices.size();
  j["triangles"] = r.mesh.triangles.size();
  if (o.components.active()) j["components_filter"] = components_json(o.components, r.components_kept, r.components_dropped);
  if (r.has_quality) j["quality"] = quality_to_json(r.quality);
  j["notes"] = r.notes;
  j["version"] = MPUMESH_VERSION;
  return j;
}

void print_summary(const RunCli& o, const std::string& output, const pipeline::RunResult& r,
                   const vk::BackendChoice& choice) {
  if (o.components.active()) std::cout << components_text(r.components_kept, r.components_dropped);
  if (r.has_quality)
    std::cout << output << ": " << r.mesh.triangles.size() << " triangles from " << r.particles.size()
              << " particles (" << choice.backend->device() << ")\n"
              << quality_to_text(r.quality);
  if (r.sparse) std::cout << "note: " << r.notes.back() << "\n";
}

void write_html(const std::string& output, const std::string& html, const pipeline::RunResult& r,
                const nlohmann::json& j, ComputeBackend& backend, Progress& progress) {
  progress.begin("report");
  ReportInputs in;
  in.ours = {std::filesystem::path(output).filename().string() + " (ours)", &r.mesh};
  for (const auto& [name, m] : r.baselines) in.baselines.push_back({name, &m});
  in.run = j;
  write_file_atomically(build_report(in, backend), html);
  progress.end();
}

nlohmann::json memory_json(const pipeline::RunResult& r) {
  return {{"estimate_gib", double(r.memory_estimate) / double(1ull << 30)},
          {"available_gib", double(available_memory_bytes()) / double(1ull << 30)},
          {"peak_rss_gib", double(peak_rss_bytes()) / double(1ull << 30)}};
}

// The one run of `mpumesh run` (a volume, one label of a label map, or a mesh).
void run_one(const RunCli& o, const pipeline::RunOptions& options, const CommonOptions& common) {
  Progress progress(common.quiet || common.json);
  RunObserver observer(progress, !common.json && !common.quiet);
  vk::BackendChoice choice;
  const pipeline::BackendOpener open = [&]() -> ComputeBackend& {
    choice = open_backend(o.backend, common, progress);
    return *choice.backend;
  };
  const pipeline::RunResult r = pipeline::run_pipeline(o.input, options, open, &observer);
  progress.begin("write mesh");
  write_mesh(r.mesh, o.output);
  if (!o.surface.empty()) write_mpu(r.surface, o.surface);
  progress.end();
  nlohmann::json j = run_json(o, o.output, r, choice);
  if (options.label > 0) j["label"] = options.label;
  if (!common.json && !common.quiet) print_summary(o, o.output, r, choice);
  j["stage_seconds"] = stage_json(progress);
  j["memory"] = memory_json(r);
  if (!o.html.empty()) {
    write_html(o.output, o.html, r, j, *choice.backend, progress);
    j["html"] = o.html;
  }
  if (!o.report.empty()) write_json_file(j, o.report);
  if (common.json) std::cout << j.dump(2) << '\n';
}

// --labels: the labels to mesh, each present and, when named, large enough.
std::vector<int64_t> labels_to_mesh(const RunCli& o, const std::map<int64_t, int64_t>& counts) {
  const std::vector<int64_t> named = seg::parse_label_list(o.labels);
  if (counts.empty()) throw InputError(o.input + ": the label map holds no label (every voxel is 0)");
  std::string present;
  for (const auto& [l, n] : counts) present += (present.empty() ? "" : ", ") + std::to_string(l);
  if (named.empty()) {
    std::vector<int64_t> all;
    for (const auto& [l, n] : counts) all.push_back(l);
    return all;
  }
  for (const int64_t l : named) {
    const auto it = counts.find(l);
    if (it == counts.end())
      throw InputError(fmt::format("{}: no voxel holds label {} (the labels present: {})", o.input, l, present));
    const std::string small = seg::too_small_to_mesh(it->second);
    if (!small.empty()) throw InputError(seg::label_name(o.input, l) + ": " + small);
  }
  return named;
}

// One label's outputs, written to temporaries and renamed together when every label is
// done, so that a run that fails leaves no output.
struct PendingOutputs {
  std::vector<std::unique_ptr<AtomicFile>> files;
  const std::string& add(const std::string& target) {
    files.push_back(std::make_unique<AtomicFile>(target));
    return files.back()->temp_path();
  }
  void commit() {
    for (auto& f : files) f->commit();
  }
};

// A label's mesh (vertices and triangles only), for the check that no two cross.
struct LabelShape {
  int64_t label;
  TriangleMesh mesh;
};

bool boxes_overlap(const TriangleMesh& a, const TriangleMesh& b) {
  auto box = [](const TriangleMesh& m) {
    Eigen::AlignedBox3d x;
    for (const auto& v : m.vertices) x.extend(v);
    return x;
  };
  return box(a).intersects(box(b));
}

// The triangle pairs by which two labels' meshes cross, for every two whose boxes overlap
// (the separation that touching labels keep is in seg/label_map.h).
nlohmann::json label_crossings(const std::vector<LabelShape>& shapes, bool talk) {
  nlohmann::json out = nlohmann::json::array();
  for (size_t a = 0; a < shapes.size(); ++a)
    for (size_t b = a + 1; b < shapes.size(); ++b) {
      if (!boxes_overlap(shapes[a].mesh, shapes[b].mesh)) continue;
      const int64_t n = count_crossings(shapes[a].mesh, shapes[b].mesh);
      out.push_back({{"labels", {shapes[a].label, shapes[b].label}}, {"triangle_pairs", n}});
      if (talk && n > 0)
        std::cout << fmt::format("note: the meshes of labels {} and {} cross ({} triangle pairs)\n", shapes[a].label,
                                 shapes[b].label, n);
    }
  return out;
}

// A label meshed after others that it touches moves its vertices out of theirs
// (mesh/mesh_separation.h), to a tenth of a voxel from them, and its quality is measured
// again; null when no earlier label is near.
nlohmann::json yield_to_earlier_labels(pipeline::RunResult& r, const std::vector<LabelShape>& earlier, double voxel,
                                       const pipeline::RunOptions& options) {
  std::vector<const TriangleMesh*> near;
  for (const LabelShape& e : earlier)
    if (boxes_overlap(r.mesh, e.mesh)) near.push_back(&e.mesh);
  if (near.empty()) return nullptr;
  const SeparationStats s = separate_from(r.mesh, near, 0.1 * voxel);
  if (s.moved_vertices > 0 && r.has_quality) r.quality = measure_quality(r.mesh, options.quality_options);
  nlohmann::json against = nlohmann::json::array();
  for (const LabelShape& e : earlier)
    if (boxes_overlap(r.mesh, e.mesh)) against.push_back(e.label);
  return {{"against_labels", against},          {"crossings_before", s.crossings_before},
          {"crossings_after", s.crossings_after}, {"moved_vertices", s.moved_vertices},
          {"reverted_vertices", s.reverted_vertices}, {"rounds", s.rounds},
          {"max_move_mm", s.max_move_mm}};
}

// --labels: every label of a label map, the volume read once; the report has a section
// per label and lists the labels skipped.
void run_labels(const RunCli& o, const pipeline::RunOptions& base, const CommonOptions& common) {
  const bool talk = !common.json && !common.quiet;
  Progress progress(!talk);
  progress.begin("read volume");
  const Volume vol = read_volume(o.input);
  progress.end();
  const std::map<int64_t, int64_t> counts = seg::label_voxel_counts(vol);
  const std::vector<int64_t> todo = labels_to_mesh(o, counts);
  const bool all = o.labels == "all";
  vk::BackendChoice choice;
  const pipeline::BackendOpener open = [&]() -> ComputeBackend& {
    if (!choice.backend) choice = open_backend(o.backend, common, progress);
    return *choice.backend;
  };
  PendingOutputs pending;
  std::vector<LabelShape> shapes;
  nlohmann::json meshed = nlohmann::json::array(), skipped = nlohmann::json::array();
  auto skip = [&](int64_t l, const std::string& why) {
    skipped.push_back({{"label", l}, {"voxels", counts.at(l)}, {"reason", why}});
    if (talk) std::cout << "note: " << seg::label_name(o.input, l) << ": skipped: " << why << "\n";
  };
  for (const int64_t l : todo) {
    const std::string small = seg::too_small_to_mesh(counts.at(l));
    if (!small.empty()) {
      skip(l, small);
      continue;
    }
    pipeline::RunOptions options = base;
    options.label = l;
    Progress lp(!talk);
    RunObserver observer(lp, talk);
    pipeline::RunResult r;
    try {
      r = pipeline::run_pipeline(vol, options, open, &observer);
    } catch (const std::exception& e) {  // InputError or NumericalError: this label's own
      if (!all || !(dynamic_cast<const InputError*>(&e) || dynamic_cast<const NumericalError*>(&e))) throw;
      skip(l, e.what());
      continue;
    }
    const nlohmann::json separation = yield_to_earlier_labels(r, shapes, vol.in_plane_spacing(), base);
    const std::string out = with_label(o.output, l);
    write_mesh(r.mesh, pending.add(out));
    if (!o.surface.empty()) write_mpu(r.surface, pending.add(with_label(o.surface, l)));
    nlohmann::json j = run_json(o, out, r, choice);
    j["label"] = l;
    if (!separation.is_null()) j["separation"] = separation;
    if (talk) print_summary(o, out, r, choice);
    j["stage_seconds"] = stage_json(lp);
    j["memory"] = memory_json(r);
    if (!o.html.empty()) {
      const std::string html = with_label(o.html, l);
      write_html(out, pending.add(html), r, j, *choice.backend, lp);
      j["html"] = html;
    }
    meshed.push_back(std::move(j));
    shapes.push_back({l, {}});
    shapes.back().mesh.vertices = r.mesh.vertices;
    shapes.back().mesh.triangles = r.mesh.triangles;
  }
  if (meshed.empty()) throw InputError(o.input + ": no label could be meshed (" + skipped.dump() + ")");
  progress.begin("label crossings");
  const nlohmann::json crossings = label_crossings(shapes, talk);
  progress.end();
  pending.commit();
  nlohmann::json j = {{"input", o.input},      {"labels", meshed},        {"skipped", skipped},
                      {"crossings", crossings}, {"version", MPUMESH_VERSION}};
  if (talk)
    std::cout << fmt::format("{} labels meshed, {} skipped\n", meshed.size(), skipped.size());
  j["stage_seconds"] = stage_json(progress);
  if (!o.report.empty()) write_json_file(j, o.report);
  if (common.json) std::cout << j.dump(2) << '\n';
}

}  // namespace

void add_run_command(CLI::App& app, CommonOptions& common, std::function<void()>& action) {
  auto o = std::make_shared<RunCli>();
  auto* cmd = app.add_subcommand(
      "run", "The whole job: a CT/MR volume (or a surface mesh, to remesh it) to a smooth adaptive mesh");
  add_run_options(cmd, *o);
  add_common(cmd, common);
  cmd->callback([&common, &action, o] {
    action = [&common, o] {
      const pipeline::RunOptions options = checked_options(*o, common);
      if (o->labels.empty()) run_one(*o, options, common);
      else run_labels(*o, options, common);
    };
  });
}

}  // namespace mpumesh::tools
