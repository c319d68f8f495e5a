// mpumesh run: the whole job (core/pipeline) from the command line. The command parses
// and checks its options and outputs, runs the pipeline, writes the mesh (and the surface),
// and turns the result into text, the JSON report and the HTML report.
#include <fmt/format.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>

#include "cli_util.h"
#include "common/error.h"
#include "common/memory.h"
#include "complex_report.h"
#include "component_cli.h"
#include "cpu/cpu_backend.h"
#include "io/atomic_file.h"
#include "mesh/component_filter.h"
#include "mesh/voxel_grid.h"
#include "io/mesh_io.h"
#include "io/tet_io.h"
#include "io/volume_io.h"
#include "mpu/mpu_io.h"
#include "option_spelling.h"
#include "geometry/drop_unused.h"
#include "multi/complex_figures.h"
#include "pipeline/complex_run.h"
#include "pipeline/label_runs.h"
#include "report_builder.h"
#include "run_json.h"
#include "run_cli.h"
#include "tet_cli.h"
#include "segment/label_map.h"

namespace mpumesh::tools {
namespace {

// The pipeline's stages go to the progress lines; its notes to standard output, spelled
// as the command's options, unless quiet or --json.
class RunObserver : public pipeline::Observer {
 public:
  RunObserver(Progress& progress, bool print_notes) : progress_(progress), print_notes_(print_notes) {}
  void begin(const std::string& stage) override { progress_.begin(stage); }
  void end() override { progress_.end(); }
  void progress(const std::string& stage, double fraction) override { progress_.fraction(stage, fraction); }
  void note(const std::string& line) override {
    if (print_notes_) std::cout << cli_text(line, "run") << "\n";
  }

