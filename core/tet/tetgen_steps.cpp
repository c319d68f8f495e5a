#include "tet/tetgen_steps.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "common/error.h"
#include "common/kd_tree.h"
#include "geometry/drop_unused.h"
#include "geometry/ray_triangle.h"

namespace mpumesh::tetgen_steps {

FaceKey face_key(uint32_t a, uint32_t b, uint32_t c) {
  FaceKey v = {a, b, c};
  std::sort(v.begin(), v.end());
  return v;
}

SurfaceFaces surface_faces(const TriangleMesh& surface) {
  SurfaceFaces faces;
  faces.reserve(surface.triangles.size() * 2);
  for (const auto& t : surface.triangles) faces.emplace(face_key(t[0], t[1], t[2]), &t);
  return faces;
}

namespace {

// The surface as TetGen's piecewise linear complex.
void to_tetgen(const TriangleMesh& m, tetgenio& in) {
  in.firstnumber = 0;
  in.numberofpoints = int(m.vertices.size());
  in.pointlist = new REAL[size_t(in.numberofpoints) * 3];
  for (size_t i = 0; i < m.vertices.size(); ++i)
    for (int d = 0; d < 3; ++d) in.pointlist[3 * i + size_t(d)] = m.vertices[i][d];
  in.numberoffacets = int(m.triangles.size());
  in.facetlist = new tetgenio::facet[size_t(in.numberoffacets)];
  in.facetmarkerlist = new int[size_t(in.numberoffacets)];
  for (size_t f = 0; f < m.triangles.size(); ++f) {
    tetgenio::facet& F = in.facetlist[f];
    F.numberofpolygons = 1;
    F.polygonlist = new tetgenio::polygon[1];
    F.numberofholes = 0;
    F.holelist = nullptr;
    F.polygonlist[0].numberofvertices = 3;
    F.polygonlist[0].vertexlist = new int[3];
    for (int k = 0; k < 3; ++k) F.polygonlist[0].vertexlist[k] = int(m.triangles[f][size_t(k)]);
    in.facetmarkerlist[f] = 1;
  }
}

// TetGen, its errors (it throws an int) as InputError; `addin`: points to insert (-i).
void run_tetgen(const std::string& switches, tetgenio& in, tetgenio& out, tetgenio* addin = nullptr) {
  std::string s = switches;
  try {
    tetrahedralize(s.data(), &in, &out, addin);
  } catch (int code) {
    static const std::map<int, std::string> kWhy = {
        {1, "out of memory"},
        {2, "an internal error"},
        {3, "a self-intersection of the surface"},
        {4, "a very small input feature (the surface's triangles too close)"},
        {5, "two very close input facets"},
        {10, "an input error"}};
    const auto it = kWhy.find(code);
    throw InputError("tetmesh: TetGen stopped: " + (it != kWhy.end() ? it->second : "error " + std::to_string(code)));
  }
}

// Step 2: each node's size, graded from the surface (see the header).
void graded_sizes(tetgenio& mesh, const TriangleMesh& surface, const std::vector<double>& spacing,
                  const TetOptions& opt, double size) {
  const PointIndex index(surface.vertices);
  const KdTree& tree = index.tree;
  mesh.numberofpointmtrs = 1;
  delete[] mesh.pointmtrlist;
  mesh.pointmtrlist = new REAL[size_t(mesh.numberofpoints)];
  tbb::parallel_for(0, mesh.numberofpoints, [&](int i) {
    const double x[3] = {mesh.pointlist[3 * i], mesh.pointlist[3 * i + 1], mesh.pointlist[3 * i + 2]};
    constexpr size_t kNear = 16;
    uint32_t idx[kNear];
    double d2[kNear];
    nanoflann::KNNResultSet<double, uint32_t> rs(kNear);
    rs.init(idx, d2);
    tree.findNeighbors(rs, x, nanoflann::SearchParams());
    double s = size;
    for (size_t k = 0; k < rs.size(); ++k) s = std::min(s, spacing[idx[k]] + opt.grading * std::sqrt(d2[k]));
    mesh.pointmtrlist[i] = s;
  });
}

// How far the ray from o along the unit d goes before it meets a triangle of m (INFINITY
// when none).
double ray_hit(const TriangleMesh& m, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double nearest = INFINITY;
  for (const auto& t : m.triangles) {
    const auto along = ray_triangle(o, d, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]);
    if (along && *along > 1e-9) nearest = std::min(nearest, *along);
  }
  return nearest;
}

// Beneath the tetrahedron p flat under a fold: from its centroid along `inward`, half its
// mean edge deep, or half way to the surface's other side where that is nearer.
Eigen::Vector3d point_under_fold(const TriangleMesh& surface, const std::array<Eigen::Vector3d, 4>& p,
                                 const Eigen::Vector3d& centroid, const Eigen::Vector3d& inward) {
  double edges = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) edges += (p[size_t(i)] - p[size_t(j)]).norm() / 6;
  return centroid + 0.5 * std::min(edges, ray_hit(surface, centroid, inward)) * inward;
}

