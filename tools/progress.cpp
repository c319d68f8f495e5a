#include "progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace mpumesh::tools {
namespace {

// A bar is drawn again at most this often (seconds), and the time left shown once this
// much of the stage is done (before, the rate says little).
constexpr double kRedraw = 0.1;
constexpr double kEstimateFrom = 0.03;
constexpr int kBarWidth = 20;

}  // namespace

Progress::Progress(bool quiet, bool tenths)
    : show_(!quiet && ::isatty(STDERR_FILENO)), tenths_(tenths && !quiet && !show_) {}

void Progress::begin(const std::string& stage) {
  stage_ = stage;
  t0_ = std::chrono::steady_clock::now();
  drawn_ = {};
  tenth_[stage] = 0;
  if (show_) std::fprintf(stderr, "  %-28s ...", stage.c_str()), std::fflush(stderr);
}

void Progress::end() {
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  times_.push_back({stage_, s});
  // "\033[K" clears what a bar left on the line.
  if (show_) std::fprintf(stderr, "\r  %-28s %8.3f s\033[K\n", stage_.c_str(), s);
}

void Progress::fraction(const std::string& stage, double f) {
  f = std::clamp(f, 0.0, 1.0);
  if (stage != stage_) outer_ = f < 1 ? stage + " " + std::to_string(int(std::lround(100 * f))) + "%" : "";
  if (tenths_) {
    const int tenth = int(std::floor(10 * f + 1e-9));
    int& last = tenth_[stage];
    if (tenth > last) {
      last = tenth;
      std::fprintf(stderr, "  %s %d%%\n", stage.c_str(), 10 * tenth);
    }
  }
  if (!show_ || stage != stage_) return;
  const auto now = std::chrono::steady_clock::now();
  if (f < 1 && std::chrono::duration<double>(now - drawn_).count() < kRedraw) return;
  draw(f, now);
}

void Progress::draw(double f, std::chrono::steady_clock::time_point now) {
  drawn_ = now;
  const double elapsed = std::chrono::duration<double>(now - t0_).count();
  char bar[kBarWidth + 1];
  const int full = int(std::lround(kBarWidth * f));
  for (int i = 0; i < kBarWidth; ++i) bar[i] = i < full ? '#' : '.';
  bar[kBarWidth] = '\0';
  char left[48] = "";
  if (f >= kEstimateFrom && f < 1) std::snprintf(left, sizeof left, "  %.0f s left", elapsed * (1 - f) / f);
  std::fprintf(stderr, "\r  %-28s [%s] %3d%%%s%s%s\033[K", stage_.c_str(), bar, int(std::lround(100 * f)), left,
               outer_.empty() ? "" : "  ", outer_.c_str());
  std::fflush(stderr);
}

void Progress::note(const std::string& line) {
  if (show_) std::fprintf(stderr, "  %s\n", line.c_str());
}

}  // namespace mpumesh::tools
