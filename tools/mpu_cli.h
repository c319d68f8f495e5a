// The MPU fit's command-line options and JSON summary, shared by `fit` and `run`.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "mpu/mpu_fit.h"

namespace mpumesh::tools {

// local_fit receives "orthopoly" or "quadric".
void add_fit_options(CLI::App* cmd, mpu::FitOptions& f, std::string& local_fit);
nlohmann::json fit_json(const mpu::FitOptions& o, const mpu::FitStats& st);

}  // namespace mpumesh::tools