// Step 3's second part: a tetrahedron with a dihedral angle under kSliverBelowDeg and its
// four nodes on the surface is one no flip or move of inner nodes mends. With two or three
// faces on the surface it lies flat under a fold: a point beneath it (from its centroid
// along the inward normal of those faces (FlatSide), half its mean edge deep, or half way to the
// surface's other side where that is nearer: a plate); with fewer, it spans a plate from
// one side to the other: a point at its centroid, inside the plate. Those points let
// TetGen's refinement replace it. Returns them.
std::vector<Eigen::Vector3d> points_for_flat_tets(const tetgenio& mesh, const TriangleMesh& surface,
                                                  const SurfaceFaces& faces, FlatSide side) {
  std::vector<Eigen::Vector3d> out;
  for (int t = 0; t < mesh.numberoftetrahedra; ++t) {
    std::array<int, 4> v;
    std::array<Eigen::Vector3d, 4> p;
    for (int k = 0; k < 4; ++k) {
      v[size_t(k)] = mesh.tetrahedronlist[4 * t + k];
      p[size_t(k)] = Eigen::Vector3d(mesh.pointlist + 3 * v[size_t(k)]);
    }
    if (*std::ranges::max_element(v) >= int(surface.vertices.size())) continue;  // an inner node: step 5's
    const std::array<double, 6> angle = dihedral_angles(p[0], p[1], p[2], p[3]);
    if (!(*std::ranges::min_element(angle) < kSliverBelowDeg)) continue;
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    int on_surface = 0;
    for (const auto& f : kTetFace) {
      const auto it = faces.find(face_key(uint32_t(v[size_t(f[0])]), uint32_t(v[size_t(f[1])]), uint32_t(v[size_t(f[2])])));
      if (it == faces.end()) continue;
      const auto& s = *it->second;
      Eigen::Vector3d n = (surface.vertices[s[1]] - surface.vertices[s[0]]).cross(surface.vertices[s[2]] - surface.vertices[s[0]]).normalized();
      // The node opposite the face: on the tetrahedron's side of it.
      const Eigen::Vector3d& opposite = p[size_t(&f - kTetFace)];
      if (side == FlatSide::kFromTetrahedron && (opposite - surface.vertices[s[0]]).dot(n) > 0) n = -n;
      normal += n;
      ++on_surface;
    }
    const Eigen::Vector3d centroid = (p[0] + p[1] + p[2] + p[3]) / 4;
    if (on_surface < 2)
      out.push_back(centroid);  // across a plate, its nodes on both sides: a point in the plate
    else if (normal.norm() > 0)
      out.push_back(point_under_fold(surface, p, centroid, -normal.normalized()));
  }
  return out;
}

// The smallest dihedral angle of abcd (degrees), or -1 when its volume is not positive.
double min_dihedral_if_positive(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                const Eigen::Vector3d& d) {
  if (!((b - a).dot((c - a).cross(d - a)) > 0)) return -1;
  const std::array<double, 6> angle = dihedral_angles(a, b, c, d);
  return *std::min_element(angle.begin(), angle.end());
}

}  // namespace

