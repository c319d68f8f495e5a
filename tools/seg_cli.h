// The segmentation options that `segment`, `points` and `run` share, and their JSON echo.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>

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
nlohmann::json segment_json(const seg::SegmentOptions& opt, const seg::Segmentation& s);

}  // namespace mpumesh::tools
