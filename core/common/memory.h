// Memory: what the machine has free, what this process has used at most, and the
// estimate of a whole run that is checked before the long work starts.
#pragma once

#include <cstdint>
#include <string>

namespace mpumesh {

// MemAvailable from /proc/meminfo, or MPUMESH_MEMORY_LIMIT_GIB when set (to test the
// check, or to keep a job inside a share of a machine).
uint64_t available_memory_bytes();

// The peak resident set size of this process so far.
uint64_t peak_rss_bytes();

// About how many bytes `run` holds at its peak for a volume of `voxels`, `points` contour
// points (0 when not known yet) and `particles`: 64 MB, plus the larger of the volume stage
// (intensities, threshold field, mask, labels: 12 B a voxel) and the fit (points, k-d
// tree, MPU leaves and lookup grid: 700 B a point), plus the particles and their Delaunay
// triangulation (3 kB each), plus 75 MB for each hardware thread beyond two (the threads'
// scratch). Measured peaks: on this 2-core machine the sample CT (7.1 M voxels, 260 k
// points, 30 k particles) 0.39 GB against 0.34 GB estimated, and resampled to
// 512 x 512 x 324 (85 M voxels, 1.46 M points, 25 k particles) 1.11 GB against 1.16 GB;
// the latter on a 16-thread host 2.06 GB (CPU path) and 2.36 GB (GPU) against 2.15 GB.
// With a volume mesh (run --volume), 3.5 kB more a particle: about 7.5 tetrahedra a
// surface vertex, TetGen's mesh and ours (the sample CT at its default, 160 k particles:
// 0.98 GB against 0.52 GB without).
uint64_t estimate_run_bytes(int64_t voxels, int64_t points, int64_t particles, bool volume_mesh = false);

// Memory for a whole run, set once at the start of a program that runs the pipeline
// (mpumesh, the whole-run benchmarks). A run allocates and frees its stages' large
// buffers over and over, and each fresh page costs a fault and the kernel's zeroing. So,
// with glibc, freed memory stays in the process for the next allocation (blocks up to
// 32 MiB come from the heap, not fresh mappings, and the heap is not trimmed).
void tune_memory();

// Whether malloc should ask for transparent huge pages (glibc.malloc.hugetlb=1) depends on
// the machine. They save 4 KiB faults: a virtual machine whose host backs each fresh page
// on first touch faults 2 MiB pages in 1.7-3 times faster per byte. But one that hands
// freed memory back to its host (free page reporting) zeroes a fresh 2 MiB page at a
// quarter of the speed of 4 KiB ones. So a job whose input is at least
// kHugePageJobBytes measures it: it touches 16 MiB of fresh memory each way, and when
// huge pages fault in at least 1.2 times faster, it starts itself again (`argv`, main's,
// through /proc/self/exe) with glibc.malloc.hugetlb=1 added to GLIBC_TUNABLES, read only
// when a program starts; otherwise it adds glibc.malloc.hugetlb=0. Either way the
// programs it starts (a benchmark's runs of mpumesh) inherit the choice.
// - Nothing is done where GLIBC_TUNABLES already sets the tunable (the user's choice, or
//   the restart), where /sys/kernel/mm/transparent_hugepage/enabled is not "madvise"
//   (with "always" large mappings get huge pages anyway, with "never" none do), or
//   without glibc.
// - Smaller jobs skip it: the probe takes 0.05-0.08 s and the restart 0.05 s.
// - MPUMESH_HUGE_PAGES=1 starts again with huge pages whatever the job and the probe;
//   MPUMESH_HUGE_PAGES=0 never does.
inline constexpr uint64_t kHugePageJobBytes = 16ull << 20;
void prefer_huge_pages_if_faster(char** argv, uint64_t input_bytes);

// Whether malloc asks for huge pages in this process (GLIBC_TUNABLES sets
// glibc.malloc.hugetlb to 1 or 2).
bool malloc_huge_pages();

// Fresh memory's first-touch time as 4 KiB pages over that as 2 MiB huge pages, over
// `bytes` each way in alternating quarters; 0 where huge pages cannot be asked for.
double huge_page_fault_speedup(uint64_t bytes);

// The bytes on disk of a file, or of the files directly in a folder (a DICOM series).
uint64_t input_bytes(const std::string& path);

// Throws InputError naming `what` when the estimate exceeds the memory available.
void check_memory(const std::string& what, uint64_t need_bytes);

}  // namespace mpumesh
