#include "truth_rows.h"

#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "common/memory.h"

namespace mpumesh::bench {

void same_memory_for_all(char** argv) {
  tune_memory();
  prefer_huge_pages_if_faster(argv, kHugePageJobBytes);
  std::printf("malloc huge pages (common/memory.h): %s, ours and the peers alike\n", malloc_huge_pages() ? "yes" : "no");
}

double timed_system(const std::string& cmd) {
  std::fflush(nullptr);  // what is printed comes before the child's output, once
  const auto t0 = std::chrono::steady_clock::now();
  if (std::system(cmd.c_str()) != 0) {
    std::fprintf(stderr, "benchmark: failed: %s\n", cmd.c_str());
    std::exit(1);
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void print_truth_header(bool slices) {
  fmt::print("  {:<16} {:>7} {:>7} {:>6} {:>7} {:>6} {:>8} {:>7} {:>7} {:>7}", "mesh", "tris", "dist", "p99", "normal",
             "p95", "K rank", "K err", "sp h/l", "sp rank");
  if (slices) fmt::print(" {:>7} {:>6}", "vol %", "slice");
  fmt::print(" {:>7}\n", "s");
}

void print_truth_row(const std::string& name, const phantom::TruthFigures& f, double seconds, bool slices) {
  fmt::print("  {:<16} {:>7} {:>7.3f} {:>6.3f} {:>7.2f} {:>6.2f} {:>7.3f}{} {:>7.3f} {:>7.2f} {:>7.2f}", name,
             f.triangles, f.distance_mean, f.distance_p99, f.normal_mean_deg, f.normal_p95_deg, f.gauss_rank,
             f.curvature_from_file ? "f" : "d", f.gauss_median_error, f.spacing_high_low, f.spacing_rank);
  if (slices) fmt::print(" {:>7.2f} {:>6.2f}", 100 * f.volume_error, f.slice_modulation);
  fmt::print(" {:>7.1f}\n", seconds);
  if (f.cap_spacing > 0)
    fmt::print("  {:<16} caps K {:.5f}, barrel K {:.5f} (1/mm2); spacing caps {:.3f} mm, barrel {:.3f} mm ({:.2f})\n",
               "", f.cap_gauss, f.barrel_gauss, f.cap_spacing, f.barrel_spacing, f.cap_spacing / f.barrel_spacing);
}

bool is_backend(const std::string& arg) { return arg == "cpu" || arg == "gpu" || arg == "auto"; }

std::string extra_args(const char* name) {
  const char* e = std::getenv(name);
  return e ? std::string(" ") + e : std::string();
}

}  // namespace mpumesh::bench
