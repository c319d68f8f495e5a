// The restricted Delaunay triangulation's state, private to the files that build it
// (mesh/restricted_delaunay.cpp, mesh/manifold_repair.cpp, mesh/lost_sheets.cpp): CGAL's
// Delaunay triangulation of the particles and repair points, f at its Voronoi vertices,
// the restricted facets, and the Triangulation that holds them.
#pragma once

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Delaunay_triangulation_cell_base_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Robust_circumcenter_traits_3.h>
#include <CGAL/Spatial_lock_grid_3.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <utility>
#include <vector>

#include "common/lap_timer.h"
#include "common/progress_fn.h"
#include "compute/compute_backend.h"
#include "mesh/circumcentre.h"
#include "mesh/restricted_delaunay.h"
#include "mpu/data_box.h"
#include "mpu/mpu_eval_ref.h"

namespace mpumesh::delaunay {

// The circumcentre of a nearly flat tetrahedron is computed exactly and rounded
// (Robust_circumcenter_traits_3, through mesh/circumcentre.h), as CGAL's surface mesher
// does: the Voronoi vertices decide which facets are restricted.
using K = CGAL::Robust_circumcenter_traits_3<CGAL::Epick>;
struct CellData {
  double f = NAN;  // f at the circumcentre (NaN: not evaluated yet)
};
using Vb = CGAL::Triangulation_vertex_base_with_info_3<uint32_t, K>;
using Cb = CGAL::Triangulation_cell_base_with_info_3<CellData, K, CGAL::Delaunay_triangulation_cell_base_3<K>>;
// Parallel insertion (TBB, with CGAL's spatial lock grid): the Delaunay triangulation of a
// point set is unique (CGAL's symbolic perturbation decides the degenerate cases), so the
// threads change only where the cells lie in memory, which nothing here depends on.
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb, CGAL::Parallel_tag>;
using Lock = CGAL::Spatial_lock_grid_3<CGAL::Tag_priority_blocking>;
using Dt = CGAL::Delaunay_triangulation_3<K, Tds, CGAL::Default, Lock>;
using Point = K::Point_3;
using Cell = Dt::Cell_handle;

inline Eigen::Vector3d vec(const Point& p) { return {p.x(), p.y(), p.z()}; }

// A cell's circumcentre from its vertices in id order: the same bits whichever order the
// cell lists them in (which depends on the insertion history and, inserted in parallel, on
// the threads), so that f's sign there, hence the mesh, is the same every run.
inline bool by_id(const Dt::Vertex_handle& a, const Dt::Vertex_handle& b) { return a->info() < b->info(); }

inline Eigen::Vector3d circumcentre(const Dt& dt, Cell c) {
  std::array<Dt::Vertex_handle, 4> v = {c->vertex(0), c->vertex(1), c->vertex(2), c->vertex(3)};
  std::sort(v.begin(), v.end(), by_id);
  return robust_circumcentre(vec(v[0]->point()), vec(v[1]->point()), vec(v[2]->point()), vec(v[3]->point()));
}

inline bool inside(const Dt& dt, Cell c) { return !dt.is_infinite(c) && c->info().f < 0; }

// A restricted facet: the facet of `cell` opposite vertex `i`, with `cell` inside and its
// neighbour outside; v holds its vertex ids ordered so the normal points out.
struct RFacet {
  Cell cell;
  int i;
  std::array<uint32_t, 3> v;
};

// f, but positive outside the fitted points' box (mpu/data_box.h): a Voronoi vertex there
// would put facets on a sheet that is not there.
inline double f_within_data(const mpu::MpuSurface& s, const Eigen::Vector3d& x) {
  return within_data(s, x) ? mpu::evaluate_f(s, x) : s.box_size;
}

// f at the circumcentres of the cells not evaluated yet (mesh/restricted_delaunay.cpp).
void evaluate_new_cells(const mpu::MpuSurface& s, Dt& dt, std::vector<char>& touched, ComputeBackend* backend,
                        const std::vector<Dt::Vertex_handle>* inserted);
// The restricted facets, all of them or those of the cells around the vertices marked in
// `touched`.
std::vector<RFacet> restricted_facets(const Dt& dt);
std::vector<RFacet> restricted_facets_near(const Dt& dt, const std::vector<char>& touched);

// One triangulation's state: the Delaunay triangulation of the particles and the repair
// points, the restricted facets, and the figures.
class Triangulation {
 public:
  Triangulation(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& points, int64_t max_repair_points,
                ComputeBackend* backend, RestrictedDelaunayStats& stats)
      : s(s),
        points(points),
        backend(backend),
        stats(stats),
        lock(bounding_box(points), 50),
        dt(K(), &lock),
        max_repair(max_repair_points > 0 ? size_t(max_repair_points) : std::max<size_t>(20000, points.size())),
        touched(points.size()) {}
  // The Delaunay triangulation of the particles (in parallel, repeatably).
  void delaunay();
  // The manifold repair and the lost sheets: after it, `facets` are the restricted facets.
  // `progress` is told 0.5 + 0.3 x the share of the first round's non-manifold elements
  // and wide facets repaired, each round.
  void make_manifold(LapTimer& timer, const ProgressFn& progress = {});
  // Components that no particle holds, or mostly off the sample (see sampled_components).
  void remove_spurious();
  // The facets as an oriented mesh: canonical order, used points then repair points.
  TriangleMesh to_mesh();

 private:
  static CGAL::Bbox_3 bounding_box(const std::vector<Eigen::Vector3d>& points) {
    Eigen::Vector3d lo = points[0], hi = lo;
    for (const auto& p : points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    return CGAL::Bbox_3(lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z());
  }
  // Inserts points as repair points (in an order that does not depend on where the cells
  // lie in memory); the new vertices go to `inserted`. Each point comes with the radius of
  // its facet's ball (0: none): a point closer than kRepairMerge of that radius to one
  // inserted before it in the same call is left out, both crossings standing for one
  // missing point. (Two groups' largest facets can have Voronoi edges that cross f = 0 at
  // nearly one place; on the sample CT fitted with ε0 = 0.347 mm two repair points 3 µm
  // apart made triangles of 0.2° and 0.4° that neither collapse nor relaxation could mend.
  // A point left out is found again in the next round if it is still needed.)
  static constexpr double kRepairMerge = 0.05;
  void insert_repair(std::vector<std::pair<Eigen::Vector3d, double>> add, Cell hint);
  // One round of the manifold repair; true when nothing is left to repair. `told` hears
  // how many elements (non-manifold groups and wide facets) the round found to repair.
  bool repair_round(int round, LapTimer& timer, const std::function<void(size_t)>& told);
  // Points on sheets no facet reaches (mesh/lost_sheets.cpp); false when there are none.
  bool add_sheet_points();

  const mpu::MpuSurface& s;
  const std::vector<Eigen::Vector3d>& points;
  ComputeBackend* backend;
  RestrictedDelaunayStats& stats;
  Lock lock;
  Dt dt;
  size_t max_repair;
  // After the first round only the cells the new points made are looked at again.
  std::vector<Eigen::Vector3d> repair;  // id - points.size() -> position
  std::vector<RFacet> facets;
  std::vector<char> touched;
  std::vector<Dt::Vertex_handle> inserted;  // the last round's repair points
  std::vector<char> is_sheet;               // per repair point: a lost-sheet point
};

}  // namespace mpumesh::delaunay
