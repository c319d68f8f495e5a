// The options that keep the wanted structures (`run`, `filter`), and what was dropped.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "mesh/component_filter.h"

namespace mpumesh::tools {

void add_component_options(CLI::App* cmd, ComponentOptions& f);
nlohmann::json components_json(const ComponentOptions& f, int64_t kept, const std::vector<DroppedComponent>& dropped);
// "kept N structures; dropped M: ..." lines.
std::string components_text(int64_t kept, const std::vector<DroppedComponent>& dropped);

}  // namespace mpumesh::tools
