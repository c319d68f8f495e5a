// An indexed triangle mesh in millimetres: #V by 3 vertices, #F by 3 vertex indices,
// counter-clockwise seen from outside (normals point out of the enclosed volume).
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <vector>

namespace mpumesh {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<uint32_t, 3>> triangles;
  // Optional per-vertex data, each either empty or one entry per vertex (written to and
  // read from PLY): unit outward normals, and the curvature of the surface the mesh was
  // made from: k1 >= k2 (1/mm), Gaussian K (1/mm^2) and mean H (1/mm). Code that changes
  // the vertices drops them; they are attached last (mesh/surface_attributes.h).
  std::vector<Eigen::Vector3f> normals;
  std::vector<std::array<float, 4>> curvature;
  // Optional per-triangle data, empty or one entry per triangle (PLY face properties
  // label_a, label_b): the labels of the two regions a multi-material complex's triangle
  // separates, a < b, 0 the background; the triangle's normal points from a into b.
  std::vector<std::array<int32_t, 2>> face_labels;
};

// The undirected edge {a, b} as one 64-bit key (smaller index in the high half).
inline uint64_t edge_key(uint32_t a, uint32_t b) {
  return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a;
}

// The signed volume the triangles enclose (mm³; positive for an outward-facing shell).
inline double enclosed_volume(const TriangleMesh& m) {
  double v = 0;
  for (const auto& t : m.triangles) v += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6.0;
  return v;
}

// The mean length of the edges at each vertex (0 at a vertex no triangle uses): the
// mesh's local spacing.
inline std::vector<double> mean_edge_lengths(const TriangleMesh& m) {
  std::vector<double> sum(m.vertices.size(), 0.0), n(m.vertices.size(), 0.0);
  for (const auto& t : m.triangles)
    for (size_t k = 0; k < 3; ++k) {
      const uint32_t a = t[k], b = t[(k + 1) % 3];
      const double e = (m.vertices[a] - m.vertices[b]).norm();
      sum[a] += e, n[a] += 1, sum[b] += e, n[b] += 1;
    }
  for (size_t i = 0; i < sum.size(); ++i) sum[i] = n[i] > 0 ? sum[i] / n[i] : 0.0;
  return sum;
}

// The triangles of `now` that differ from those of `was` (the same mesh before some
// vertices moved or edges flipped): other vertices, or one of them moved.
inline std::vector<uint32_t> changed_triangles(const TriangleMesh& now, const TriangleMesh& was) {
  std::vector<uint32_t> out;
  for (uint32_t t = 0; t < now.triangles.size(); ++t) {
    bool same = now.triangles[t] == was.triangles[t];
    for (uint32_t v : now.triangles[t]) same = same && now.vertices[v] == was.vertices[v];
    if (!same) out.push_back(t);
  }
  return out;
}

}  // namespace mpumesh
