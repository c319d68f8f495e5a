// The HTML report of a mesh (mpumesh run --html, mpumesh report): renders of the result
// coloured by curvature and by triangle quality, the paper's Fig. 4 comparison (one
// zoomed region of our mesh and of each baseline side by side), histograms of minimum
// angle and radius ratio, particle spacing against |K|, stage times, the input and every
// parameter. Pictures are drawn on the backend given (Vulkan or the CPU reference).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "compute/compute_backend.h"
#include "geometry/triangle_mesh.h"

namespace mpumesh::tools {

struct ReportMesh {
  std::string name;
  const TriangleMesh* mesh = nullptr;
};

struct ReportInputs {
  ReportMesh ours;
  std::vector<ReportMesh> baselines;  // e.g. marching cubes, the original MPU
  // What run knows (its JSON report: input, stages, device, parameters); may be empty.
  nlohmann::json run = nlohmann::json::object();
};

std::string build_report(const ReportInputs& in, ComputeBackend& backend);

}  // namespace mpumesh::tools
