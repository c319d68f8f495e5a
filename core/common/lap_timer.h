// Seconds between successive lap() calls: the per-step timings in the reports.
#pragma once

#include <chrono>

namespace mpumesh {

class LapTimer {
 public:
  using Clock = std::chrono::steady_clock;
  explicit LapTimer(Clock::time_point start = Clock::now()) : last_(start) {}
  // Seconds since the previous lap (or the start).
  double lap() {
    const Clock::time_point now = Clock::now();
    const double d = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    return d;
  }

 private:
  Clock::time_point last_;
};

}  // namespace mpumesh
