#include "mesh/surface_attributes.h"

#include "common/error.h"
#include "common/neighbour_grid.h"
#include "geometry/angle.h"
#include "mpu/mpu_eval_ref.h"
#include "particles/sizing_field.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <numbers>

namespace mpumesh {

void attach_surface_attributes(TriangleMesh& mesh, const mpu::MpuSurface& surface, ComputeBackend& backend) {
  const std::vector<mpu::EvalRow> rows = backend.mpu_eval(surface, mesh.vertices);
  mesh.normals.assign(mesh.vertices.size(), Eigen::Vector3f::Zero());
  mesh.curvature.assign(mesh.vertices.size(), {0, 0, 0, 0});
  for (size_t i = 0; i < rows.size(); ++i) {
    const mpu::EvalRow& r = rows[i];
    const Eigen::Vector3d g(r.g[0], r.g[1], r.g[2]);
    const double len = g.norm();
    if (len > 0) mesh.normals[i] = (g / len).cast<float>();
    mesh.curvature[i] = {float(r.k1), float(r.k2), float(r.gauss), float(r.mean)};
  }
}

void estimate_mesh_curvature(TriangleMesh& mesh) {
  const size_t n = mesh.vertices.size();
  std::vector<Eigen::Vector3d> normal(n, Eigen::Vector3d::Zero()), laplace(n, Eigen::Vector3d::Zero());
  std::vector<double> angle_sum(n, 0.0), area(n, 0.0);
  double signed_volume = 0;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d p[3] = {mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]};
    const Eigen::Vector3d cr = (p[1] - p[0]).cross(p[2] - p[0]);
    const double a2 = cr.norm();  // twice the area
    signed_volume += p[0].dot(p[1].cross(p[2])) / 6;
    if (!(a2 > 0)) continue;
    double ang[3], cot[3];
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d u = p[(k + 1) % 3] - p[k], v = p[(k + 2) % 3] - p[k];
      ang[k] = angle_between(u, v);
      cot[k] = u.dot(v) / a2;
    }
    const bool obtuse = ang[0] > std::numbers::pi / 2 || ang[1] > std::numbers::pi / 2 || ang[2] > std::numbers::pi / 2;
    for (int k = 0; k < 3; ++k) {
      const uint32_t i = t[size_t(k)];
      normal[i] += cr;  // area-weighted (twice)
      angle_sum[i] += ang[k];
      // Edge (i, j) is opposite corner l, edge (i, l) opposite corner j.
      const Eigen::Vector3d eij = p[k] - p[(k + 1) % 3], eil = p[k] - p[(k + 2) % 3];
      laplace[i] += cot[(k + 2) % 3] * eij + cot[(k + 1) % 3] * eil;
      if (!obtuse)
        area[i] += (eij.squaredNorm() * cot[(k + 2) % 3] + eil.squaredNorm() * cot[(k + 1) % 3]) / 8;
      else
        area[i] += a2 / 2 / (ang[k] > std::numbers::pi / 2 ? 2 : 4);
    }
  }
  // A mesh whose triangles wind clockwise from outside encloses a negative volume.
  const double outward = signed_volume < 0 ? -1.0 : 1.0;
  mesh.normals.assign(n, Eigen::Vector3f::Zero());
  mesh.curvature.assign(n, {0, 0, 0, 0});
  for (size_t i = 0; i < n; ++i) {
    const double len = normal[i].norm();
    if (!(len > 0) || !(area[i] > 0)) continue;
    const Eigen::Vector3d nv = outward * normal[i] / len;
    const double K = (2 * std::numbers::pi - angle_sum[i]) / area[i];
    const double H = -0.5 * laplace[i].dot(nv) / (2 * area[i]);
    const double d = std::sqrt(std::max(H * H - K, 0.0));
    mesh.normals[i] = nv.cast<float>();
    mesh.curvature[i] = {float(H + d), float(H - d), float(K), float(H)};
  }
}

std::vector<double> gauss_at_mesh_scale(const TriangleMesh& m) {
  const size_t n = m.vertices.size();
  MPUMESH_ASSERT(m.curvature.size() == n, "gauss_at_mesh_scale: the mesh has no curvature");
  std::vector<Eigen::Vector3d> normal(n, Eigen::Vector3d::Zero());
  std::vector<double> area(n, 0.0), length(n, 0.0), edges(n, 0.0), gauss(n), kappa(n);
  for (const auto& t : m.triangles) {
    const Eigen::Vector3d c = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]);
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
      const double e = (m.vertices[a] - m.vertices[b]).norm();
      normal[a] += c, area[a] += c.norm() / 6;
      length[a] += e, edges[a] += 1, length[b] += e, edges[b] += 1;
    }
  }
  for (size_t i = 0; i < n; ++i) {
    if (normal[i].norm() > 0) normal[i].normalize();
    length[i] = edges[i] > 0 ? length[i] / edges[i] : 0.0;
    gauss[i] = m.curvature[i][2];
    kappa[i] = std::max(std::abs(double(m.curvature[i][0])), std::abs(double(m.curvature[i][1])));
  }
  particles::average_over_patches(m.vertices, normal, area, length, gauss, kappa);
  return gauss;
}

void smooth_curvature(TriangleMesh& m, double sigma) {
  const size_t n = m.vertices.size();
  MPUMESH_ASSERT(m.curvature.size() == n && m.normals.size() == n, "smooth_curvature: the mesh has no curvature");
  if (n == 0 || !(sigma > 0)) return;
  std::vector<double> area(n, 0.0);
  for (const auto& t : m.triangles) {
    const double a3 = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm() / 6;
    for (uint32_t v : t) area[v] += a3;
  }
  const double reach = 3 * sigma, inv2s2 = 1 / (2 * sigma * sigma);
  const NeighbourGrid grid(m.vertices, reach);
  std::vector<std::array<float, 4>> out(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      double w = 0, s1 = 0, s2 = 0;
      grid.for_each_within(m.vertices[i], [&](uint32_t j) {
        if (m.normals[j].dot(m.normals[i]) < 0.5f || !std::isfinite(m.curvature[j][0]) ||
            !std::isfinite(m.curvature[j][1]))
          return;
        const double wj = area[j] * std::exp(-(m.vertices[j] - m.vertices[i]).squaredNorm() * inv2s2);
        w += wj, s1 += wj * m.curvature[j][0], s2 += wj * m.curvature[j][1];
      });
      if (!(w > 0)) {
        out[i] = m.curvature[i];
        continue;
      }
      const double k1 = s1 / w, k2 = s2 / w;
      out[i] = {float(k1), float(k2), float(k1 * k2), float(0.5 * (k1 + k2))};
    }
  });
  m.curvature.swap(out);
}

}  // namespace mpumesh
