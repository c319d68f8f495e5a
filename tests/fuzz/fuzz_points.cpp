// Oriented point clouds (PLY, XYZ) and position lists (core/io/point_io.cpp): the first
// byte picks which.
#include "fuzz_common.h"
#include "io/point_io.h"

MPUMESH_FUZZ_TARGET({
  if (bytes.empty()) return 0;
  const std::string rest = bytes.substr(1);
  switch (uint8_t(bytes[0]) % 3) {
    case 0: mpumesh::parse_point_cloud(rest, ".ply", "fuzz.ply"); break;
    case 1: mpumesh::parse_point_cloud(rest, ".xyz", "fuzz.xyz"); break;
    default: mpumesh::parse_positions(rest, "fuzz-positions");
  }
})
