#include "mesh/cgal_geometry.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <iterator>
#include <set>

#include "common/error.h"

namespace mpumesh {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Triangle = K::Triangle_3;

Point to_cgal(const Eigen::Vector3d& p) { return Point(p.x(), p.y(), p.z()); }

// CGAL's box search scans a set of boxes below this size instead of splitting it (its
// default is 10): see intersecting_triangles.
constexpr std::ptrdiff_t kBoxCutoff = 1000;

// Whether triangles fa and fb of the mesh (its vertices as `pts`) cross: exact
// predicates chosen by how many vertices they share, as PMP does internally; without
// `adjacent`, triangles that share a vertex never count.
bool triangles_cross(const TriangleMesh& mesh, const std::vector<Point>& pts, size_t fa, size_t fb, bool adjacent) {
  const auto& a = mesh.triangles[fa];
  const auto& b = mesh.triangles[fb];
  int shared = 0, ia = -1, ib = -1;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a[size_t(i)] == b[size_t(j)]) {
        ++shared;
        ia = i;
        ib = j;
      }
  if (shared > 0 && !adjacent) return false;
  const Triangle ta(pts[a[0]], pts[a[1]], pts[a[2]]), tb(pts[b[0]], pts[b[1]], pts[b[2]]);
  if (shared == 0) return CGAL::do_intersect(ta, tb);
  if (shared == 1) {
    // The edge opposite the shared vertex of either triangle must meet the other.
    const K::Segment_3 sa(pts[a[size_t((ia + 1) % 3)]], pts[a[size_t((ia + 2) % 3)]]);
    const K::Segment_3 sb(pts[b[size_t((ib + 1) % 3)]], pts[b[size_t((ib + 2) % 3)]]);
    return CGAL::do_intersect(sa, tb) || CGAL::do_intersect(sb, ta);
  }
  if (shared == 2) {
    // Sharing an edge: they overlap only when coplanar and folded onto the same side.
    size_t oa = 0, ob = 0;
    for (size_t i = 0; i < 3; ++i) {
      if (a[i] != b[0] && a[i] != b[1] && a[i] != b[2]) oa = i;
      if (b[i] != a[0] && b[i] != a[1] && b[i] != a[2]) ob = i;
    }
    const Point& p = pts[a[(oa + 1) % 3]];
    const Point& q = pts[a[(oa + 2) % 3]];
    return CGAL::coplanar(p, q, pts[a[oa]], pts[b[ob]]) &&
           CGAL::coplanar_orientation(p, q, pts[a[oa]], pts[b[ob]]) == CGAL::POSITIVE;
  }
  return true;  // the same triangle twice
}

using Box = CGAL::Box_intersection_d::Box_with_handle_d<double, 3, size_t, CGAL::Box_intersection_d::ID_EXPLICIT>;

// The pairs (smaller handle first) of overlapping boxes of `a` with each other, or of `a`
// against `b`: two of CGAL's sequential searches side by side, on the boxes that reach
// below and above a plane x = split (the median lower x; a box across it is in both). A
// pair goes to the half that holds the larger of its two lower x bounds, where both its
// boxes are, so it is found once.
std::vector<std::pair<uint32_t, uint32_t>> overlapping_boxes(const std::vector<Box>& a, const std::vector<Box>* b) {
  if (a.empty()) return {};
  std::vector<double> lows(a.size());
  for (size_t i = 0; i < a.size(); ++i) lows[i] = a[i].min_coord(0);
  std::nth_element(lows.begin(), lows.begin() + ptrdiff_t(lows.size() / 2), lows.end());
  const double split = lows[lows.size() / 2];
  std::vector<std::pair<uint32_t, uint32_t>> found[2];
  auto search = [&](int upper) {
    auto in_half = [&](const Box& x) { return upper ? x.max_coord(0) >= split : x.min_coord(0) < split; };
    auto part = [&](const std::vector<Box>& all) {
      std::vector<Box> out;
      std::copy_if(all.begin(), all.end(), std::back_inserter(out), in_half);
      return out;
    };
    auto keep = [&](const Box& x, const Box& y) {
      if ((std::max(x.min_coord(0), y.min_coord(0)) >= split) != bool(upper)) return;  // the other half's
      const size_t f = x.handle(), g = y.handle();
      if (f != g) found[upper].emplace_back(uint32_t(std::min(f, g)), uint32_t(std::max(f, g)));
    };
    std::vector<Box> ha = part(a);
    if (b) {
      std::vector<Box> hb = part(*b);
      CGAL::box_intersection_d(ha.begin(), ha.end(), hb.begin(), hb.end(), keep, kBoxCutoff);
    } else {
      CGAL::box_self_intersection_d(ha.begin(), ha.end(), keep, kBoxCutoff);
    }
  };
  tbb::parallel_invoke([&] { search(0); }, [&] { search(1); });
  found[0].insert(found[0].end(), found[1].begin(), found[1].end());
  return std::move(found[0]);
}

}  // namespace

