// The benchmarks' table of surface meshes measured side by side against the marching-cubes
// surface of the same volume: for each mesh its triangles, time, topology, triangle
// quality, smoothness (mean dihedral angle) and fidelity to the marching-cubes surface
// (mean and 99th-percentile distances both ways, and bones missing: marching-cubes
// components of more than 100 triangles whose vertices lie, at the median, farther than
// 2 mm from the mesh).
#pragma once

#include <string>
#include <vector>

#include "geometry/triangle_mesh.h"
#include "mesh/quality.h"

namespace mpumesh::bench {

struct Row {
  std::string name;
  const TriangleMesh* mesh = nullptr;
  double seconds = 0;
  Quality q;
  double mean_to_mc = 0, p99_to_mc = 0, p99_from_mc = 0;
  int64_t bones = 0;
  std::vector<std::string> missing;  // each missing bone: size, centre, median distance
};

// Fills r.q and, unless r.mesh is `mc` itself, the distances and the bones.
void measure(Row& r, const TriangleMesh& mc, bool self_intersections);

// The table, its legend and the bones missing per row.
void print_rows(const std::vector<Row>& rows);

}  // namespace mpumesh::bench
