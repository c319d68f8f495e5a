// Stage progress for long work: on a terminal (stderr is a tty and not --quiet) each stage
// prints a line with its elapsed time when it ends; otherwise nothing is printed. Stage
// times are kept for the JSON summary either way.
#pragma once

#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace mpumesh::tools {

class Progress {
 public:
  explicit Progress(bool quiet);
  void begin(const std::string& stage);
  void end();  // of the current stage
  void note(const std::string& line);  // a line a user should see (not when quiet)
  const std::vector<std::pair<std::string, double>>& stage_seconds() const { return times_; }

 private:
  bool show_;
  std::string stage_;
  std::chrono::steady_clock::time_point t0_;
  std::vector<std::pair<std::string, double>> times_;
};

}  // namespace mpumesh::tools
