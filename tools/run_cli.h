// The options of `mpumesh run`, which the command and the Python module share: their
// CLI11 definitions (one set of names, checks and messages), the pipeline's options they
// make, and the JSON report of a run.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "cli_util.h"
#include "commands.h"
#include "mesh/component_filter.h"
#include "pipeline/run_pipeline.h"
#include "seg_cli.h"
#include "tet/tetrahedralize.h"

namespace mpumesh::tools {

// What --labels paths hold in place of the label.
inline constexpr std::string_view kLabelField = "{label}";

struct RunCli {
  std::string input, output, report, html, surface, volume, local_fit = "orthopoly";
  TetOptions tet;
  SegmentCli seg;
  mpu::FitOptions fit;
  particles::SampleOptions sample;
  BackendOptions backend;
  bool self_intersections = true, ruled_caps = false, keep_specks = false;
  int count_retries = -1;  // -1: 2 when neither --particles nor --spacing is given, else 0
  int optimize_rounds = OptimizeOptions{}.rounds;
  ComponentOptions components;
  int64_t label = 0;   // --label
  std::string labels;  // --labels: "all" or a list
  // --separate: each label's own surface, or a mesh's parts remeshed as one surface, not
  // one complex
  bool separate = false;
  int threads = 0;     // 0: every core
};

// The input and the output paths.
void add_run_paths(CLI::App* cmd, RunCli& o);
// Every other option (segmentation, fit, particles, components, backend, threads).
void add_run_parameters(CLI::App* cmd, RunCli& o);

// `path` with its "{label}" replaced by the label.
std::string with_label(std::string path, int64_t label);

// The outputs, checked before the long work starts (their directories writable, the mesh
// format known, --labels paths holding {label}).
void check_run_outputs(const RunCli& o);
// The outputs of a complex (`what` names its source in messages: --labels, or a mesh of
// several parts): -o a PLY or a path with {label}, --surface with {label}, no --volume
// and no --html.
void check_complex_outputs(const RunCli& o, const std::string& what);
// Throws InputError unless each path given holds {label}.
void check_label_paths(const std::vector<const std::string*>& paths, const std::string& what);
// The parameters, checked, as the pipeline's options (throws InputError; the particles'
// and the volume mesh's options with "COMMAND: " in front, when a command is named).
pipeline::RunOptions run_options(RunCli& o, const CommonOptions& common, const std::string& command = "run");

}  // namespace mpumesh::tools
