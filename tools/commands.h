// The subcommands of `mpumesh`, each registered on the CLI11 app with its options and run
// through run_command() (which catches, prints one line and sets the exit code).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

namespace mpumesh::tools {

struct CommonOptions {
  bool quiet = false;
  bool json = false;
  bool progress = false;  // --progress: off a terminal, a line per tenth of a long stage
  char** argv = nullptr;  // main's, for a long job to start itself again (common/memory.h)
};

// Each returns the callback that runs the command once CLI11 has parsed the arguments.
void add_devices_command(CLI::App& app, CommonOptions& common, std::function<void()>& action);
void add_mc_command(CLI::App& app, CommonOptions& common, std::function<void()>& action);
void add_quality_command(CLI::App& app, CommonOptions& common, std::function<void()>& action);
void add_filter_command(CLI::App& app, CommonOptions& common, std::function<void()>& action);
void add_convert_command(CLI::App& app, CommonOptions& common, std::function<void()>& action);
void add_segment_command(CLI::App& app, CommonOptions& common, std::function<void()>& action);
void add_points_command(CLI::App& app, CommonOptions& common, std::function<void()>& action);
void add_fit_command(CLI::App& app, CommonOptions& common, std::function<void()>& action);
void add_eval_command(CLI::App& app, CommonOptions& common, std::function<void()>& action);
void add_polygonize_command(CLI::App& app, CommonOptions& common, std::function<void()>& action);
void add_sample_command(CLI::App& app, CommonOptions& common, std::function<void()>& action);
void add_triangulate_command(CLI::App& app, CommonOptions& common, std::function<void()>& action);
void add_run_command(CLI::App& app, CommonOptions& common, std::function<void()>& action);
void add_render_command(CLI::App& app, CommonOptions& common, std::function<void()>& action);
void add_report_command(CLI::App& app, CommonOptions& common, std::function<void()>& action);
void add_tetmesh_command(CLI::App& app, CommonOptions& common, std::function<void()>& action);

}  // namespace mpumesh::tools
