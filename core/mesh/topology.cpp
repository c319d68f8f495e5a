#include "mesh/topology.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <functional>
#include <numeric>
#include <span>

#include "common/error.h"
#include "geometry/vertex_faces.h"
#include "mesh/edge_faces.h"

namespace mpumesh {
namespace {

struct UnionFind {
  std::vector<int32_t> parent;
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int32_t find(int32_t x) {
    while (parent[size_t(x)] != x) x = parent[size_t(x)] = parent[size_t(parent[size_t(x)])];
    return x;
  }
  void unite(int32_t a, int32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[size_t(std::max(a, b))] = std::min(a, b);
  }
};

}  // namespace

std::vector<int32_t> triangle_components(const TriangleMesh& mesh, int64_t* count) {
  UnionFind uf(mesh.vertices.size());
  for (const auto& t : mesh.triangles) {
    uf.unite(int32_t(t[0]), int32_t(t[1]));
    uf.unite(int32_t(t[1]), int32_t(t[2]));
  }
  std::vector<int32_t> label(mesh.vertices.size(), -1), out(mesh.triangles.size());
  int32_t n = 0;
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    int32_t r = uf.find(int32_t(mesh.triangles[f][0]));
    if (label[size_t(r)] < 0) label[size_t(r)] = n++;
    out[f] = label[size_t(r)];
  }
  if (count) *count = n;
  return out;
}

Topology analyze_topology(const TriangleMesh& mesh) {
  Topology t;
  t.triangles = int64_t(mesh.triangles.size());
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const auto& tri : mesh.triangles) {
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) ++t.degenerate_triangles;
    for (uint32_t v : tri) used[v] = 1;
  }
  t.vertices = std::count(used.begin(), used.end(), 1);
  // The vertex a face runs the edge `key` from.
  const auto from = [&](uint32_t f, uint64_t key) {
    const auto& tri = mesh.triangles[f];
    for (size_t c = 0; c < 3; ++c)
      if (edge_key(tri[c], tri[(c + 1) % 3]) == key) return tri[c];
    return UINT32_MAX;
  };
  const EdgeFaces edges(mesh.triangles);
  t.edges = int64_t(edges.size());
  for (size_t e = 0; e < edges.size(); ++e) {
    const std::span<const uint32_t> faces = edges.faces(e);
    if (faces.size() == 1) ++t.border_edges;
    else if (faces.size() > 2) ++t.nonmanifold_edges;
    // (A face that holds the edge twice runs it both ways.)
    else if (faces[0] != faces[1] && from(faces[0], edges.keys()[e]) == from(faces[1], edges.keys()[e]))
      ++t.misoriented_edges;
  }
  // Fans: around each vertex, triangles are linked when they share an edge at the vertex.
  const VertexFaces vf = vertex_faces(mesh);
  t.nonmanifold_vertices = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, mesh.vertices.size(), 4096), int64_t(0),
      [&](const tbb::blocked_range<size_t>& r, int64_t count) {
        std::vector<std::pair<uint32_t, int32_t>> other;
        for (size_t v = r.begin(); v != r.end(); ++v) {
          const auto fs = vf[v];
          if (fs.size() < 2) continue;
          UnionFind uf(fs.size());
          // Triangles around v sharing another vertex share an edge through v.
          other.clear();
          for (size_t k = 0; k < fs.size(); ++k)
            for (uint32_t w : mesh.triangles[fs[k]])
              if (w != v) other.push_back({w, int32_t(k)});
          std::sort(other.begin(), other.end());
          for (size_t k = 1; k < other.size(); ++k)
            if (other[k].first == other[k - 1].first) uf.unite(other[k].second, other[k - 1].second);
          int fans = 0;
          for (size_t k = 0; k < fs.size(); ++k) fans += uf.find(int32_t(k)) == int32_t(k);
          count += fans > 1;
        }
        return count;
      },
      std::plus<int64_t>());
  triangle_components(mesh, &t.components);
  t.euler = t.vertices - t.edges + t.triangles;
  t.closed = t.border_edges == 0 && t.triangles > 0;
  t.manifold = t.closed && t.nonmanifold_edges == 0 && t.nonmanifold_vertices == 0 && t.degenerate_triangles == 0;
  t.oriented = t.manifold && t.misoriented_edges == 0;
  if (t.manifold && t.oriented) t.genus = (2 * t.components - t.euler) / 2;
  return t;
}

void require_closed_manifold(const TriangleMesh& mesh, const std::string& path, const std::string& noun,
                             const std::string& why) {
  const Topology t = analyze_topology(mesh);
  if (!t.closed || t.nonmanifold_edges > 0)
    throw InputError(fmt::format("{}: {} is not a closed manifold ({} border edges, {} non-manifold edges); {}", path,
                                 noun, t.border_edges, t.nonmanifold_edges, why));
}

}  // namespace mpumesh
