// What the volume mesh writers (io/tet_io.cpp) share: text appended in place, Abaqus id
// lists, and the writers of a multi-material complex's volume mesh (io/tet_io_complex.cpp).
#pragma once

#include <fmt/format.h>

#include <cstdint>
#include <iterator>
#include <string>
#include <vector>

#include "geometry/tet_mesh.h"

namespace mpumesh::tet_text {

// Appends to a string (fmt's buffer-free way: one allocation growing as needed).
struct Out {
  std::string s;
  template <class... A>
  void put(fmt::format_string<A...> f, A&&... a) {
    fmt::format_to(std::back_inserter(s), f, std::forward<A>(a)...);
  }
};

// Abaqus lists: at most 16 entries a line, 1-based.
void id_list(Out& o, const std::vector<uint32_t>& ids);

// An Abaqus/CalculiX *NODE line: the 1-based id and the coordinates, each in at most 20
// characters (CalculiX reads a number from its field's first 20), with as many
// significant digits as fit (17, 15 for a number written with an exponent).
void inp_node(Out& o, size_t id, const Eigen::Vector3d& p);

// medit's text: each vertex's reference the region of a tetrahedron that uses it, each
// tetrahedron's its region, the boundary triangles' `triangle_ref`; `comments` (lines
// starting with #) after the header.
std::string medit(const TetMesh& m, const std::string& comments, const std::vector<int32_t>& triangle_ref);

// A complex's volume mesh (TetMesh::multi_material) in each format, with its groups: a
// volume per label (label_L), a surface per interface (interface_a_b; the background's box
// `box`).
std::string msh_complex(const TetMesh& m);
std::string vtu_complex(const TetMesh& m);
std::string medit_complex(const TetMesh& m);
std::string inp_complex(const TetMesh& m);

// The group names, as every format spells them (upper case in .inp).
std::string label_name(int32_t label);
std::string interface_name(const std::array<int32_t, 2>& labels);

}  // namespace mpumesh::tet_text
