#include "common/memory.h"

#include <malloc.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

#include "common/error.h"
#include "common/option_names.h"

namespace mpumesh {

uint64_t available_memory_bytes() {
  if (const char* env = std::getenv("MPUMESH_MEMORY_LIMIT_GIB")) {
    const double gib = std::atof(env);
    if (gib > 0) return uint64_t(gib * double(1ull << 30));
  }
  std::ifstream in("/proc/meminfo");
  std::string key;
  uint64_t kb = 0;
  std::string unit;
  while (in >> key >> kb >> unit)
    if (key == "MemAvailable:") return kb * 1024;
  const long pages = sysconf(_SC_AVPHYS_PAGES), size = sysconf(_SC_PAGESIZE);
  return pages > 0 && size > 0 ? uint64_t(pages) * uint64_t(size) : UINT64_MAX;
}

void tune_memory() {
#if defined(__GLIBC__) && defined(__linux__)
  mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest
  mallopt(M_TRIM_THRESHOLD, INT32_MAX);
#endif
}

uint64_t peak_rss_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return uint64_t(u.ru_maxrss) * 1024;  // kB on Linux
}

uint64_t estimate_run_bytes(int64_t voxels, int64_t points, int64_t particles, bool volume_mesh) {
  const uint64_t threads = std::max(2u, std::thread::hardware_concurrency());
  return (64ull << 20) + std::max(uint64_t(voxels) * 12, uint64_t(points) * 700) + uint64_t(particles) * 3000 +
         (volume_mesh ? uint64_t(particles) * 3500 : 0) + (threads - 2) * (75ull << 20);
}

void check_memory(const std::string& what, uint64_t need) {
  const uint64_t have = available_memory_bytes();
  if (need > have) {
    char msg[160];
    std::snprintf(msg, sizeof msg, ": this job needs about %.2f GiB, more than the %.2f GiB of memory available",
                  double(need) / double(1ull << 30), double(have) / double(1ull << 30));
    throw InputError(what + msg + " (ask for fewer " + option_ref("particles") + ", or crop or downsample the volume)");
  }
}

}  // namespace mpumesh
