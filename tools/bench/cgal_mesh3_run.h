// The body of the Mesh_3 peer (cgal_mesh3_peer.h), for its two instantiations: sequential
// (cgal_mesh3_peer.cpp) and parallel (cgal_mesh3_parallel.cpp, TBB), compiled apart.
#pragma once

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/make_mesh_3.h>
#include <CGAL/Image_3.h>
#include <CGAL/Mesh_3/initialize_triangulation_from_gray_image.h>
#include <CGAL/Mesh_3/initialize_triangulation_from_labeled_image.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <map>
#include <sstream>

#include "cgal_mesh3_peer.h"

namespace mpumesh::bench::mesh3 {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Domain = CGAL::Labeled_mesh_domain_3<K>;

// The volume padded by one voxel of `background` on every side, as a float CGAL image in
// index space scaled by the spacing (an axis-aligned frame; vertices are mapped to the
// volume's physical frame at the end).
inline CGAL::Image_3 padded_image(const Volume& v, float background) {
  const int64_t nx = v.dims[0] + 2, ny = v.dims[1] + 2, nz = v.dims[2] + 2;
  _image* im = ::_createImage(std::size_t(nx), std::size_t(ny), std::size_t(nz), 1, v.spacing.x(), v.spacing.y(),
                              v.spacing.z(), 4, WK_FLOAT, SGN_UNKNOWN);
  float* d = static_cast<float*>(im->data);
  for (int64_t k = 0; k < nz; ++k)
    for (int64_t j = 0; j < ny; ++j)
      for (int64_t i = 0; i < nx; ++i) {
        const bool in = i >= 1 && j >= 1 && k >= 1 && i <= v.dims[0] && j <= v.dims[1] && k <= v.dims[2];
        d[i + nx * (j + ny * k)] = in ? v.at(i - 1, j - 1, k - 1) : background;
      }
  im->tx = float(-v.spacing.x());
  im->ty = float(-v.spacing.y());
  im->tz = float(-v.spacing.z());
  return CGAL::Image_3(im);
}

// The label map padded by one voxel of background (0), as an 8-bit CGAL image in the
// same frame as padded_image.
inline CGAL::Image_3 padded_labels(const Volume& v) {
  const int64_t nx = v.dims[0] + 2, ny = v.dims[1] + 2, nz = v.dims[2] + 2;
  _image* im = ::_createImage(std::size_t(nx), std::size_t(ny), std::size_t(nz), 1, v.spacing.x(), v.spacing.y(),
                              v.spacing.z(), 1, WK_FIXED, SGN_UNSIGNED);
  unsigned char* d = static_cast<unsigned char*>(im->data);
  for (int64_t k = 0; k < nz; ++k)
    for (int64_t j = 0; j < ny; ++j)
      for (int64_t i = 0; i < nx; ++i) {
        const bool in = i >= 1 && j >= 1 && k >= 1 && i <= v.dims[0] && j <= v.dims[1] && k <= v.dims[2];
        const float x = in ? v.at(i - 1, j - 1, k - 1) : 0.f;
        d[i + nx * (j + ny * k)] = static_cast<unsigned char>(std::clamp(std::lround(x), 0L, 255L));
      }
  im->tx = float(-v.spacing.x());
  im->ty = float(-v.spacing.y());
  im->tz = float(-v.spacing.z());
  return CGAL::Image_3(im);
}

// Mesh_3's refinement as `p` asks: with cells, sliver perturbation and exudation; manifold()
// where `p.manifold`.
template <class C3t3, class Criteria>
void refine(C3t3& c3t3, const Domain& domain, const Criteria& criteria, const Mesh3Params& p) {
  if (p.cell_size > 0 && p.manifold)
    CGAL::refine_mesh_3(c3t3, domain, criteria, CGAL::parameters::perturb(), CGAL::parameters::exude(),
                        CGAL::parameters::manifold());
  else if (p.cell_size > 0)
    CGAL::refine_mesh_3(c3t3, domain, criteria, CGAL::parameters::perturb(), CGAL::parameters::exude());
  else if (p.manifold)
    CGAL::refine_mesh_3(c3t3, domain, criteria, CGAL::parameters::no_perturb(), CGAL::parameters::no_exude(),
                        CGAL::parameters::manifold());
  else
    CGAL::refine_mesh_3(c3t3, domain, criteria, CGAL::parameters::no_perturb(), CGAL::parameters::no_exude());
}

// Mesh_3 on `v` as `p` asks, its triangulation sequential or parallel by `Tag`.
template <class Tag>
Mesh3Result run(const Volume& v, const Mesh3Params& p) {
  using Tr = typename CGAL::Mesh_triangulation_3<Domain, CGAL::Default, Tag>::type;
  using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr>;
  using Criteria = CGAL::Mesh_criteria_3<Tr>;
  const auto t0 = std::chrono::steady_clock::now();
  Mesh3Result r;
  float lo = v.voxels.empty() ? 0.f : v.voxels[0];
  for (float x : v.voxels) lo = std::min(lo, x);
  const float background = std::min(lo, float(p.iso - 1000));
  const CGAL::Image_3 image = p.labels ? padded_labels(v) : padded_image(v, background);
  // CGAL's gray-image domain: trilinear interpolation of the image, inside where the
  // value exceeds iso; or its labelled-image domain: the label of the voxel a point lies in.
  Domain domain = p.labels ? Domain::create_labeled_image_mesh_domain(image)
                           : Domain::create_gray_image_mesh_domain(image, CGAL::parameters::iso_value = p.iso,
                                                                   CGAL::parameters::value_outside = background);
  Criteria criteria =
      p.cell_size > 0
          ? Criteria(CGAL::parameters::facet_angle = p.facet_angle, CGAL::parameters::facet_size = p.facet_size,
                     CGAL::parameters::facet_distance = p.facet_distance, CGAL::parameters::cell_radius_edge_ratio = 3,
                     CGAL::parameters::cell_size = p.cell_size)
          : Criteria(CGAL::parameters::facet_angle = p.facet_angle, CGAL::parameters::facet_size = p.facet_size,
                     CGAL::parameters::facet_distance = p.facet_distance);
  // CGAL's own start for images: a seed in every connected component of the thresholded
  // image, and the surface points that rays from it meet. (With its default random
  // start, or a few points of each marching-cubes component, Mesh_3 loses whole bones of
  // the sample CT.) It reports on std::cout; that is muted.
  C3t3 c3t3;
  {
    std::ostringstream muted;
    std::streambuf* saved = std::cout.rdbuf(muted.rdbuf());
    if (p.labels)
      initialize_triangulation_from_labeled_image(c3t3, domain, image, criteria, static_cast<unsigned char>(0));
    else
      initialize_triangulation_from_gray_image(c3t3, domain, image, criteria, float(p.iso), float());
    std::cout.rdbuf(saved);
  }
  r.initial_points = int64_t(c3t3.triangulation().number_of_vertices());
  refine(c3t3, domain, criteria, p);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // The boundary facets, oriented outward (from the inside cell).
  std::map<typename Tr::Vertex_handle, uint32_t> index;
  auto vid = [&](typename Tr::Vertex_handle h) {
    auto [it, fresh] = index.emplace(h, uint32_t(r.mesh.vertices.size()));
    if (fresh) {
      const auto& pt = h->point().point();
      r.mesh.vertices.push_back(v.origin + v.direction * Eigen::Vector3d(pt.x(), pt.y(), pt.z()));
    }
    return it->second;
  };
  for (auto it = c3t3.facets_in_complex_begin(); it != c3t3.facets_in_complex_end(); ++it) {
    typename Tr::Cell_handle cell = it->first;
    int i = it->second;
    // The view of the facet from the cell of the higher subdomain (inside, in complex).
    const typename Tr::Cell_handle other = cell->neighbor(i);
    const int here = c3t3.is_in_complex(cell) ? int(c3t3.subdomain_index(cell)) : 0;
    const int there = c3t3.is_in_complex(other) ? int(c3t3.subdomain_index(other)) : 0;
    if (there > here) {
      i = other->index(cell);
      cell = other;
    }
    if (p.labels) r.mesh.face_labels.push_back({std::min(here, there), std::max(here, there)});
    // Facet i of a positively oriented cell, counter-clockwise seen from outside the
    // cell: (i+1, i+2, i+3) for odd i, reversed for even i.
    uint32_t a = vid(cell->vertex((i + 1) & 3)), b = vid(cell->vertex((i + 2) & 3)), c = vid(cell->vertex((i + 3) & 3));
    if (i % 2 == 0) std::swap(b, c);
    r.mesh.triangles.push_back({a, b, c});
  }
  if (p.cell_size > 0) {
    for (auto it = c3t3.cells_in_complex_begin(); it != c3t3.cells_in_complex_end(); ++it) {
      std::array<uint32_t, 4> t;
      for (int k = 0; k < 4; ++k) {
        const typename Tr::Vertex_handle h = it->vertex(k);
        auto [at, fresh] = index.emplace(h, uint32_t(r.mesh.vertices.size()));
        if (fresh) {
          const auto& pt = h->point().point();
          r.mesh.vertices.push_back(v.origin + v.direction * Eigen::Vector3d(pt.x(), pt.y(), pt.z()));
        }
        t[size_t(k)] = at->second;
      }
      r.volume.tets.push_back(t);
      r.volume.region.push_back(p.labels ? int32_t(c3t3.subdomain_index(it)) : 1);
    }
    r.volume.nodes = r.mesh.vertices;
    std::vector<int32_t> present = r.volume.region;
    std::sort(present.begin(), present.end());
    r.volume.regions = int32_t(std::unique(present.begin(), present.end()) - present.begin());
    for (auto& t : r.volume.tets) {  // positive in the physical frame (the direction may mirror)
      const auto& n = r.volume.nodes;
      if ((n[t[1]] - n[t[0]]).dot((n[t[2]] - n[t[0]]).cross(n[t[3]] - n[t[0]])) < 0) std::swap(t[2], t[3]);
    }
  }
  // Should the convention above be the other one, the enclosed volume tells.
  double vol = 0;
  for (const auto& t : r.mesh.triangles)
    vol += r.mesh.vertices[t[0]].dot(r.mesh.vertices[t[1]].cross(r.mesh.vertices[t[2]]));
  if (vol < 0)
    for (auto& t : r.mesh.triangles) std::swap(t[1], t[2]);
  return r;
}

}  // namespace mpumesh::bench::mesh3