 private:
  Progress& progress_;
  bool print_notes_;
};

void print_summary(const RunCli& o, const std::string& output, const pipeline::RunResult& r,
                   const vk::BackendChoice& choice) {
  if (r.components) std::cout << components_text(r.components->kept, r.components->dropped);
  if (r.quality)
    std::cout << output << ": " << r.mesh.triangles.size() << " triangles from " << r.particles.size()
              << " particles (" << choice.backend->device() << ")\n"
              << quality_to_text(*r.quality);
  if (r.sparse) std::cout << "note: " << cli_text(r.notes.back(), "run") << "\n";
  if (r.volume) std::cout << tet_text(o.volume, r.volume->stats);
}

// The HTML report of a run, written to `html`.
void write_html(const std::string& output, const std::string& html, const pipeline::RunResult& r,
                const nlohmann::json& j, const vk::BackendChoice& choice, const Progress& own, Progress& progress) {
  progress.begin("report");
  ReportInputs in;
  in.ours = {std::filesystem::path(output).filename().string() + " (ours)", &r.mesh};
  for (const auto& [name, m] : r.baselines) in.baselines.push_back({name, &m});
  in.run.result = &r;
  in.run.device = choice.backend->device();
  in.run.stage_seconds = r.stage_seconds;
  for (const auto& st : own.stage_seconds()) in.run.stage_seconds.push_back(st);
  in.run.parameters = report_parameters(j);
  in.run.spell = cli_spelling("run");
  write_file_atomically(build_report(in, *choice.backend), html);
  progress.end();
}

// Where a run's HTML report goes: the file written (a temporary, for --labels) and the
// path the JSON report names.
struct HtmlTarget {
  std::string write_to, name;
};

// A run's JSON report and, with an HTML target, its HTML report; the caller adds what else
// it knows (the label) before the HTML is written.
nlohmann::json report_run(const RunCli& o, const std::string& output, const HtmlTarget& html,
                          const pipeline::RunResult& r, const vk::BackendChoice& choice, Progress& own,
                          const std::function<void(nlohmann::json&)>& add) {
  nlohmann::json j = run_json(r, {output, o.volume, &choice, cli_spelling("run")});
  add(j);
  j["stage_seconds"] = stage_seconds_json(r.stage_seconds, own);
  j["memory"] = memory_json(r);
  if (!html.write_to.empty()) {
    write_html(output, html.write_to, r, j, choice, own, own);
    j["html"] = html.name;
  }
  return j;
}

// The one run of `mpumesh run` (a volume, one label of a label map, or a mesh; `mesh`: the
// mesh already read).
void run_one(const RunCli& o, const pipeline::RunOptions& options, const CommonOptions& common,
             const TriangleMesh* mesh = nullptr) {
  // The pipeline's stages are shown on `shown`; the command's own (the backend, writing,
  // the report) on `own`, whose times the report adds to the pipeline's.
  Progress shown(common.quiet || common.json, common.progress), own(common.quiet || common.json);
  RunObserver observer(shown, !common.json && !common.quiet);
  EarlyBackend early(o.backend);
  vk::BackendChoice choice;
  const pipeline::BackendOpener open = [&]() -> ComputeBackend& {
    choice = early.open(common, own);
    return *choice.backend;
  };
  const pipeline::RunResult r = mesh ? pipeline::run_pipeline(*mesh, o.input, options, open, &observer)
                                      : pipeline::run_pipeline(o.input, options, open, &observer);
  own.begin("write mesh");
  write_mesh(r.mesh, o.output);
  if (!o.surface.empty()) write_mpu(r.surface, o.surface);
  if (r.volume) write_tet_mesh(r.volume->mesh, o.volume);
  own.end();
  if (!common.json && !common.quiet) print_summary(o, o.output, r, choice);
  if (o.html.empty() && o.report.empty() && !common.json) return;
  const nlohmann::json j = report_run(o, o.output, {o.html, o.html}, r, choice, own, [&](nlohmann::json& j) {
    if (options.label > 0) j["label"] = options.label;
  });
  if (!o.report.empty()) write_json_file(j, o.report);
  if (common.json) std::cout << j.dump(2) << '\n';
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

// What every --labels run starts from: the volume read once, the labels to mesh, the
// backend opened when first needed. The labels' stages are shown on `shown` (each run
// keeps its own times); the command's own (reading, the backend) on `progress`.
struct LabelMapRun {
  LabelMapRun(const RunCli& o, const CommonOptions& common)
      : common(common), talk(!common.json && !common.quiet), shown(!talk, common.progress), progress(!talk),
        observer(shown, talk),
        early(o.backend) {
    progress.begin("read volume");
    vol = read_volume(o.input);
    progress.end();
    todo = pipeline::labels_to_mesh(o.input, seg::parse_label_list(o.labels), seg::label_voxel_counts(vol));
    open = [this]() -> ComputeBackend& {
      if (!choice.backend) choice = early.open(this->common, progress);
      return *choice.backend;
    };
  }
  LabelMapRun(const LabelMapRun&) = delete;
  LabelMapRun& operator=(const LabelMapRun&) = delete;

  const CommonOptions& common;
  const bool talk;
  Progress shown, progress;
  RunObserver observer;
  EarlyBackend early;
  Volume vol;
  std::vector<int64_t> todo;
  vk::BackendChoice choice;
  pipeline::BackendOpener open;
};

// --labels --separate: every label of a label map, the volume read once
// (pipeline/label_runs.h); the report has a section per label and lists the labels skipped.
void run_labels(const RunCli& o, const pipeline::RunOptions& base, const CommonOptions& common) {
  LabelMapRun lm(o, common);
  const bool talk = lm.talk;
  vk::BackendChoice& choice = lm.choice;
  Progress& progress = lm.progress;
  PendingOutputs pending;
  nlohmann::json meshed = nlohmann::json::array();
  const auto on_label = [&](pipeline::LabelRun& run) {
    const pipeline::RunResult& r = run.result;
    const std::string out = with_label(o.output, run.label);
    write_mesh(r.mesh, pending.add(out));
    if (!o.surface.empty()) write_mpu(r.surface, pending.add(with_label(o.surface, run.label)));
    if (talk) print_summary(o, out, r, choice);
    HtmlTarget html;
    if (!o.html.empty()) html = {pending.add(with_label(o.html, run.label)), with_label(o.html, run.label)};
    Progress own(!talk);
    meshed.push_back(report_run(o, out, html, r, choice, own, [&](nlohmann::json& j) { add_label_json(j, run); }));
  };
  const pipeline::LabelsResult result =
      pipeline::run_labels(lm.vol, lm.todo, o.labels == "all", base, lm.open, &lm.observer, on_label);
  pending.commit();
  nlohmann::json j = {{"input", o.input},
                      {"labels", meshed},
                      {"skipped", skipped_labels_json(result.skipped)},
                      {"crossings", label_crossings_json(result.crossings)},
                      {"version", MPUMESH_VERSION}};
  if (talk) std::cout << fmt::format("{} labels meshed, {} skipped\n", result.meshed.size(), result.skipped.size());
  j["stage_seconds"] = stage_seconds_json({}, progress);
  if (!o.report.empty()) write_json_file(j, o.report);
  if (common.json) std::cout << j.dump(2) << '\n';
}

// The complex's outputs: the whole as one PLY with label_a, label_b, or with {label} in the
// path each label's closed boundary cut from it (neighbours share their interface's
// vertices exactly).
void write_complex(const RunCli& o, const pipeline::ComplexResult& r, PendingOutputs& pending) {
  if (r.volume) write_tet_mesh(r.volume->mesh, pending.add(o.volume));
  if (o.output.find(kLabelField) == std::string::npos) {
    write_mesh(r.complex.mesh, pending.add(o.output));
    return;
  }
  for (const pipeline::ComplexRegion& g : r.regions) {
    TriangleMesh m = multi::label_boundary(r.complex.mesh, g.label);
    drop_unused_points(m.vertices, m.triangles);
    write_mesh(m, pending.add(with_label(o.output, g.label)));
  }
}

// The complex's HTML report, written with the other outputs (`pending`).
void write_complex_html(const RunCli& o, const pipeline::ComplexResult& r, const nlohmann::json& j,
                        const vk::BackendChoice& choice, Progress& progress, PendingOutputs& pending) {
  progress.begin("report");
  ComplexReportInputs in;
  in.name = std::filesystem::path(o.output).filename().string();
  in.input = o.input;
  in.result = &r;
  in.stage_seconds = {{"labels", r.seconds_labels},
                      {"union", r.seconds_union},
                      {"complex", r.seconds_complex},
                      {"volume mesh", r.seconds_volume}};
  for (const auto& st : progress.stage_seconds()) in.stage_seconds.push_back(st);
  for (const char* key : {"sample", "triangulation", "optimization"}) in.parameters[key] = j["complex"][key];
  CpuBackend cpu;
  ComputeBackend& backend = choice.backend ? *choice.backend : static_cast<ComputeBackend&>(cpu);
  in.device = backend.device();
  write_file_atomically(build_complex_report(in, backend), pending.add(o.html));
  progress.end();
}

// A complex's outputs written (with `pending`, the files its runs added), its warnings and
// summary printed, its report written.
void finish_complex(const RunCli& o, const pipeline::ComplexResult& r, const vk::BackendChoice& choice,
                    const CommonOptions& common, PendingOutputs& pending, Progress& progress) {
  progress.begin("write mesh");
  write_complex(o, r, pending);
  progress.end();
  nlohmann::json j = complex_run_json(r, o.input, {o.output, o.volume, choice.backend ? &choice : nullptr, {}});
  if (!o.html.empty()) {
    write_complex_html(o, r, j, choice, progress, pending);
    j["html"] = o.html;
  }
  pending.commit();
  const multi::ComplexFigures& f = r.figures;
  const char* region = r.from_mesh ? "part" : "label";
  int64_t open_edges = 0;
  int64_t pinched = 0;
  for (const multi::RegionFigures& g : f.regions) {
    open_edges += g.defects;
    pinched += g.pinched_vertices;
    if (g.defects > 0 && !common.quiet)
      std::cerr << fmt::format("mpumesh: warning: {} {}'s boundary in the complex has {} edges that are not closed "
                               "and oriented (a sample too sparse there)\n",
                               region, g.label, g.defects);
  }
  if (!common.json && !common.quiet)
    std::cout << fmt::format(
        "{}: {} {}s, {} triangles, {} interfaces, {} junction curves ({:.1f} mm), smallest angle {:.1f} deg, "
        "{} crossing pairs, {} shells removed, every {} closed: {}, pinched vertices: {}\n",
        o.output, f.regions.size(), region, r.complex.mesh.triangles.size(), f.interfaces.size(), f.junction_curves,
        f.junction_length_mm, f.min_angle_deg, f.crossing_pairs, r.shells_removed, region,
        open_edges == 0 ? "yes" : "no", pinched);
  if (r.volume && !common.json && !common.quiet) std::cout << tet_text(o.volume, r.volume->stats);
  j["stage_seconds"] = stage_seconds_json({}, progress);
  if (!o.report.empty()) write_json_file(j, o.report);
  if (common.json) std::cout << j.dump(2) << '\n';
}

// --labels without --separate: one multi-material complex of the labels
// (pipeline/complex_run.h).
void run_complex_labels(const RunCli& o, const pipeline::RunOptions& base, const CommonOptions& common) {
  LabelMapRun lm(o, common);
  Progress& progress = lm.progress;
  PendingOutputs pending;
  const auto on_label = [&](pipeline::LabelRun& run) {
    if (!o.surface.empty()) write_mpu(run.result.surface, pending.add(with_label(o.surface, run.label)));
  };
  pipeline::RunOptions quiet_base = base;
  quiet_base.quality.reset();
  const pipeline::ComplexResult r =
      pipeline::run_complex(lm.vol, lm.todo, o.labels == "all", quiet_base, lm.open, &lm.observer, on_label);
  finish_complex(o, r, lm.choice, common, pending, progress);
}

// A surface mesh: its parts remeshed as one complex (pipeline/complex_run.h) when it has
// two or more and --separate is not given, else one run. A marching-cubes surface (its
// vertices on a voxel grid's edges, mesh/voxel_grid.h) is a scan's surface, its
// components the scan's structures and specks: it is remeshed as one surface, as the scan
// itself would be.
void run_mesh(const RunCli& o, const pipeline::RunOptions& base, const CommonOptions& common) {
  const bool talk = !common.json && !common.quiet;
  Progress shown(!talk, common.progress), progress(!talk);
  progress.begin("read mesh");
  const TriangleMesh mesh = read_mesh(o.input);
  const int64_t parts = o.separate || voxel_grid_spacing(mesh) ? 1 : count_parts(mesh);
  progress.end();
  if (parts < 2) return run_one(o, base, common, &mesh);
  const std::string what = fmt::format("{} ({} parts)", o.input, parts);
  check_complex_outputs(o, what);
  if (!o.surface.empty())
    throw InputError(fmt::format("--surface: the parts' fits of the complex of {} are not written; they come with "
                                 "--separate",
                                 what));
  RunObserver observer(shown, talk);
  EarlyBackend early(o.backend);
  vk::BackendChoice choice;
  const pipeline::BackendOpener open = [&]() -> ComputeBackend& {
    if (!choice.backend) choice = early.open(common, progress);
    return *choice.backend;
  };
  pipeline::RunOptions quiet_base = base;
  quiet_base.quality.reset();
  const pipeline::ComplexResult r = pipeline::run_parts_complex(mesh, o.input, quiet_base, open, &observer);
  PendingOutputs pending;
  finish_complex(o, r, choice, common, pending, progress);
}

}  // namespace

void add_run_command(CLI::App& app, CommonOptions& common, std::function<void()>& action) {
  auto o = std::make_shared<RunCli>();
  auto* cmd = app.add_subcommand(
      "run", "The whole job: a CT/MR volume (or a surface mesh, to remesh it) to a smooth adaptive mesh");
  add_run_paths(cmd, *o);
  add_run_parameters(cmd, *o);
  add_common(cmd, common);
  add_progress_flag(cmd, common);
  cmd->callback([&common, &action, o] {
    action = [&common, o] {
      check_run_outputs(*o);
      if (common.argv) prefer_huge_pages_if_faster(common.argv, input_bytes(o->input));
      const pipeline::RunOptions options = run_options(*o, common);
      std::optional<tbb::global_control> threads;
      if (o->threads > 0) threads.emplace(tbb::global_control::max_allowed_parallelism, size_t(o->threads));
      if (o->labels.empty() && pipeline::is_mesh_path(o->input)) run_mesh(*o, options, common);
      else if (o->labels.empty()) run_one(*o, options, common);
      else if (o->separate) run_labels(*o, options, common);
      else run_complex_labels(*o, options, common);
    };
  });
}

}  // namespace mpumesh::tools
