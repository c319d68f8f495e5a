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
// points (0 when not known yet) and `particles`: per voxel the intensities, the threshold
// field, the mask and labels (about 24 B); per point its position and normal, the k-d tree
// and the MPU leaves with their lookup-grid entries (about 2.4 kB, measured on the sample
// CT: 260,330 points, 258,581 leaves); per particle its state, the neighbour grids and the
// Delaunay triangulation with the surface mesher's bookkeeping (about 3 kB).
uint64_t estimate_run_bytes(int64_t voxels, int64_t points, int64_t particles);

// Throws InputError naming `what` when the estimate exceeds the memory available.
void check_memory(const std::string& what, uint64_t need_bytes);

}  // namespace mpumesh
