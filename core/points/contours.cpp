#include "points/contours.h"

#include <algorithm>

#include "common/error.h"

namespace mpumesh::pts {

double Contour::signed_area() const {
  double a = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    const auto& q = points[(i + 1) % points.size()];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * a;
}

std::vector<Contour> marching_squares(const float* g, int64_t nx, int64_t ny) {
  // Edge ids: horizontal edge (i,j)-(i+1,j) is i + nx*j; vertical edge (i,j)-(i,j+1) is
  // nx*ny + i + nx*j. vertex_of[edge] is its vertex, next[v] the vertex its outgoing
  // segment reaches.
  const int64_t n = nx * ny;
  std::vector<int32_t> vertex_of(size_t(2 * n), -1);
  std::vector<Eigen::Vector2d> pos;
  auto in = [&](int64_t i, int64_t j) { return g[i + nx * j] >= 0.0f; };
  auto frac = [](float a, float b) { return std::clamp(double(a) / (double(a) - double(b)), kMinEdgeFraction, 1.0 - kMinEdgeFraction); };
  auto vertex = [&](int64_t edge) {
    int32_t& v = vertex_of[size_t(edge)];
    if (v < 0) {
      v = int32_t(pos.size());
      if (edge < n) {
        const int64_t i = edge % nx, j = edge / nx;
        pos.emplace_back(double(i) + frac(g[edge], g[edge + 1]), double(j));
      } else {
        const int64_t e = edge - n, i = e % nx, j = e / nx;
        pos.emplace_back(double(i), double(j) + frac(g[e], g[e + nx]));
      }
    }
    return v;
  };
  std::vector<std::pair<int32_t, int32_t>> segments;
  for (int64_t j = 0; j + 1 < ny; ++j)
    for (int64_t i = 0; i + 1 < nx; ++i) {
      // Corners counter-clockwise: c0 (i,j), c1 (i+1,j), c2 (i+1,j+1), c3 (i,j+1); edge k
      // runs from corner k to corner k+1.
      const bool c[4] = {in(i, j), in(i + 1, j), in(i + 1, j + 1), in(i, j + 1)};
      const int code = c[0] | c[1] << 1 | c[2] << 2 | c[3] << 3;
      if (code == 0 || code == 15) continue;
      const int64_t edge[4] = {i + nx * j, n + (i + 1) + nx * j, i + nx * (j + 1), n + i + nx * j};
      // A segment's end is numbered before its start (vertex() numbers a vertex when first
      // asked): the order, and so every contour's first point, is fixed in the code, not
      // left to the compiler's order of evaluating arguments.
      auto add_segment = [&](int64_t from_edge, int64_t to_edge) {
        const int32_t to = vertex(to_edge);
        segments.emplace_back(vertex(from_edge), to);
      };
      if (code == 5 || code == 10) {  // saddle: cut off each inside corner
        for (int k = 0; k < 4; ++k)
          if (c[k]) add_segment(edge[k], edge[(k + 3) % 4]);
        continue;
      }
      int out_edge = -1, in_edge = -1;  // inside -> outside, outside -> inside (counter-clockwise)
      for (int k = 0; k < 4; ++k) {
        if (c[k] && !c[(k + 1) % 4]) out_edge = k;
        if (!c[k] && c[(k + 1) % 4]) in_edge = k;
      }
      add_segment(edge[out_edge], edge[in_edge]);
    }
  std::vector<int32_t> next(pos.size(), -1);
  for (const auto& [a, b] : segments) {
    MPUMESH_ASSERT(next[size_t(a)] < 0, "marching squares: two segments leave one vertex");
    next[size_t(a)] = b;
  }
  std::vector<Contour> out;
  std::vector<uint8_t> seen(pos.size(), 0);
  for (size_t s = 0; s < pos.size(); ++s) {
    if (seen[s]) continue;
    Contour c;
    for (int32_t v = int32_t(s);; v = next[size_t(v)]) {
      MPUMESH_ASSERT(v >= 0, "marching squares: open contour (is the border ring negative?)");
      if (seen[size_t(v)]) {
        MPUMESH_ASSERT(v == int32_t(s), "marching squares: contours cross");
        break;
      }
      seen[size_t(v)] = 1;
      c.points.push_back(pos[size_t(v)]);
    }
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace mpumesh::pts
