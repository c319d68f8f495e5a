// The particle and triangulation stages' options and JSON, which `sample`, `triangulate`
// and `run` share.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "mesh/restricted_delaunay.h"
#include "particles/particle_system.h"

namespace mpumesh::tools {

// `iterations_flag`: "--iterations" for sample, "--particle-iterations" for run (where
// --iterations is Chan-Vese's).
void add_sample_options(CLI::App* cmd, particles::SampleOptions& o, const std::string& iterations_flag);
nlohmann::json sample_json(const particles::SampleOptions& o, const particles::SampleStats& st,
                           const particles::ParticleState& ps);
nlohmann::json triangulation_json(const RestrictedDelaunayStats& st);

}  // namespace mpumesh::tools
