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
// 32 MiB come from the heap, not fresh mappings, and the heap is not trimmed). Malloc
// does not ask for transparent huge pages (glibc.malloc.hugetlb=1): they save faults, but
// a virtual machine that hands freed memory back to its host (free page reporting)
// zeroes a fresh 2 MiB page at a quarter of the speed of 4 KiB ones, and the run is
// slower.
void tune_memory();

// Throws InputError naming `what` when the estimate exceeds the memory available.
void check_memory(const std::string& what, uint64_t need_bytes);

}  // namespace mpumesh
