// Volume meshes in the formats finite-element users load, by extension, written in ASCII:
// - .msh: gmsh MSH 4.1; each region a volume entity with its physical group
//   ("region_1", ...), 4-node tetrahedra (type 4);
// - .vtu: VTK XML unstructured grid, tetrahedra (type 10), the cell array `region`;
// - .mesh: medit (MeshVersionFormatted 2), each vertex's and tetrahedron's reference its
//   region, the boundary triangles too;
// - .inp: Abaqus/CalculiX, the mesh alone (no analysis step, so that a deck can *INCLUDE
//   it): *NODE (NSET NALL), *ELEMENT TYPE=C3D4 (ELSET EALL), an ELSET REGION_r per region
//   and the NSET BOUNDARY of the surface's nodes.
// Nodes and elements are numbered from 1 in every format. Writing goes through a temporary
// name and a rename (io/atomic_file.h). The readers read these files back (for `quality`
// and the tests), and .vtu files as meshio writes them too (binary, zlib-compressed,
// with triangles beside the tetrahedra; io/vtu_arrays.h); they refuse what they cannot
// read with an InputError naming the file.
#pragma once

#include <string>

#include "geometry/tet_mesh.h"

namespace mpumesh {

enum class TetFormat { kMsh, kVtu, kMedit, kInp };

bool is_tet_mesh_path(const std::string& path);
// Throws InputError naming the path for another extension.
TetFormat tet_format_from_path(const std::string& path);

void write_tet_mesh(const TetMesh& mesh, const std::string& path);
TetMesh read_tet_mesh(const std::string& path);
// The same from a file's bytes; `path` names it in errors.
TetMesh parse_tet_mesh(const std::string& text, TetFormat format, const std::string& path);

}  // namespace mpumesh
