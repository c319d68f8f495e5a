#include "cli_util.h"

#include <cstdio>
#include <fstream>

#include "common/error.h"
#include "common/eval_precision.h"
#include "io/atomic_file.h"

namespace mpumesh::tools {

void add_backend_options(CLI::App* cmd, BackendOptions& b) {
  cmd->add_option("--backend", b.name, "cpu, gpu (Vulkan) or auto (a hardware GPU if any, else cpu)")
      ->check(CLI::IsMember({"cpu", "gpu", "auto"}))
      ->capture_default_str();
  cmd->add_option("--device", b.device, "Vulkan device index (see `mpumesh devices`)");
  // Set as the option is read, before any surface is fitted or read (their leaf records
  // follow it: common/eval_precision.h).
  cmd->add_option_function<std::string>(
         "--cpu-eval", [](const std::string& v) { set_eval_precision(*parse_eval_precision(v)); },
         "the CPU's MPU evaluation: float64 (the default) or float32 (16 leaves a vector step; f within 2e-4 mm "
         "of float64's)")
      ->check(CLI::IsMember({"float64", "float32"}));
}

void add_common(CLI::App* cmd, CommonOptions& common) {
  cmd->add_flag("--quiet,-q", common.quiet, "print nothing but errors");
  cmd->add_flag("--json", common.json, "print a JSON summary on stdout");
}

void add_progress_flag(CLI::App* cmd, CommonOptions& common) {
  cmd->add_flag("--progress", common.progress,
                "off a terminal (a log), print a line each time a long stage passes a tenth; on a terminal a bar "
                "with the time left shows anyway");
}

namespace {

void announce(const vk::BackendChoice& choice, const CommonOptions& common, Progress& progress) {
  if (!choice.note.empty() && !common.quiet) std::fprintf(stderr, "mpumesh: %s\n", choice.note.c_str());
  progress.note("device: " + choice.backend->device());
}

}  // namespace

vk::BackendChoice open_backend(const BackendOptions& b, const CommonOptions& common, Progress& progress) {
  progress.begin("backend");
  vk::BackendChoice choice = vk::make_backend(b.name, b.device);
  progress.end();
  announce(choice, common, progress);
  return choice;
}

EarlyBackend::EarlyBackend(const BackendOptions& b)
    : options_(b), made_(std::async(std::launch::async, [b] { return vk::make_backend(b.name, b.device); })) {}

vk::BackendChoice EarlyBackend::open(const CommonOptions& common, Progress& progress) {
  progress.begin("backend");
  // Asked again after the first failed: made here, failing the same way.
  vk::BackendChoice choice = made_.valid() ? made_.get() : vk::make_backend(options_.name, options_.device);
  progress.end();
  announce(choice, common, progress);
  return choice;
}

nlohmann::json backend_json(const vk::BackendChoice& choice) {
  return {{"kind", choice.backend->kind()},
          {"device", choice.backend->device()},
          {"note", choice.note},
          {"cpu_eval", eval_precision_name(eval_precision())}};
}

void write_json_file(const nlohmann::json& j, const std::string& path) { write_file_atomically(j.dump(2) + '\n', path); }

nlohmann::json stage_json(const Progress& p) {
  nlohmann::json s = nlohmann::json::object();
  // A stage run more than once (run's particles and triangulation, when it raises the
  // count) reports its total.
  for (const auto& [name, sec] : p.stage_seconds()) s[name] = s.value(name, 0.0) + sec;
  return s;
}

}  // namespace mpumesh::tools
