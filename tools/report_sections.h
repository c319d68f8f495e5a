// The sections that the report of one surface (report_builder.h) and the report of a
// multi-material complex (complex_report.h) share.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "compute/compute_backend.h"
#include "geometry/triangle_mesh.h"
#include "pipeline/run_result.h"
#include "render/render_scene.h"
#include "report/html_report.h"

namespace mpumesh::tools {

// The charts' series colours, in turn.
extern const char* const kReportColours[5];

// A render of `m` as a PNG, drawn on the backend.
std::string render_png(ComputeBackend& backend, const TriangleMesh& m, render::RenderOptions ro);

// The volume mesh's figures and a histogram of its dihedral angles.
void add_volume_mesh(report::HtmlPage& page, const pipeline::VolumeMeshResult& v);

// The stages' times as bars (a stage run more than once summed).
void add_stage_times(report::HtmlPage& page, const std::string& device,
                     const std::vector<std::pair<std::string, double>>& stage_seconds);

// A run's parameters and stage figures as JSON text.
void add_parameters(report::HtmlPage& page, const nlohmann::json& params);

}  // namespace mpumesh::tools
