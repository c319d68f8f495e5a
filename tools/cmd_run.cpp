// mpumesh run: the whole job (core/pipeline) from the command line. The command parses
// and checks its options and outputs, runs the pipeline, writes the mesh (and the surface),
// and turns the result into text, the JSON report and the HTML report.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>

#include "cli_util.h"
#include "component_cli.h"
#include "commands.h"
#include "common/error.h"
#include "common/memory.h"
#include "io/atomic_file.h"
#include "io/mesh_io.h"
#include "io/read_file.h"
#include "mpu/mpu_io.h"
#include "mpu_cli.h"
#include "pipeline/run_pipeline.h"
#include "report_builder.h"
#include "sample_cli.h"
#include "seg_cli.h"

namespace mpumesh::tools {
namespace {

struct RunCli {
  std::string input, output, report, html, surface, local_fit = "orthopoly";
  SegmentCli seg;
  mpu::FitOptions fit;
  particles::SampleOptions sample;
  BackendOptions backend;
  bool self_intersections = true, partial_volume_caps = false;
  int count_retries = -1;  // -1: 2 when neither --particles nor --spacing is given, else 0
  ComponentFilter components;
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

// Every output and parameter, checked before the long work starts; the pipeline's options.
pipeline::RunOptions checked_options(RunCli& o, const CommonOptions& common) {
  check_writable(o.output);
  mesh_format_from_path(o.output);
  if (!o.report.empty()) check_writable(o.report);
  if (!o.surface.empty()) check_writable(o.surface);
  if (!o.html.empty()) {
    check_writable(o.html);
    if (lower_extension(o.html) != ".html") throw InputError(o.html + ": the HTML report must be a .html file");
  }
  o.fit.local_fit = o.local_fit == "quadric" ? mpu::LocalFit::kQuadric : mpu::LocalFit::kOrthopoly;
  mpu::validate(o.fit);
  particles::validate(o.sample, "run", "particle-iterations");
  pipeline::RunOptions r;
  if (!pipeline::is_mesh_path(o.input)) r.segment = resolve(o.seg);
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
nlohmann::json run_json(const RunCli& o, const pipeline::RunResult& r, const vk::BackendChoice& choice) {
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
  j["output"] = o.output;
  j["vertices"] = r.mesh.vertices.size();
  j["triangles"] = r.mesh.triangles.size();
  if (o.components.active()) j["components_filter"] = components_json(o.components, r.components_kept, r.components_dropped);
  if (r.has_quality) j["quality"] = quality_to_json(r.quality);
  j["notes"] = r.notes;
  j["version"] = MPUMESH_VERSION;
  return j;
}

void print_summary(const RunCli& o, const pipeline::RunResult& r, const vk::BackendChoice& choice) {
  if (o.components.active()) std::cout << components_text(r.components_kept, r.components_dropped);
  if (r.has_quality)
    std::cout << o.output << ": " << r.mesh.triangles.size() << " triangles from " << r.particles.size()
              << " particles (" << choice.backend->device() << ")\n"
              << quality_to_text(r.quality);
  if (r.sparse) std::cout << "note: " << r.notes.back() << "\n";
}

void write_html(const RunCli& o, const pipeline::RunResult& r, const nlohmann::json& j, ComputeBackend& backend,
                Progress& progress) {
  progress.begin("report");
  ReportInputs in;
  in.ours = {std::filesystem::path(o.output).filename().string() + " (ours)", &r.mesh};
  for (const auto& [name, m] : r.baselines) in.baselines.push_back({name, &m});
  in.run = j;
  write_file_atomically(build_report(in, backend), o.html);
  progress.end();
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
      Progress progress(common.quiet || common.json);
      RunObserver observer(progress, !common.json && !common.quiet);
      vk::BackendChoice choice;
      const pipeline::BackendOpener open = [&]() -> ComputeBackend& {
        choice = open_backend(o->backend, common, progress);
        return *choice.backend;
      };
      const pipeline::RunResult r = pipeline::run_pipeline(o->input, options, open, &observer);
      progress.begin("write mesh");
      write_mesh(r.mesh, o->output);
      if (!o->surface.empty()) write_mpu(r.surface, o->surface);
      progress.end();
      nlohmann::json j = run_json(*o, r, choice);
      if (!common.json && !common.quiet) print_summary(*o, r, choice);
      j["stage_seconds"] = stage_json(progress);
      j["memory"] = {{"estimate_gib", double(r.memory_estimate) / double(1ull << 30)},
                     {"available_gib", double(available_memory_bytes()) / double(1ull << 30)},
                     {"peak_rss_gib", double(peak_rss_bytes()) / double(1ull << 30)}};
      if (!o->html.empty()) {
        write_html(*o, r, j, *choice.backend, progress);
        j["html"] = o->html;
      }
      if (!o->report.empty()) write_json_file(j, o->report);
      if (common.json) std::cout << j.dump(2) << '\n';
    };
  });
}

}  // namespace mpumesh::tools
