#include "mesh/component_filter.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>

#include "common/error.h"
#include "common/option_names.h"
#include "geometry/ray_triangle.h"
#include "mesh/topology.h"

namespace mpumesh {
namespace {

struct Component {
  std::vector<uint32_t> triangles;
  double volume = 0;                  // signed
  double area = 0;
  int32_t shell = -1;                 // for a cavity: the enclosing shell
  std::vector<int32_t> cavities;      // for a shell
};

// Whether p lies inside the closed component c: the parity of the crossings of a ray from
// p along a fixed, slightly skew direction (no axis-aligned degeneracies on voxel data).
bool inside(const TriangleMesh& m, const Component& c, const Eigen::Vector3d& p) {
  const Eigen::Vector3d dir = Eigen::Vector3d(0.5773, 0.5774, 0.5775).normalized();
  int crossings = 0;
  for (uint32_t f : c.triangles) {
    const auto& t = m.triangles[f];
    const auto along = ray_triangle(p, dir, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]);
    crossings += along && *along > 0;
  }
  return crossings % 2 == 1;
}

std::vector<Component> components_of(const TriangleMesh& m) {
  int64_t n = 0;
  const std::vector<int32_t> id = triangle_components(m, &n);
  std::vector<Component> c(static_cast<size_t>(n));
  for (uint32_t f = 0; f < m.triangles.size(); ++f) {
    Component& k = c[size_t(id[f])];
    k.triangles.push_back(f);
    const auto& t = m.triangles[f];
    k.volume += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6.0;
    k.area += 0.5 * (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm();
  }
  // Each cavity to the smallest shell that holds one of its vertices: the cavities in
  // parallel (each ray test scans a shell's triangles), then listed with their shells in
  // order.
  tbb::parallel_for(size_t(0), c.size(), [&](size_t k) {
    if (c[k].volume >= 0) return;
    const Eigen::Vector3d p = m.vertices[m.triangles[c[k].triangles[0]][0]];
    for (size_t s = 0; s < c.size(); ++s)
      if (c[s].volume > 0 && inside(m, c[s], p) && (c[k].shell < 0 || c[s].volume < c[size_t(c[k].shell)].volume))
        c[k].shell = int32_t(s);
  });
  for (size_t k = 0; k < c.size(); ++k)
    if (c[k].shell >= 0) c[size_t(c[k].shell)].cavities.push_back(int32_t(k));
  return c;
}

// A shell's (or a cavity's that no shell holds) volume less its cavities', and its area
// with theirs.
double net_volume(const std::vector<Component>& c, size_t k) {
  double v = c[k].volume;
  for (int32_t q : c[k].cavities) v += c[size_t(q)].volume;
  return v;
}
double total_area(const std::vector<Component>& c, size_t k) {
  double a = c[k].area;
  for (int32_t q : c[k].cavities) a += c[size_t(q)].area;
  return a;
}

// The shells (and cavities no shell holds, kept as they are), largest volume first.
std::vector<size_t> shells_by_volume(const std::vector<Component>& c) {
  std::vector<size_t> shells;
  for (size_t k = 0; k < c.size(); ++k)
    if (c[k].volume >= 0 || c[k].shell < 0) shells.push_back(k);
  std::stable_sort(shells.begin(), shells.end(),
                   [&](size_t a, size_t b) { return net_volume(c, a) > net_volume(c, b); });
  return shells;
}

}  // namespace

int64_t count_parts(const TriangleMesh& m) { return int64_t(shells_by_volume(components_of(m)).size()); }

std::vector<MeshPart> split_parts(const TriangleMesh& m) {
  const std::vector<Component> c = components_of(m);
  std::vector<MeshPart> parts;
  for (size_t k : shells_by_volume(c)) {
    MeshPart part;
    part.volume_mm3 = net_volume(c, k);
    part.area_mm2 = total_area(c, k);
    std::vector<uint32_t> index(m.vertices.size(), UINT32_MAX);
    std::vector<int32_t> members = {int32_t(k)};
    members.insert(members.end(), c[k].cavities.begin(), c[k].cavities.end());
    std::vector<uint32_t> faces;
    for (int32_t q : members) faces.insert(faces.end(), c[size_t(q)].triangles.begin(), c[size_t(q)].triangles.end());
    std::sort(faces.begin(), faces.end());
    std::vector<char> used(m.vertices.size(), 0);
    for (uint32_t f : faces)
      for (uint32_t v : m.triangles[f]) used[v] = 1;
    for (uint32_t v = 0; v < m.vertices.size(); ++v)
      if (used[v]) {
        index[v] = uint32_t(part.mesh.vertices.size());
        part.mesh.vertices.push_back(m.vertices[v]);
      }
    for (uint32_t f : faces)
      part.mesh.triangles.push_back({index[m.triangles[f][0]], index[m.triangles[f][1]], index[m.triangles[f][2]]});
    parts.push_back(std::move(part));
  }
  return parts;
}

FilteredMesh filter_components(const TriangleMesh& m, const ComponentOptions& filter) {
  FilteredMesh out;
  std::vector<Component> c = components_of(m);
  const std::vector<size_t> shells = shells_by_volume(c);
  auto net = [&](size_t k) { return net_volume(c, k); };
  auto area = [&](size_t k) { return total_area(c, k); };
  std::vector<char> keep_triangle(m.triangles.size(), 0);
  for (size_t r = 0; r < shells.size(); ++r) {
    const size_t k = shells[r];
    const bool sized = (filter.largest <= 0 || int64_t(r) < filter.largest) && net(k) >= filter.min_volume_mm3;
    const bool sheet = 2 * net(k) < filter.min_thickness_mm * area(k);
    const bool keep = sized && !sheet;
    std::vector<int32_t> parts = {int32_t(k)};
    parts.insert(parts.end(), c[k].cavities.begin(), c[k].cavities.end());
    if (keep) {
      ++out.kept;
      for (int32_t q : parts)
        for (uint32_t f : c[size_t(q)].triangles) keep_triangle[f] = 1;
      continue;
    }
    DroppedComponent d;
    d.volume_mm3 = net(k);
    d.area_mm2 = area(k);
    d.thin = sized;
    int64_t corners = 0;
    std::vector<uint32_t> used;
    for (int32_t q : parts)
      for (uint32_t f : c[size_t(q)].triangles) {
        ++d.triangles;
        for (uint32_t v : m.triangles[f]) d.centre += m.vertices[v], ++corners, used.push_back(v);
      }
    d.centre /= double(std::max<int64_t>(corners, 1));
    std::sort(used.begin(), used.end());
    d.vertices = int64_t(std::unique(used.begin(), used.end()) - used.begin());
    out.dropped.push_back(d);
  }
  // The kept triangles and their vertices, in their order, with the attributes.
  std::vector<uint32_t> index(m.vertices.size(), UINT32_MAX);
  for (uint32_t f = 0; f < m.triangles.size(); ++f)
    if (keep_triangle[f])
      for (uint32_t v : m.triangles[f]) index[v] = 0;
  const bool normals = m.normals.size() == m.vertices.size(), curvature = m.curvature.size() == m.vertices.size();
  for (uint32_t v = 0; v < m.vertices.size(); ++v) {
    if (index[v] == UINT32_MAX) continue;
    index[v] = uint32_t(out.mesh.vertices.size());
    out.mesh.vertices.push_back(m.vertices[v]);
    if (normals) out.mesh.normals.push_back(m.normals[v]);
    if (curvature) out.mesh.curvature.push_back(m.curvature[v]);
  }
  for (uint32_t f = 0; f < m.triangles.size(); ++f)
    if (keep_triangle[f]) out.mesh.triangles.push_back({index[m.triangles[f][0]], index[m.triangles[f][1]], index[m.triangles[f][2]]});
  return out;
}

void require_kept(const FilteredMesh& f, const ComponentOptions& filter, const std::string& path) {
  if (!f.mesh.triangles.empty()) return;
  const double largest = f.dropped.empty() ? 0.0 : f.dropped.front().volume_mm3;
  throw InputError(fmt::format("{}: {} {} mm3 drops every structure (the largest encloses {:.1f} mm3); "
                               "nothing written",
                               path, option_ref("min_volume"), filter.min_volume_mm3, largest));
}

}  // namespace mpumesh
