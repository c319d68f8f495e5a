#include "mesh/topology.h"

#include <fmt/format.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <functional>
#include <numeric>

#include "common/error.h"
#include "geometry/vertex_faces.h"

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
  // Half-edges (from, to, face), sorted by undirected key.
  struct Half {
    uint64_t key;
    uint32_t from, face;
  };
  std::vector<Half> he;
  he.reserve(mesh.triangles.size() * 3);
  std::vector<char> used(mesh.vertices.size(), 0);
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto& tri = mesh.triangles[f];
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) ++t.degenerate_triangles;
    for (int c = 0; c < 3; ++c) {
      uint32_t a = tri[size_t(c)], b = tri[size_t((c + 1) % 3)];
      used[a] = 1;
      he.push_back({edge_key(a, b), a, uint32_t(f)});
    }
  }
  t.vertices = std::count(used.begin(), used.end(), 1);
  // (Only counted, so the order of equal keys does not matter.)
  tbb::parallel_sort(he.begin(), he.end(), [](const Half& x, const Half& y) { return x.key < y.key; });
  for (size_t i = 0; i < he.size();) {
    size_t j = i;
    while (j < he.size() && he[j].key == he[i].key) ++j;
    const size_t n = j - i;
    ++t.edges;
    if (n == 1) ++t.border_edges;
    else if (n > 2) ++t.nonmanifold_edges;
    else if (he[i].from == he[i + 1].from) ++t.misoriented_edges;
    i = j;
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
