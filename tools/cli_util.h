// Pieces every subcommand shares: the backend and output options, the JSON file writer,
// the stage-time summary.
#pragma once

#include <future>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.h"
#include "progress.h"
#include "vulkan_backend.h"

namespace mpumesh::tools {

struct BackendOptions {
  std::string name = "auto";
  int device = -1;
};

void add_backend_options(CLI::App* cmd, BackendOptions& b);
void add_common(CLI::App* cmd, CommonOptions& common);
// --progress, for the commands with long stages (run, tetmesh).
void add_progress_flag(CLI::App* cmd, CommonOptions& common);

// Makes the backend, timed as the "backend" stage; prints the choice's note unless quiet.
vk::BackendChoice open_backend(const BackendOptions& b, const CommonOptions& common, Progress& progress);
nlohmann::json backend_json(const vk::BackendChoice& choice);

// The backend made on a thread of its own from the start of a command, so that finding
// the Vulkan devices (the loader opens every driver: about 0.1 s with lavapipe alone)
// overlaps reading the input. `open` takes it, as open_backend does (the "backend" stage
// is then the wait); the thread's error, if any, is thrown there, and a later `open`
// makes the backend anew.
class EarlyBackend {
 public:
  explicit EarlyBackend(const BackendOptions& b);
  vk::BackendChoice open(const CommonOptions& common, Progress& progress);

 private:
  BackendOptions options_;
  std::future<vk::BackendChoice> made_;
};

// Writes `j` to `path` atomically.
void write_json_file(const nlohmann::json& j, const std::string& path);
nlohmann::json stage_json(const Progress& p);

}  // namespace mpumesh::tools