std::vector<std::pair<uint32_t, uint32_t>> intersecting_triangles(const TriangleMesh& mesh,
                                                                 const std::vector<uint32_t>* among, bool adjacent) {
  // CGAL 5.5 (Debian 12) has no triangle-soup variant of PMP::self_intersections, and the
  // meshes measured here may be non-manifold; so: bounding-box pairs, then the exact tests
  // of triangles_cross.
  std::vector<Point> pts;
  pts.reserve(mesh.vertices.size());
  for (const auto& v : mesh.vertices) pts.push_back(to_cgal(v));
  auto make_boxes = [&](auto&& ids, size_t n) {
    std::vector<Box> boxes;
    boxes.reserve(n);
    for (size_t k = 0; k < n; ++k) {
      const size_t f = ids(k);
      const auto& t = mesh.triangles[f];
      if (CGAL::collinear(pts[t[0]], pts[t[1]], pts[t[2]])) continue;  // degenerate: counted by topology
      boxes.emplace_back(pts[t[0]].bbox() + pts[t[1]].bbox() + pts[t[2]].bbox(), f);
    }
    return boxes;
  };
  std::vector<Box> boxes = make_boxes([](size_t k) { return k; }, mesh.triangles.size());
  // The box pairs come from CGAL's sequential search with a cutoff of 1,000 boxes (below
  // it a box set is scanned, not split), in two halves side by side: on a mesh of 10^5
  // triangles about five times faster than CGAL's parallel search at its default cutoff
  // of 10. The exact tests then run on every core.
  // Listing most triangles, the whole mesh against itself is the faster search (the
  // listed ones against all of them runs the box search both ways); its pairs are then
  // kept where they hold a listed triangle.
  std::vector<char> listed;
  if (among && 2 * among->size() > mesh.triangles.size()) {
    listed.assign(mesh.triangles.size(), 0);
    for (uint32_t f : *among) listed[f] = 1;
  }
  std::vector<std::pair<uint32_t, uint32_t>> candidates;
  if (!among || !listed.empty()) {
    candidates = overlapping_boxes(boxes, nullptr);
  } else {
    const std::vector<Box> some = make_boxes([&](size_t k) { return size_t((*among)[k]); }, among->size());
    candidates = overlapping_boxes(some, &boxes);
  }
  if (!listed.empty())
    candidates.erase(std::remove_if(candidates.begin(), candidates.end(),
                                    [&](const auto& p) { return !listed[p.first] && !listed[p.second]; }),
                     candidates.end());
  std::vector<char> crossing(candidates.size(), 0);
  tbb::parallel_for(size_t(0), candidates.size(), [&](size_t k) {
    crossing[k] = triangles_cross(mesh, pts, candidates[k].first, candidates[k].second, adjacent);
  });
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  for (size_t k = 0; k < candidates.size(); ++k)
    if (crossing[k]) pairs.push_back(candidates[k]);
  // A pair of two listed triangles is found twice (once from each side).
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

std::vector<std::pair<uint32_t, uint32_t>> crossing_pairs(const TriangleMesh& a, const TriangleMesh& b) {
  auto triangles = [](const TriangleMesh& m) {
    std::vector<Triangle> t;
    t.reserve(m.triangles.size());
    for (const auto& f : m.triangles)
      t.emplace_back(to_cgal(m.vertices[f[0]]), to_cgal(m.vertices[f[1]]), to_cgal(m.vertices[f[2]]));
    return t;
  };
  const std::vector<Triangle> ta = triangles(a), tb = triangles(b);
  auto boxes = [](const std::vector<Triangle>& t) {
    std::vector<Box> out;
    out.reserve(t.size());
    for (size_t i = 0; i < t.size(); ++i)
      if (!t[i].is_degenerate()) out.emplace_back(t[i].bbox(), i);
    return out;
  };
  std::vector<Box> ba = boxes(ta), bb = boxes(tb);
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  CGAL::box_intersection_d(
      ba.begin(), ba.end(), bb.begin(), bb.end(),
      [&](const Box& x, const Box& y) {
        if (CGAL::do_intersect(ta[x.handle()], tb[y.handle()]))
          pairs.emplace_back(uint32_t(x.handle()), uint32_t(y.handle()));
      },
      kBoxCutoff);
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

int64_t count_crossings(const TriangleMesh& a, const TriangleMesh& b) { return int64_t(crossing_pairs(a, b).size()); }

std::vector<std::pair<uint32_t, uint32_t>> new_intersections(const TriangleMesh& now, const TriangleMesh& was,
                                                             const std::vector<uint32_t>& changed) {
  if (changed.empty()) return {};
  const auto before = intersecting_triangles(was, &changed, true);
  const std::set<std::pair<uint32_t, uint32_t>> old(before.begin(), before.end());
  std::vector<std::pair<uint32_t, uint32_t>> out;
  for (const auto& p : intersecting_triangles(now, &changed, true))
    if (!old.count(p)) out.push_back(p);
  return out;
}

int64_t count_self_intersections(const TriangleMesh& mesh) {
  return int64_t(intersecting_triangles(mesh, nullptr).size());
}

namespace {

using Prim = CGAL::AABB_triangle_primitive<K, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Prim>>;

// The non-degenerate triangles of `to` (kept alive beside the tree that points into them).
std::vector<Triangle> cgal_triangles(const TriangleMesh& to) {
  if (to.triangles.empty()) throw InputError("reference mesh has no triangles");
  std::vector<Triangle> tris;
  tris.reserve(to.triangles.size());
  for (const auto& t : to.triangles) {
    Triangle tr(to_cgal(to.vertices[t[0]]), to_cgal(to.vertices[t[1]]), to_cgal(to.vertices[t[2]]));
    if (!tr.is_degenerate()) tris.push_back(tr);
  }
  return tris;
}

}  // namespace

std::vector<double> point_distances(const std::vector<Eigen::Vector3d>& points, const TriangleMesh& to) {
  const std::vector<Triangle> tris = cgal_triangles(to);
  Tree tree(tris.cbegin(), tris.cend());
  tree.accelerate_distance_queries();
  std::vector<double> d(points.size());
  for (size_t i = 0; i < points.size(); ++i) d[i] = std::sqrt(tree.squared_distance(to_cgal(points[i])));
  return d;
}

DistanceSamples sample_distances(const TriangleMesh& from, const TriangleMesh& to) {
  const std::vector<Triangle> tris = cgal_triangles(to);
  Tree tree(tris.cbegin(), tris.cend());
  tree.accelerate_distance_queries();
  DistanceSamples s;
  auto add = [&](const Eigen::Vector3d& p, double w) {
    s.distance.push_back(std::sqrt(tree.squared_distance(to_cgal(p))));
    s.weight.push_back(w);
  };
  // Vertices are shared: each gets one third of the area of its triangles; the interior
  // points (barycentric 2/3,1/6,1/6 rotations) split the rest of each triangle.
  std::vector<double> vw(from.vertices.size(), 0.0);
  for (const auto& t : from.triangles) {
    const Eigen::Vector3d &a = from.vertices[t[0]], &b = from.vertices[t[1]], &c = from.vertices[t[2]];
    const double area = 0.5 * (b - a).cross(c - a).norm();
    for (uint32_t v : t) vw[v] += area / 6.0;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& p0 = k == 0 ? a : k == 1 ? b : c;
      add((2.0 / 3.0) * p0 + (1.0 / 6.0) * (a + b + c - p0), area / 6.0);
    }
  }
  for (size_t v = 0; v < from.vertices.size(); ++v)
    if (vw[v] > 0) add(from.vertices[v], vw[v]);
  return s;
}

std::vector<ClosestOnMesh> closest_and_inside(const std::vector<Eigen::Vector3d>& points, const TriangleMesh& to) {
  const std::vector<Triangle> tris = cgal_triangles(to);
  Tree tree(tris.cbegin(), tris.cend());
  tree.accelerate_distance_queries();
  // A fixed, slightly skew direction: no axis-aligned degeneracies on voxel data.
  const K::Vector_3 dir(0.5773, 0.5774, 0.5775);
  std::vector<ClosestOnMesh> out(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const Point p = to_cgal(points[i]);
    const Point c = tree.closest_point(p);
    out[i].point = Eigen::Vector3d(c.x(), c.y(), c.z());
    out[i].inside = tree.number_of_intersected_primitives(K::Ray_3(p, dir)) % 2 == 1;
  }
  return out;
}

}  // namespace mpumesh
