// The HTML report of a multi-material complex (mpumesh run --labels ... --html, or a
// mesh's parts): per label its enclosed volume against its voxels' (or the input part's)
// and its closedness, per interface its area and triangles' shape, the junction curves,
// the crossing triangle pairs and the shells removed; renders coloured by label; the
// triangles' shape; the volume mesh per label when one was made; the stage times and how
// the complex was sampled, triangulated and optimised.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "compute/compute_backend.h"
#include "pipeline/complex_run.h"

namespace mpumesh::tools {

struct ComplexReportInputs {
  std::string name;  // the complex's file, for the title
  std::string input;
  const pipeline::ComplexResult* result = nullptr;
  std::string device;
  std::vector<std::pair<std::string, double>> stage_seconds;
  // The sampling's, triangulation's and optimisation's figures.
  nlohmann::json parameters = nlohmann::json::object();
};

std::string build_complex_report(const ComplexReportInputs& in, ComputeBackend& backend);

}  // namespace mpumesh::tools
