#include "common/memory.h"

#include <malloc.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>
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

namespace {

constexpr uint64_t kHugePage = 2ull << 20;
// The probe's fresh memory, each way; and how much faster huge pages must fault in.
constexpr uint64_t kHugePageProbeBytes = 16ull << 20;
constexpr double kHugePageMinSpeedup = 1.2;

// One anonymous mapping aligned to a huge page, asked for huge pages or for none.
struct ProbeRegion {
  void* map = MAP_FAILED;
  char* at = nullptr;
  uint64_t bytes = 0;
  ProbeRegion(uint64_t n, bool huge) : bytes(n + kHugePage) {
    map = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (map == MAP_FAILED) return;
    at = reinterpret_cast<char*>((reinterpret_cast<uintptr_t>(map) + kHugePage - 1) & ~(kHugePage - 1));
    if (madvise(at, n, huge ? MADV_HUGEPAGE : MADV_NOHUGEPAGE) != 0) at = nullptr;
  }
  ~ProbeRegion() {
    if (map != MAP_FAILED) munmap(map, bytes);
  }
  ProbeRegion(const ProbeRegion&) = delete;
  ProbeRegion& operator=(const ProbeRegion&) = delete;
};

// Seconds to write one byte in every 4 KiB page of [p, p + n).
double touch_seconds(char* p, uint64_t n) {
  const auto t0 = std::chrono::steady_clock::now();
  for (uint64_t i = 0; i < n; i += 4096) static_cast<volatile char*>(p)[i] = 1;
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

bool huge_pages_on_request() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string line;
  std::getline(in, line);
  return line.find("[madvise]") != std::string::npos;
}

}  // namespace

double huge_page_fault_speedup(uint64_t bytes) {
  bytes = std::max(kHugePage, bytes / kHugePage * kHugePage);
  const ProbeRegion small(bytes, false), huge(bytes, true);
  if (!small.at || !huge.at) return 0;
  // Quarters in turn, so that a change in the machine's load falls on both.
  const uint64_t quarter = std::max(kHugePage, bytes / 4 / kHugePage * kHugePage);
  double t_small = 0, t_huge = 0;
  for (uint64_t off = 0; off + quarter <= bytes; off += quarter) {
    t_small += touch_seconds(small.at + off, quarter);
    t_huge += touch_seconds(huge.at + off, quarter);
  }
  return t_huge > 0 ? t_small / t_huge : 0;
}

uint64_t input_bytes(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) {
    const uint64_t n = fs::file_size(path, ec);
    return ec ? 0 : n;
  }
  uint64_t total = 0;
  if (fs::is_directory(path, ec))
    for (const auto& e : fs::directory_iterator(path, ec))
      if (e.is_regular_file(ec)) total += e.file_size(ec);
  return total;
}

bool malloc_huge_pages() {
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  const char* at = tunables ? std::strstr(tunables, "glibc.malloc.hugetlb=") : nullptr;
  return at && std::atoi(at + std::strlen("glibc.malloc.hugetlb=")) > 0;
}

void prefer_huge_pages_if_faster(char** argv, uint64_t job_bytes) {
#if defined(__GLIBC__) && defined(__linux__)
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (tunables && std::strstr(tunables, "glibc.malloc.hugetlb")) return;
  const char* choice = std::getenv("MPUMESH_HUGE_PAGES");
  const std::string_view forced = choice ? choice : "";
  if (forced == "0") return;
  if (forced != "1" && (job_bytes < kHugePageJobBytes || !huge_pages_on_request())) return;
  const bool huge = forced == "1" || huge_page_fault_speedup(kHugePageProbeBytes) >= kHugePageMinSpeedup;
  // Either way the choice goes into GLIBC_TUNABLES, so that the programs this one starts
  // (a benchmark's runs of mpumesh) make the same one without a probe of their own.
  const std::string before = tunables && *tunables ? std::string(tunables) + ":" : std::string();
  const auto choose = [&](bool on) {
    return setenv("GLIBC_TUNABLES", (before + "glibc.malloc.hugetlb=" + (on ? "1" : "0")).c_str(), 1) == 0;
  };
  if (!choose(huge) || !huge) return;
  std::fflush(nullptr);
  execv("/proc/self/exe", argv);  // returns only on failure: the run goes on as it is
  choose(false);
#else
  (void)argv, (void)job_bytes;
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
