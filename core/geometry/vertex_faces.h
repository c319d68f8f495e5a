// The faces of each vertex of a triangle set, in face order, as compressed rows: the
// faces of vertex v are faces[first[v]] .. faces[first[v + 1] - 1]: two passes over the
// faces and two allocations, against one or more allocations a vertex for a vector per
// vertex.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "geometry/triangle_mesh.h"

namespace mpumesh {

struct VertexFaces {
  std::vector<uint32_t> first, faces;
  std::span<const uint32_t> operator[](size_t v) const {
    return {faces.data() + first[v], size_t(first[v + 1] - first[v])};
  }
};

// verts_of(f): face f's three vertices (below `vertices`).
template <class VertsOf>
VertexFaces vertex_faces(size_t vertices, size_t faces, VertsOf verts_of) {
  VertexFaces r;
  r.first.assign(vertices + 1, 0);
  r.faces.resize(3 * faces);
  for (size_t f = 0; f < faces; ++f)
    for (uint32_t v : verts_of(f)) ++r.first[v + 1];
  for (size_t v = 0; v < vertices; ++v) r.first[v + 1] += r.first[v];
  std::vector<uint32_t> fill(r.first.begin(), r.first.end() - 1);
  for (size_t f = 0; f < faces; ++f)
    for (uint32_t v : verts_of(f)) r.faces[fill[v]++] = uint32_t(f);
  return r;
}

// Of a mesh's triangles.
inline VertexFaces vertex_faces(const TriangleMesh& m) {
  return vertex_faces(m.vertices.size(), m.triangles.size(), [&](size_t f) { return m.triangles[f]; });
}

}  // namespace mpumesh
