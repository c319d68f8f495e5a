// A long stage's fraction done, 0 to 1, told to whoever watches the run (the command
// line's bar, Python's progress callback) from the thread that runs the stage: the
// particle batches, the triangulation's phases, the optimisation's rounds, TetGen's
// steps. Empty: nobody watches.
#pragma once

#include <algorithm>
#include <functional>

namespace mpumesh {

using ProgressFn = std::function<void(double)>;

inline void tell(const ProgressFn& progress, double fraction) {
  if (progress) progress(std::clamp(fraction, 0.0, 1.0));
}

}  // namespace mpumesh
