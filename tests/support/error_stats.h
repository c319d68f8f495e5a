// How far a backend's values are from the double-precision reference's, for the
// cross-backend tests: the largest absolute error, the largest relative one (against
// |reference|, where that is at least a floor) and the root mean square, printed on one
// line. Each kernel's test states its tolerances once, against these.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace mpumesh::test {

struct ErrorStats {
  double max_abs = 0, max_rel = 0, sum_sq = 0;
  size_t n = 0, n_rel = 0;  // values, and those with a relative error
  // One value against the reference's; the relative error only where |want| >= rel_floor.
  void add(double got, double want, double rel_floor = 0) {
    const double e = std::abs(got - want);
    max_abs = std::max(max_abs, e);
    if (std::abs(want) >= rel_floor && std::abs(want) > 0) max_rel = std::max(max_rel, e / std::abs(want)), ++n_rel;
    sum_sq += e * e;
    ++n;
  }
  // An error measured directly (a distance, an angle): absolute only.
  void add_error(double e) { add(e, 0.0, INFINITY); }
  double rms() const { return n ? std::sqrt(sum_sq / double(n)) : 0.0; }
  std::string line(const std::string& what) const {
    char buf[256];
    if (n_rel > 0)
      std::snprintf(buf, sizeof buf, "%s: max abs %.3g, max rel %.3g, rms %.3g over %zu", what.c_str(), max_abs,
                    max_rel, rms(), n);
    else
      std::snprintf(buf, sizeof buf, "%s: max %.3g, rms %.3g over %zu", what.c_str(), max_abs, rms(), n);
    return buf;
  }
};

}  // namespace mpumesh::test
