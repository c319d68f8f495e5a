// The JSON report of a run (`mpumesh run --report`, `--json`, the Python module's
// `report`): the pipeline's typed summary (core/pipeline/run_result.h) written under the
// report's keys, and read back from a file for `mpumesh report --run-report`. The keys
// are written here and nowhere else.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "pipeline/complex_run.h"
#include "pipeline/label_runs.h"
#include "pipeline/run_result.h"
#include "progress.h"
#include "vulkan_backend.h"

namespace mpumesh::tools {

// How an edge spells core's option names (common/option_names.h) in text it shows.
using OptionSpelling = std::function<std::string(std::string_view)>;

// What the caller adds to a run's summary.
struct RunReportContext {
  std::string output;         // the mesh written ("" for none)
  std::string volume_output;  // the volume mesh written ("" for none)
  const vk::BackendChoice* backend = nullptr;
  OptionSpelling spell;
};

// The run's JSON report, without the stage times, the HTML path and the memory, which
// the caller adds (stage_seconds_json, memory_json).
nlohmann::json run_json(const pipeline::RunResult& r, const RunReportContext& ctx);
nlohmann::json memory_json(const pipeline::RunResult& r);
// The stage times: the pipeline's and the caller's own (writing, the backend, the report),
// a stage run more than once (the particles and the triangulation when the count is
// raised) with its total.
nlohmann::json stage_seconds_json(const std::vector<std::pair<std::string, double>>& pipeline_stages,
                                  const Progress& own);

// The particle stage's figures (`sample`, `run`); `spacing` when measured.
nlohmann::json sample_json(const particles::SampleOptions& o, const particles::SampleStats& st,
                           const particles::SpacingSummary* spacing);
nlohmann::json triangulation_json(const RestrictedDelaunayStats& st);
nlohmann::json input_json(const pipeline::InputInfo& in);

// A label's section of a --labels report (its run's report with the label and what its
// separation did), and the report's list parts.
void add_label_json(nlohmann::json& j, const pipeline::LabelRun& run);
nlohmann::json skipped_labels_json(const std::vector<pipeline::SkippedLabel>& skipped);
nlohmann::json label_crossings_json(const std::vector<pipeline::LabelCrossing>& crossings);
// The complex of a --labels run: per label its enclosed volume against its voxels' and its
// closedness, per interface its area and triangles' shape, the junction curves, the
// crossing triangle pairs, and how it was sampled and triangulated.
nlohmann::json complex_json(const pipeline::ComplexResult& r);
// The report of a complex's run (`run --labels` without --separate, a mesh's parts): the
// input and the outputs (ctx.output, ctx.volume_output), the complex, the labels meshed
// and skipped, the volume mesh; without the stage times, which the caller adds.
nlohmann::json complex_run_json(const pipeline::ComplexResult& r, const std::string& input,
                                const RunReportContext& ctx);

// What `mpumesh report --run-report` reads back from a run's JSON report for the HTML
// page: the summary's parts the page shows (the others stay empty), and the device and
// stage times. Throws InputError naming `path` when a part has the wrong shape.
struct RunReportRead {
  pipeline::RunResult run;
  std::string device;
  std::vector<std::pair<std::string, double>> stage_seconds;
};
RunReportRead read_run_json(const nlohmann::json& j, const std::string& path);

}  // namespace mpumesh::tools
