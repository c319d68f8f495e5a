// The HTML report of a mesh (mpumesh run --html, mpumesh report): renders of the result
// coloured by curvature and by triangle quality, the paper's Fig. 4 comparison (one
// zoomed region of our mesh and of each baseline side by side), histograms of minimum
// angle and radius ratio, particle spacing against |K|, stage times, the input and every
// parameter. Pictures are drawn on the backend given (Vulkan or the CPU reference).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "compute/compute_backend.h"
#include "geometry/triangle_mesh.h"
#include "pipeline/run_result.h"
#include "run_json.h"

namespace mpumesh::tools {

struct ReportMesh {
  std::string name;
  const TriangleMesh* mesh = nullptr;
};

// What the page shows of the run that made the mesh (none for a mesh alone).
struct ReportRun {
  const pipeline::RunResult* result = nullptr;
  std::string device;
  std::vector<std::pair<std::string, double>> stage_seconds;
  // The sections of the run's JSON report shown as they are (segmentation, fit,
  // particles, triangulation, optimisation).
  nlohmann::json parameters = nlohmann::json::object();
  OptionSpelling spell = [](std::string_view name) { return std::string(name); };
};

struct ReportInputs {
  ReportMesh ours;
  std::vector<ReportMesh> baselines;  // e.g. marching cubes, the original MPU
  ReportRun run;
};

// The sections of a run's JSON report that the page shows as they are.
nlohmann::json report_parameters(const nlohmann::json& run_json);

std::string build_report(const ReportInputs& in, ComputeBackend& backend);

}  // namespace mpumesh::tools
