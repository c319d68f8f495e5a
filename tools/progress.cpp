#include "progress.h"

#include <unistd.h>

#include <cstdio>

namespace mpumesh::tools {

Progress::Progress(bool quiet) : show_(!quiet && ::isatty(STDERR_FILENO)) {}

void Progress::begin(const std::string& stage) {
  stage_ = stage;
  t0_ = std::chrono::steady_clock::now();
  if (show_) std::fprintf(stderr, "  %-28s ...", stage.c_str()), std::fflush(stderr);
}

void Progress::end() {
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  times_.push_back({stage_, s});
  if (show_) std::fprintf(stderr, "\r  %-28s %8.3f s\n", stage_.c_str(), s);
}

void Progress::note(const std::string& line) {
  if (show_) std::fprintf(stderr, "  %s\n", line.c_str());
}

}  // namespace mpumesh::tools