// Step 5: sliver perturbation (Tournois, Srinivasan and Alliez 2009 perturb the vertices
// of slivers for the same end): each inner node of a tetrahedron whose smallest dihedral
// angle is under kSliverBelowDeg moves, within its star, to the place among 26
// directions at three step lengths (a tenth, a fifth and two fifths of its shortest edge)
// that most raises its star's smallest dihedral angle, keeping every tetrahedron of the
// star positive; rounds until none moves. Returns the nodes moved.
int64_t perturb_slivers(TetMesh& m, uint32_t surface_nodes) {
  std::vector<std::vector<uint32_t>> star(m.nodes.size());
  for (uint32_t t = 0; t < m.tets.size(); ++t)
    for (uint32_t v : m.tets[t]) star[v].push_back(t);
  auto shape = [&](uint32_t t) {
    const auto& v = m.tets[t];
    return tet_shape(m.nodes[v[0]], m.nodes[v[1]], m.nodes[v[2]], m.nodes[v[3]]);
  };
  // The star's smallest dihedral angle, or -1 where a tetrahedron is not positive; it
  // stops early (returning a value no better) once one is at most `beat`.
  auto star_min = [&](uint32_t v, double beat) {
    double worst = 180;
    for (uint32_t t : star[v]) {
      const auto& q = m.tets[t];
      const double d = min_dihedral_if_positive(m.nodes[q[0]], m.nodes[q[1]], m.nodes[q[2]], m.nodes[q[3]]);
      if (d < 0) return -1.0;
      worst = std::min(worst, d);
      if (worst <= beat) return worst;
    }
    return worst;
  };
  int64_t moved = 0;
  for (int round = 0; round < 5; ++round) {
    int64_t this_round = 0;
    for (uint32_t t = 0; t < m.tets.size(); ++t) {
      if (!(shape(t).min_dihedral_deg < kSliverBelowDeg)) continue;
      for (uint32_t v : m.tets[t]) {
        if (v < surface_nodes) continue;
        double shortest = INFINITY;
        for (uint32_t s : star[v])
          for (uint32_t w : m.tets[s])
            if (w != v) shortest = std::min(shortest, (m.nodes[w] - m.nodes[v]).norm());
        const Eigen::Vector3d home = m.nodes[v];
        double best = star_min(v, -1);
        Eigen::Vector3d best_at = home;
        for (double step : {0.1, 0.2, 0.4})
          for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dz = -1; dz <= 1; ++dz) {
                if (dx == 0 && dy == 0 && dz == 0) continue;
                m.nodes[v] = home + step * shortest * Eigen::Vector3d(dx, dy, dz).normalized();
                const double q = star_min(v, best);
                if (q > best + 1e-9) best = q, best_at = m.nodes[v];
              }
        m.nodes[v] = best_at;
        this_round += best_at != home;
      }
    }
    moved += this_round;
    if (this_round == 0) break;
  }
  return moved;
}

// A coarse quality mesh, its nodes given the graded sizes, refined (TetGen's -r: the sizes
// inside a tetrahedron interpolated from its nodes'; a background mesh for a second
// tetrahedralization from the surface would cost many times more, in locating each new
// point in it).
std::unique_ptr<tetgenio> quality_tetrahedra(const TriangleMesh& surface, const std::vector<double>& spacing,
                                             const TetOptions& opt, double size, FlatSide side, TetStats& st,
                                             const ProgressFn& progress) {
  tetgenio in, coarse;
  auto out = std::make_unique<tetgenio>();
  to_tetgen(surface, in);
  run_tetgen("pYq2.0Q", in, coarse);
  tell(progress, 0.2);
  graded_sizes(coarse, surface, spacing, opt, size);
  const std::string refine =
      fmt::format("rYq{}/{}mO{}/7o/{}Q", opt.radius_edge, opt.min_dihedral, opt.optimize_level, opt.max_dihedral);
  run_tetgen(refine, coarse, *out);
  tell(progress, 0.7);
  const SurfaceFaces faces = surface_faces(surface);
  const std::vector<Eigen::Vector3d> for_flat = points_for_flat_tets(*out, surface, faces, side);
  if (for_flat.empty()) return out;
  st.flat_tet_points = int64_t(for_flat.size());
  tetgenio add;
  auto again = std::make_unique<tetgenio>();
  add.numberofpoints = int(for_flat.size());
  add.pointlist = new REAL[for_flat.size() * 3];
  for (size_t i = 0; i < for_flat.size(); ++i)
    for (int d = 0; d < 3; ++d) add.pointlist[3 * i + size_t(d)] = for_flat[i][d];
  run_tetgen("i" + refine, coarse, *again, &add);
  tell(progress, 0.9);
  return again;
}


