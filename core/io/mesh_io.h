// Mesh files, chosen by extension: PLY (binary little-endian written; ASCII and both
// binary byte orders read), STL (binary written; ASCII and binary read, vertices welded by
// exact position), OBJ and OFF. Polygons are read as triangle fans. Every reader checks
// counts, sizes and indices and throws InputError naming the file and the problem; writers
// go through AtomicFile, so a failed write never replaces a good file.
#pragma once

#include <string>

#include "geometry/triangle_mesh.h"

namespace mpumesh {

enum class MeshFormat { kPly, kStl, kObj, kOff };

// Throws InputError for an extension that is none of .ply .stl .obj .off.
MeshFormat mesh_format_from_path(const std::string& path);

TriangleMesh read_mesh(const std::string& path);
void write_mesh(const TriangleMesh& mesh, const std::string& path);

// From memory, for the fuzzers and tests; `name` is used in error messages.
TriangleMesh parse_mesh(const std::string& bytes, MeshFormat format, const std::string& name);

}  // namespace mpumesh
