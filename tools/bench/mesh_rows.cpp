#include "mesh_rows.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>

#include "mesh/cgal_geometry.h"

namespace mpumesh::bench {
namespace {

double weighted_percentile(const DistanceSamples& d, double q) {
  std::vector<size_t> o(d.distance.size());
  for (size_t i = 0; i < o.size(); ++i) o[i] = i;
  std::sort(o.begin(), o.end(), [&](size_t a, size_t b) { return d.distance[a] < d.distance[b]; });
  double total = 0;
  for (double w : d.weight) total += w;
  double acc = 0;
  for (size_t i : o) {
    acc += d.weight[i];
    if (acc >= q * total) return d.distance[i];
  }
  return o.empty() ? 0 : d.distance[o.back()];
}

}  // namespace

void measure(Row& r, const TriangleMesh& mc, bool self_intersections) {
  QualityOptions qo;
  qo.self_intersections = self_intersections;
  r.q = measure_quality(*r.mesh, qo);
  if (r.mesh == &mc) return;
  const DistanceSamples to = sample_distances(*r.mesh, mc), from = sample_distances(mc, *r.mesh);
  double sw = 0, sd = 0;
  for (size_t i = 0; i < to.distance.size(); ++i) {
    sw += to.weight[i];
    sd += to.weight[i] * to.distance[i];
  }
  r.mean_to_mc = sw > 0 ? sd / sw : 0;
  r.p99_to_mc = weighted_percentile(to, 0.99);
  r.p99_from_mc = weighted_percentile(from, 0.99);
  // Bones: marching-cubes components of more than 100 triangles; missing when the median
  // distance of their vertices to the mesh exceeds 2 mm.
  int64_t ncomp = 0;
  const std::vector<int32_t> comp = triangle_components(mc, &ncomp);
  std::vector<int64_t> tri_count(size_t(ncomp), 0);
  for (int32_t c : comp) ++tri_count[size_t(c)];
  std::vector<std::vector<Eigen::Vector3d>> verts(static_cast<size_t>(ncomp));
  for (size_t t = 0; t < mc.triangles.size(); ++t)
    if (tri_count[size_t(comp[t])] > 100) verts[size_t(comp[t])].push_back(mc.vertices[mc.triangles[t][0]]);
  for (size_t c = 0; c < verts.size(); ++c) {
    if (verts[c].empty()) continue;
    ++r.bones;
    std::vector<double> d = point_distances(verts[c], *r.mesh);
    std::nth_element(d.begin(), d.begin() + ptrdiff_t(d.size() / 2), d.end());
    if (d[d.size() / 2] > 2.0) {
      Eigen::Vector3d centre = Eigen::Vector3d::Zero();
      for (const auto& v : verts[c]) centre += v;
      centre /= double(verts[c].size());
      r.missing.push_back(fmt::format("{} triangles around ({:.1f}, {:.1f}, {:.1f}) mm, median distance {:.2f} mm",
                                      tri_count[c], centre.x(), centre.y(), centre.z(), d[d.size() / 2]));
    }
  }
}


void print_rows(const std::vector<Row>& rows) {
  std::printf("\n%-16s %9s %8s %6s %5s %6s %6s %8s %7s %7s %7s %6s %7s %7s %7s %8s\n", "mesh", "triangles", "time s",
              "closed", "manif", "genus", "comps", "self-int", "minang", "%<30", "%<20", "RR", "dihed", "mean-d",
              "p99 to", "p99 from");
  for (const Row& r : rows) {
    const Quality& q = r.q;
    std::printf("%-16s %9lld %8.2f %6s %5s %6lld %6lld %8lld %7.2f %7.2f %7.2f %6.3f %7.2f %7.3f %7.3f %8.3f\n",
                r.name.c_str(), (long long)q.topo.triangles, r.seconds, q.topo.closed ? "yes" : "no",
                q.topo.manifold ? "yes" : "no", (long long)q.topo.genus, (long long)q.topo.components,
                (long long)q.self_intersections, q.angle_min, q.pct_angle_below[2], q.pct_angle_below[1],
                q.radius_ratio_mean, q.dihedral_mean, r.mean_to_mc, r.p99_to_mc, r.p99_from_mc);
  }
  std::printf("(minang: smallest angle, degrees; %%<30, %%<20: %% of triangles whose smallest angle is under 30, 20 "
              "degrees; RR: mean radius ratio; dihed: mean dihedral angle, degrees; mean-d, p99 to: distance to the "
              "marching-cubes surface, p99 from: from it, mm)\n");
  for (const Row& r : rows) {
    if (r.bones) std::printf("%s: %lld of %lld bones missing\n", r.name.c_str(), (long long)r.missing.size(), (long long)r.bones);
    for (const std::string& m : r.missing) std::printf("  missing: %s\n", m.c_str());
  }
}

}  // namespace mpumesh::bench
