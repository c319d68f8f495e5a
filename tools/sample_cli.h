// The particle stage's options, which `sample` and `run` share (their JSON: run_json.h).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "particles/particle_system.h"

namespace mpumesh::tools {

// `iterations_flag`: "--iterations" for sample, "--particle-iterations" for run (where
// --iterations is Chan-Vese's).
void add_sample_options(CLI::App* cmd, particles::SampleOptions& o, const std::string& iterations_flag);

}  // namespace mpumesh::tools
