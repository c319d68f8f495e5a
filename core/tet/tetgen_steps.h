// The steps a volume mesh is made in (tet/tetrahedralize.h describes them), shared by one
// closed surface (tet/tetrahedralize.cpp) and a multi-material complex
// (multi/complex_tetrahedralize.cpp): the surface's triangles as TetGen's piecewise linear
// complex, kept as they are (-Y); a coarse quality mesh refined to graded sizes, with
// points where tetrahedra of surface nodes lie flat; the tetrahedra joined across the faces
// that are not the surface's; slivers' inner nodes moved.
#pragma once

#ifndef TETLIBRARY
#define TETLIBRARY
#endif
#include <tetgen.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "geometry/tet_mesh.h"
#include "geometry/triangle_mesh.h"
#include "tet/tetrahedralize.h"

namespace mpumesh::tetgen_steps {

// The dihedral angle (degrees) under which a tetrahedron is mended (steps 3, 5 and 6).
inline constexpr double kSliverBelowDeg = 10;

// The triangle abc as one key, whatever the order of its nodes: its nodes ascending.
using FaceKey = std::array<uint32_t, 3>;
FaceKey face_key(uint32_t a, uint32_t b, uint32_t c);
struct FaceKeyHash {
  size_t operator()(const FaceKey& k) const {
    return std::hash<uint64_t>()((uint64_t(k[0]) << 32 | k[1]) * 0x9E3779B97F4A7C15ull ^ k[2]);
  }
};

// The surface's triangles by their nodes (face_key).
using SurfaceFaces = std::unordered_map<FaceKey, const std::array<uint32_t, 3>*, FaceKeyHash>;
SurfaceFaces surface_faces(const TriangleMesh& surface);

// How step 3 finds the inside beneath a flat tetrahedron's faces on the surface: the
// surface's normals point out of every tetrahedron (one closed surface), or each face's
// side is the one its tetrahedron lies on (a complex, whose triangles face from one label
// into another).
enum class FlatSide { kSurfaceOutward, kFromTetrahedron };

// Steps 1-3 on `surface` (its vertices' spacing given): TetGen's tetrahedra of the whole
// inside of its outermost triangles, every triangle a face of them. Throws InputError
// when TetGen stops.
// `progress` is told the steps done: the coarse mesh (0.2), the refined one (0.7), the
// points for flat tetrahedra (0.9).
std::unique_ptr<tetgenio> quality_tetrahedra(const TriangleMesh& surface, const std::vector<double>& spacing,
                                             const TetOptions& opt, double size, FlatSide side, TetStats& st,
                                             const ProgressFn& progress = {});

// TetGen's nodes, and its tetrahedra positively oriented.
std::vector<std::array<uint32_t, 4>> positive_tets(const tetgenio& out, std::vector<Eigen::Vector3d>& nodes);

// The tetrahedra joined across the faces that are not the surface's: each one's component,
// and the surface's faces as the tetrahedra have them (sorted by key).
struct Components {
  std::vector<uint32_t> component;  // per tetrahedron: the smallest tetrahedron of its component
  struct Face {
    FaceKey key;
    uint32_t tet;
    int face;  // kTetFace's
    bool operator<(const Face& o) const { return std::pair(key, std::pair(tet, face)) < std::pair(o.key, std::pair(o.tet, o.face)); }
  };
  std::vector<Face> faces;
};
Components solid_components(const std::vector<std::array<uint32_t, 4>>& tets, const SurfaceFaces& input);

// Whether the surface triangle s, a face of tetrahedron t's as `f`, has its normal out of t.
bool faces_out_of(const std::vector<Eigen::Vector3d>& nodes, const std::array<uint32_t, 4>& t, int f,
                  const std::array<uint32_t, 3>& s);

// Step 5 (tet/tetrahedralize.h): the inner nodes (index >= surface_nodes) of slivers moved.
// Returns the nodes moved.
int64_t perturb_slivers(TetMesh& m, uint32_t surface_nodes);

// The last figures: the nodes TetGen put on the boundary and inside, the unused nodes
// dropped, the quality, the time since t0.
void finish(TetMesh& m, size_t surface_vertices, std::chrono::steady_clock::time_point t0, TetStats& st);

// The size inside (mm): `asked`, or four times the surface's median edge.
double interior_size(const std::vector<double>& spacing, double asked);

}  // namespace mpumesh::tetgen_steps
