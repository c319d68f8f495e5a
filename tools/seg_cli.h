// The segmentation options that `segment`, `points` and `run` share, and their JSON echo.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_util.h"
#include "segment/segmentation.h"

namespace mpumesh::tools {

struct SegmentCli {
  std::string method;                // "" until given: chan-vese, or threshold when only --threshold is
  std::string threshold = "226";
  std::string window;                // "" = the bone window
  bool threshold_given = false;
  seg::ChanVeseParams cv;
};

void add_segment_options(CLI::App* cmd, SegmentCli& s);
seg::SegmentOptions resolve(const SegmentCli& s);
// What the volume-reading commands share: the volume, the backend, the segmentation.
struct SegmentedVolume {
  Volume volume;
  vk::BackendChoice backend;
  seg::SegmentOptions options;
  seg::Segmentation segmentation;
};
// Reads `input`, opens the backend and segments, each as a timed stage.
SegmentedVolume read_and_segment(const std::string& input, const SegmentCli& s, const BackendOptions& b,
                                 const CommonOptions& common, Progress& progress);

nlohmann::json segment_json(const seg::SegmentOptions& opt, const seg::SegmentationSummary& s);

}  // namespace mpumesh::tools