std::vector<std::array<uint32_t, 4>> positive_tets(const tetgenio& out, std::vector<Eigen::Vector3d>& nodes) {
  nodes.resize(size_t(out.numberofpoints));
  for (size_t i = 0; i < nodes.size(); ++i)
    nodes[i] = Eigen::Vector3d(out.pointlist[3 * i], out.pointlist[3 * i + 1], out.pointlist[3 * i + 2]);
  const size_t nt = size_t(out.numberoftetrahedra);
  std::vector<std::array<uint32_t, 4>> tets(nt);
  for (size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 4; ++k) tets[t][size_t(k)] = uint32_t(out.tetrahedronlist[4 * t + size_t(k)]);
    const auto& p = nodes;
    const auto& v = tets[t];
    if ((p[v[1]] - p[v[0]]).dot((p[v[2]] - p[v[0]]).cross(p[v[3]] - p[v[0]])) < 0) std::swap(tets[t][2], tets[t][3]);
  }
  return tets;
}

Components solid_components(const std::vector<std::array<uint32_t, 4>>& tets, const SurfaceFaces& input) {
  // The surface's faces bound the components (a wall between two solids, or a cavity's,
  // has a tetrahedron on either side); any other face joins the two tetrahedra that share it.
  const size_t nt = tets.size();
  Components c;
  std::unordered_map<FaceKey, uint32_t, FaceKeyHash> open;  // an inner face seen once -> its tetrahedron
  open.reserve(nt * 2);
  std::vector<uint32_t> parent(nt);
  std::iota(parent.begin(), parent.end(), 0u);
  auto root = [&](uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  for (uint32_t t = 0; t < nt; ++t)
    for (int f = 0; f < 4; ++f) {
      const auto& v = tets[t];
      const FaceKey key = face_key(v[size_t(kTetFace[f][0])], v[size_t(kTetFace[f][1])], v[size_t(kTetFace[f][2])]);
      if (input.count(key)) {
        c.faces.push_back({key, t, f});
        continue;
      }
      const auto it = open.find(key);
      if (it == open.end()) {
        open.emplace(key, t);
      } else {
        const uint32_t a = root(t), b = root(it->second);
        parent[std::max(a, b)] = std::min(a, b);
        open.erase(it);
      }
    }
  std::sort(c.faces.begin(), c.faces.end());
  c.component.resize(nt);
  for (uint32_t t = 0; t < nt; ++t) c.component[t] = root(t);
  return c;
}

bool faces_out_of(const std::vector<Eigen::Vector3d>& nodes, const std::array<uint32_t, 4>& t, int f,
                  const std::array<uint32_t, 3>& s) {
  const Eigen::Vector3d a = nodes[t[size_t(kTetFace[f][0])]];
  const Eigen::Vector3d out_normal =
      (nodes[t[size_t(kTetFace[f][1])]] - a).cross(nodes[t[size_t(kTetFace[f][2])]] - a);
  const Eigen::Vector3d surface_normal = (nodes[s[1]] - nodes[s[0]]).cross(nodes[s[2]] - nodes[s[0]]);
  return surface_normal.dot(out_normal) > 0;
}

void finish(TetMesh& m, size_t surface_vertices, std::chrono::steady_clock::time_point t0, TetStats& st) {
  st.interior_points = int64_t(m.nodes.size()) - int64_t(surface_vertices);
  {  // nodes on the boundary that the surface did not have
    std::vector<uint32_t> on;
    for (const auto& f : m.boundary)
      for (uint32_t v : f)
        if (v >= surface_vertices) on.push_back(v);
    std::sort(on.begin(), on.end());
    st.boundary_points = int64_t(std::unique(on.begin(), on.end()) - on.begin());
    st.interior_points -= st.boundary_points;
  }
  drop_unused_points(m.nodes, m.tets, m.boundary);  // the cavities' nodes
  st.quality = measure_tet_quality(m);
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double interior_size(const std::vector<double>& spacing, double asked) {
  std::vector<double> order = spacing;
  std::nth_element(order.begin(), order.begin() + ptrdiff_t(order.size() / 2), order.end());
  return asked > 0 ? asked : 4 * order[order.size() / 2];
}

}  // namespace mpumesh::tetgen_steps
