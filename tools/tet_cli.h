// The volume mesh's options, shared by `tetmesh` and `run --volume`, and its figures as
// JSON and text (core/tet/tetrahedralize.h).
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "tet/tetrahedralize.h"

namespace mpumesh::tools {

// `prefix`: "" for tetmesh (--size, --grading), "volume-" for run (--volume-size, ...).
void add_tet_options(CLI::App* cmd, TetOptions& o, const std::string& prefix);

nlohmann::json tet_quality_json(const TetQuality& q);
nlohmann::json tet_json(const TetOptions& o, const TetStats& st);
std::string tet_text(const std::string& path, const TetStats& st);
// The shape figures alone (for `quality` of a volume mesh file).
std::string tet_quality_text(const TetQuality& q);

}  // namespace mpumesh::tools
