// Volume meshes (core/io/tet_io.cpp, io/vtu_arrays.cpp): gmsh MSH 4.1, VTK .vtu (ASCII
// and base64, zlib-compressed or not), medit and Abaqus; the first byte picks the format.
#include "fuzz_common.h"
#include "io/tet_io.h"

MPUMESH_FUZZ_TARGET({
  if (bytes.empty()) return 0;
  const auto format = static_cast<mpumesh::TetFormat>(uint8_t(bytes[0]) % 4);
  mpumesh::parse_tet_mesh(bytes.substr(1), format, "fuzz-tet");
})
