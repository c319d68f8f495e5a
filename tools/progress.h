// Stage progress for long work. On a terminal (stderr is a tty and not --quiet) each stage
// prints a line with its elapsed time when it ends, and a long stage (one that reports its
// fraction done) a bar with its percentage and an estimate of the time left while it runs,
// beside the loop around it ("labels 40%"); off a terminal nothing is printed, except
// with `tenths` (--progress) one line each time a stage passes a tenth. Stage times are
// kept for the JSON summary either way.
#pragma once

#include <chrono>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "common/progress_fn.h"

namespace mpumesh::tools {

class Progress {
 public:
  explicit Progress(bool quiet, bool tenths = false);
  void begin(const std::string& stage);
  void end();  // of the current stage
  // How far `stage` is, 0 to 1: the current stage, or a loop around the stages.
  void fraction(const std::string& stage, double f);
  ProgressFn fraction_of(std::string stage) {
    return [this, stage = std::move(stage)](double f) { fraction(stage, f); };
  }
  void note(const std::string& line);  // a line a user should see (not when quiet)
  const std::vector<std::pair<std::string, double>>& stage_seconds() const { return times_; }

 private:
  void draw(double f, std::chrono::steady_clock::time_point now);
  bool show_, tenths_;
  std::string stage_, outer_;
  std::chrono::steady_clock::time_point t0_, drawn_;
  std::map<std::string, int> tenth_;  // per stage, the last tenth printed
  std::vector<std::pair<std::string, double>> times_;
};

}  // namespace mpumesh::tools
