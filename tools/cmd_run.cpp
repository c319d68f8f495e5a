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
#include "component_cli.h"
#include "io/atomic_file.h"
#include "io/mesh_io.h"
#include "io/tet_io.h"
#include "io/volume_io.h"
#include "mesh/mesh_separation.h"
#include "mpu/mpu_io.h"
#include "report_builder.h"
#include "run_cli.h"
#include "tet_cli.h"
#include "segment/label_map.h"

namespace mpumesh::tools {
namespace {

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

void print_summary(const RunCli& o, const std::string& output, const pipeline::RunResult& r,
                   const vk::BackendChoice& choice) {
  if (r.components.active()) std::cout << components_text(r.components_kept, r.components_dropped);
  if (r.has_quality)
    std::cout << output << ": " << r.mesh.triangles.size() << " triangles from " << r.particles.size()
              << " particles (" << choice.backend->device() << ")\n"
              << quality_to_text(r.quality);
  if (r.sparse) std::cout << "note: " << r.notes.back() << "\n";
  if (r.has_volume) std::cout << tet_text(o.volume, r.volume_stats);
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

// The one run of `mpumesh run` (a volume, one label of a label map, or a mesh).
void run_one(const RunCli& o, const pipeline::RunOptions& options, const CommonOptions& common) {
  Progress progress(common.quiet || common.json);
  RunObserver observer(progress, !common.json && !common.quiet);
  EarlyBackend early(o.backend);
  vk::BackendChoice choice;
  const pipeline::BackendOpener open = [&]() -> ComputeBackend& {
    choice = early.open(common, progress);
    return *choice.backend;
  };
  const pipeline::RunResult r = pipeline::run_pipeline(o.input, options, open, &observer);
  progress.begin("write mesh");
  write_mesh(r.mesh, o.output);
  if (!o.surface.empty()) write_mpu(r.surface, o.surface);
  if (r.has_volume) write_tet_mesh(r.volume, o.volume);
  progress.end();
  if (!common.json && !common.quiet) print_summary(o, o.output, r, choice);
  // The summary (0.05 s on the sample CT: the particles' spacing figures) only for a
  // report or --json.
  if (o.html.empty() && o.report.empty() && !common.json) return;
  nlohmann::json j = run_json(o, o.output, r, choice);
  if (options.label > 0) j["label"] = options.label;
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

// A label's mesh (vertices and triangles only), for the labels after it to yield to.
struct LabelShape {
  int64_t label;
  TriangleMesh mesh;
};

// A label meshed after others that it touches moves its vertices out of theirs
// (mesh/mesh_separation.h), to a tenth of a voxel from them, and its quality is measured
// again; null when no earlier label is near. The triangle pairs by which its final mesh
// still crosses each of them go to `crossings` (and to the user, where there are any).
nlohmann::json yield_to_earlier_labels(pipeline::RunResult& r, int64_t label, const std::vector<LabelShape>& earlier,
                                       double voxel, const pipeline::RunOptions& options, bool talk,
                                       nlohmann::json& crossings) {
  std::vector<const TriangleMesh*> near;
  nlohmann::json against = nlohmann::json::array();
  for (const LabelShape& e : earlier)
    if (bounding_boxes_overlap(r.mesh, e.mesh)) {
      near.push_back(&e.mesh);
      against.push_back(e.label);
    }
  if (near.empty()) return nullptr;
  const SeparationStats s = separate_from(r.mesh, near, 0.1 * voxel);
  if (s.moved_vertices > 0 && r.has_quality) r.quality = measure_quality(r.mesh, options.quality_options);
  for (size_t k = 0; k < near.size(); ++k) {
    const int64_t other = against[k].get<int64_t>(), n = s.crossings_with[k];
    crossings.push_back({{"labels", {std::min(other, label), std::max(other, label)}}, {"triangle_pairs", n}});
    if (talk && n > 0)
      std::cout << fmt::format("note: the meshes of labels {} and {} cross ({} triangle pairs)\n", other, label, n);
  }
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
  EarlyBackend early(o.backend);
  progress.begin("read volume");
  const Volume vol = read_volume(o.input);
  progress.end();
  const std::map<int64_t, int64_t> counts = seg::label_voxel_counts(vol);
  const std::vector<int64_t> todo = labels_to_mesh(o, counts);
  const bool all = o.labels == "all";
  vk::BackendChoice choice;
  const pipeline::BackendOpener open = [&]() -> ComputeBackend& {
    if (!choice.backend) choice = early.open(common, progress);
    return *choice.backend;
  };
  PendingOutputs pending;
  std::vector<LabelShape> shapes;
  nlohmann::json meshed = nlohmann::json::array(), skipped = nlohmann::json::array();
  nlohmann::json crossings = nlohmann::json::array();
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
    const nlohmann::json separation =
        yield_to_earlier_labels(r, l, shapes, vol.in_plane_spacing(), base, talk, crossings);
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
  std::sort(crossings.begin(), crossings.end(),
            [](const nlohmann::json& x, const nlohmann::json& y) { return x["labels"] < y["labels"]; });
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
  add_run_paths(cmd, *o);
  add_run_parameters(cmd, *o);
  add_common(cmd, common);
  cmd->callback([&common, &action, o] {
    action = [&common, o] {
      check_run_outputs(*o);
      const pipeline::RunOptions options = run_options(*o, common);
      std::optional<tbb::global_control> threads;
      if (o->threads > 0) threads.emplace(tbb::global_control::max_allowed_parallelism, size_t(o->threads));
      if (o->labels.empty()) run_one(*o, options, common);
      else run_labels(*o, options, common);
    };
  });
}

}  // namespace mpumesh::tools
