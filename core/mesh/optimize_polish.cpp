// Step 4 of the mesh optimisation (mesh/mesh_optimize.h): the flat caps removed, then
// the poorest triangles' vertices polished.
#include <algorithm>
#include <cmath>

#include "geometry/tet_mesh.h"
#include "geometry/vertex_faces.h"
#include "mesh/optimize_steps.h"
#include "mesh/quality.h"

namespace mpumesh::optimize {

// Step 4's first part (see the header): each vertex of three triangles whose tetrahedron
// with its three neighbours has a dihedral angle under flat_cap_deg is removed, the
// triangle of its neighbours taking its three, where that triangle is no triangle yet,
// each neighbour keeps three triangles and the triangle's smallest angle is at least the
// three's, or polish_below_deg. The three triangles' area vectors add up to the new
// one's, so it faces as they did. Returns how many (each a vertex and two triangles
// fewer); the removed vertex stays in the list, used by no triangle.
int64_t remove_flat_caps(TriangleMesh& m, const OptimizeOptions& opt, const FrozenVertices& frozen) {
  auto& T = m.triangles;
  const auto& x = m.vertices;
  const auto vf = vertex_faces(m);
  std::vector<char> locked(x.size(), 0), gone(T.size(), 0);
  int64_t done = 0;
  for (uint32_t v = 0; v < x.size(); ++v) {
    if (vf[v].size() != 3 || frozen[v] || locked[v]) continue;
    // The ring a, b, c in the order of v's triangles (v, a, b), (v, b, c), (v, c, a).
    const Tri& first = T[vf[v][0]];
    const int i = int(std::find(first.begin(), first.end(), v) - first.begin());
    const uint32_t a = first[size_t((i + 1) % 3)], b = first[size_t((i + 2) % 3)];
    uint32_t c = UINT32_MAX;
    for (uint32_t f : vf[v])
      for (uint32_t w : T[f])
        if (w != v && w != a && w != b) c = w;
    const Tri merged = {a, b, c};
    if (c == UINT32_MAX ||
        std::any_of(merged.begin(), merged.end(), [&](uint32_t w) { return frozen[w] || locked[w] || vf[w].size() <= 3; }))
      continue;
    const std::array<double, 6> dihedral = dihedral_angles(x[v], x[a], x[b], x[c]);
    if (!(*std::min_element(dihedral.begin(), dihedral.end()) < opt.flat_cap_deg)) continue;
    const double angle = triangle_min_angle_deg(x[a], x[b], x[c]);
    if (!(angle >= std::min(opt.polish_below_deg, smallest_angle(x, T, vf[v])))) continue;
    bool exists = false;  // abc already a triangle (a speck of four vertices)
    for (uint32_t f : vf[a])
      exists = exists || (std::count(T[f].begin(), T[f].end(), b) && std::count(T[f].begin(), T[f].end(), c) &&
                          !std::count(T[f].begin(), T[f].end(), v));
    if (exists) continue;
    T[vf[v][0]] = merged;
    gone[vf[v][1]] = gone[vf[v][2]] = 1;
    locked[v] = locked[a] = locked[b] = locked[c] = 1;
    ++done;
  }
  drop_gone_faces(T, gone);
  return done;
}

namespace {

// Step 4's places for each vertex of `verts` (kPlaces each, in order): its neighbours'
// mean, then 12 directions at 5, 15 and 30% of its shortest edge, all in its tangent plane
// (the mean of its triangles' normals), then put on f = 0 on the backend.
constexpr int kDirections = 12;
constexpr double kSteps[] = {0.05, 0.15, 0.3};
constexpr size_t kPlaces = 1 + kDirections * std::size(kSteps);
particles::ParticleState polish_places(const TriangleMesh& m, const mpu::MpuSurface& s, ComputeBackend& backend,
                                       const std::vector<double>& spacing, const OptimizeOptions& opt,
                                       const VertexFaces& vf, const std::vector<uint32_t>& verts) {
  const auto& T = m.triangles;
  const auto& x = m.vertices;
  particles::ParticleState st;
  st.resize(verts.size() * kPlaces);
  for (size_t i = 0; i < verts.size(); ++i) {
    const uint32_t v = verts[i];
    Eigen::Vector3d nrm = Eigen::Vector3d::Zero(), mean = Eigen::Vector3d::Zero();
    double shortest = INFINITY;
    int count = 0;
    for (uint32_t f : vf[v]) {
      nrm += area_normal(x, T[f]);
      for (uint32_t w : T[f])
        if (w != v) mean += x[w], ++count, shortest = std::min(shortest, (x[w] - x[v]).norm());
    }
    nrm.normalize();
    const Eigen::Vector3d u = nrm.unitOrthogonal(), w = nrm.cross(u);
    size_t k = i * kPlaces;
    const Eigen::Vector3d to_mean = mean / count - x[v];
    st.x[k++] = x[v] + to_mean - to_mean.dot(nrm) * nrm;
    for (double step : kSteps)
      for (int d = 0; d < kDirections; ++d) {
        const double a = 2 * M_PI * d / kDirections;
        st.x[k++] = x[v] + step * shortest * (std::cos(a) * u + std::sin(a) * w);
      }
    for (size_t j = i * kPlaces; j < k; ++j) st.sigma[j] = spacing[v];
  }
  project_onto_surface(s, backend, st, opt);
  return st;
}

}  // namespace

// Step 4 (see the header): each vertex of a triangle still under polish_below_deg takes,
// of its places (polish_places), the one that most raises the smallest angle around it,
// turning no triangle by more than max_turn_deg; one vertex after another. Returns the
// moves made.
int64_t polish_pass(TriangleMesh& m, const mpu::MpuSurface& s, ComputeBackend& backend,
                    const std::vector<double>& spacing, const OptimizeOptions& opt, const FrozenVertices& frozen) {
  const auto& T = m.triangles;
  auto& x = m.vertices;
  std::vector<uint32_t> verts;
  for (const Tri& t : T)
    if (triangle_min_angle_below(x[t[0]], x[t[1]], x[t[2]], opt.polish_below_deg))
      for (uint32_t v : t)
        if (!frozen[v]) verts.push_back(v);
  std::sort(verts.begin(), verts.end());
  verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  if (verts.empty()) return 0;
  const auto vf = vertex_faces(m);
  const particles::ParticleState st = polish_places(m, s, backend, spacing, opt, vf, verts);
  const double cos_turn = std::cos(opt.max_turn_deg * M_PI / 180);
  int64_t moved = 0;
  for (size_t i = 0; i < verts.size(); ++i) {
    const uint32_t v = verts[i];
    const Eigen::Vector3d home = x[v];
    std::vector<Eigen::Vector3d> normals;
    for (uint32_t f : vf[v]) normals.push_back(area_normal(x, T[f]));
    double best = smallest_angle(x, T, vf[v]);
    Eigen::Vector3d best_at = home;
    for (size_t j = i * kPlaces; j < (i + 1) * kPlaces; ++j) {
      if (!landed(st, j)) continue;
      x[v] = st.x[j];
      bool ok = true;
      for (size_t q = 0; q < vf[v].size() && ok; ++q) ok = turned_within(normals[q], area_normal(x, T[vf[v][q]]), cos_turn);
      const double angle = ok ? smallest_angle(x, T, vf[v]) : -1;
      if (angle > best + 1e-9) best = angle, best_at = x[v];
    }
    x[v] = best_at;
    moved += best_at != home;
  }
  return moved;
}


}  // namespace mpumesh::optimize
