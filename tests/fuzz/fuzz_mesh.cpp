// PLY, STL, OBJ and OFF meshes (core/io/mesh_io.cpp): the first byte picks the format.
#include "fuzz_common.h"
#include "io/mesh_io.h"

MPUMESH_FUZZ_TARGET({
  if (bytes.empty()) return 0;
  const auto format = static_cast<mpumesh::MeshFormat>(uint8_t(bytes[0]) % 4);
  mpumesh::parse_mesh(bytes.substr(1), format, "fuzz-mesh");
})
