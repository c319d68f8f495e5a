#include "mpu/mpu_fit.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <new>
#include <type_traits>

#include "common/error.h"
#include "common/option_names.h"
#include "common/lap_timer.h"
#include "common/kd_tree.h"
#include "mpu/ball_search.h"
#include "mpu/fit_points.h"
#include "mpu/lattice_cache.h"
#include "mpu/local_fit.h"

namespace mpumesh::mpu {
namespace {

struct Cell {
  Eigen::Vector3d centre;
  double size;
  int depth;
  std::array<int64_t, 3> ijk;  // index among the cells of its depth: lowest corner box_min + ijk size
};

}  // namespace

const char* local_fit_name(LocalFit f) { return f == LocalFit::kOrthopoly ? "orthopoly" : "quadric"; }

void validate(const FitOptions& o) {
  auto need = [](bool ok, const char* name, const char* what) {
    if (!ok) throw InputError("fit: " + option_ref(name) + " must be " + what);
  };
  need(std::isfinite(o.eps) && o.eps >= 0, "eps", "zero (automatic) or positive");
  need(o.nmin >= 6 && o.nmin <= 100000, "nmin", "between 6 and 100000");
  need(std::isfinite(o.alpha) && o.alpha >= 0.5 && o.alpha <= 4, "alpha", "between 0.5 and 4");
  need(std::isfinite(o.lambda) && o.lambda > 0 && o.lambda <= 1, "lambda", "in (0, 1]");
  need(std::isfinite(o.min_radius), "min_radius", "a number (negative: automatic)");
  need(std::isfinite(o.min_radius_floor) && o.min_radius_floor >= 0, "min_radius_floor", "zero or positive");
  need(o.max_depth >= 0 && o.max_depth <= 16, "max_depth", "between 0 and 16");
  need(o.max_degree >= 2 && o.max_degree <= 4, "max_degree", "2, 3 or 4");
  need(o.grid_cells >= 0 && o.grid_cells <= 512, "grid_cells", "between 0 (automatic) and 512");
}

namespace {

// The state of one fit: the distinct points, their searches, the surface being built,
// and the auxiliary points' values cached per octree level.
class Fitter {
 public:
  // `shared`: a tree over points equal to the cloud's, or null to build one.
  Fitter(const PointCloud& cloud, const FitOptions& opt, MpuSurface& s, const KdTree* shared)
      : cloud(cloud),
        opt(opt),
        s(s),
        tree(given_or_built(shared, cloud.positions, own_index)) {
    eps = opt.eps > 0 ? opt.eps : 0.25 * median_spacing(cloud.positions, tree);
    // The median distance to the 12th nearest point (about the largest sampling gap), when
    // the smallest radius or the slope length needs it.
    gap12 = opt.min_radius < 0 || opt.fit_normals ? median_spacing(cloud.positions, tree, 12) : 0.0;
    min_radius = opt.min_radius >= 0 ? opt.min_radius : std::max(1.5 * gap12, opt.min_radius_floor);
    slope_length = opt.fit_normals ? 0.25 * gap12 : 0.0;
  }
  // The octree, level by level from the root: each cell fitted in parallel, split where
  // its fit is off by more than eps. Fills the surface's leaves and `st`'s level figures.
  void fit_levels(FitStats& st, LapTimer& timer);
  double eps = 0, min_radius = 0, slope_length = 0, gap12 = 0;

 private:
  struct Outcome {
    Leaf leaf;
    double error = 0;
    bool split = false;
    bool kept_by_held_bound = false;  // above eps, and would have split but for split_bound
  };
  // The support ball of a cell: radius alpha times its diagonal (at least the smallest),
  // grown by lambda R until it holds nmin points.
  struct Support {
    Ball ball;
    bool grown = false, at_min_radius = false;
    size_t initial = 0;  // points before growing
  };

  double aux_value(const Eigen::Vector3d& q);
  void lattice_points(const Cell& c, std::vector<AuxPoint>& aux);
  std::vector<AuxPoint> aux_points(const Cell& c, bool lattice);
  Support support(const Cell& c);
  Outcome fit_ball(const Cell& c, const Ball& b, bool away);
  // A cell away from the data: the general quadric held to its corners and centre, kept
  // when those 9 agree in sign and the quadric has that sign on all 27 points of the
  // half-cell lattice; else held to all 27. False (`aux` then the 27's usable values)
  // when fewer than 5 are usable.
  bool fit_away(const Cell& c, const Ball& b, std::vector<AuxPoint>& aux, Outcome& o);
  bool one_side_on_lattice(const Leaf& leaf, const std::vector<AuxPoint>& aux, const Cell& c) const;
  // No auxiliary point farther than eps from the surface on the other side of the leaf's
  // zero set.
  bool agrees_with(const Leaf& leaf, const std::vector<AuxPoint>& aux) const;
  // No usable fit at the depth cap (no auxiliary point agreed in sign): the plane through
  // the ball's points along their mean normal, so f stays defined.
  void plane_fallback(const Ball& ball, Outcome& o);
  Outcome process(const Cell& c);
  // The error above which a cell splits: eps, or kHeldSplit eps where the children's balls
  // would be held at the smallest radius. Those are 2/3 of the cell's radius, not half,
  // so the split lowers the error less, while the largest error over a ball's points
  // mostly measures the points' scatter there (eps is about 3 sigma). On the sample CT
  // the rule keeps a fifth fewer leaves at 0.03 mm more p99 distance to marching cubes;
  // the phantoms' trees stop above that level. A larger bound lets the distance grow.
  static constexpr double kHeldSplit = 2.0;
  bool children_held(const Cell& c) const { return opt.alpha * 0.5 * c.size * std::sqrt(3.0) < min_radius; }
  double split_bound(const Cell& c) const { return children_held(c) ? kHeldSplit * eps : eps; }
  // A cell from its depth and index: the centre follows from the index, as the corners do.
  Cell make_cell(int depth, const std::array<int64_t, 3>& ijk) const {
    const double size = s.box_size / double(int64_t(1) << depth);
    const Eigen::Vector3d centre =
        s.box_min + size * Eigen::Vector3d(double(ijk[0]) + 0.5, double(ijk[1]) + 0.5, double(ijk[2]) + 0.5);
    return Cell{centre, size, depth, ijk};
  }

  const PointCloud& cloud;
  const FitOptions& opt;
  MpuSurface& s;
  std::unique_ptr<PointIndex> own_index;
  const KdTree& tree;
  // Balls, growth and the auxiliary points' six nearest on a grid of cells about the
  // smallest ball (ball_search.h); the k-d tree keeps the large balls of the coarse levels
  // and the six nearest where the grid finds ties or too few points: the grid answers
  // the small balls faster than the tree, with the same results.
  std::unique_ptr<BallSearch> search_;
  // Auxiliary points for a general quadric: the cell's corners and centre, with the mean
  // signed distance to their 6 nearest points when all 6 agree in sign (Ohtake 2003).
  // Neighbouring cells share corners, so within a level each corner's value is found once
  // (at the position computed from its integer index, so that it is the same whichever
  // cell asks first).
  // A cell away from the data (see `away` in process) may also need its 12 edge midpoints
  // and 6 face centres: 27 points on the half-cell lattice, cached the same way (their keys
  // tagged with kHalfLattice). Its quadric is extrapolated from points outside the cell,
  // and the 9 points alone leave it free to cross zero between them, which puts spurious
  // sheets of f = 0 in the air beside a CT's bone. Where the quadric held to the 9 keeps
  // their one sign on all 27 points, the 18 others are not looked up (fit_away): two
  // thirds of the away cells on the sample CT.
  LatticeCache lattice_values;  // NaN: signs disagree
  // The level above's: a corner at depth d is a half-cell lattice point at depth d - 1,
  // and a corner there too when its indices are even (the same position to the bit: the
  // sizes differ by powers of two). On the sample CT it answers 60,700 of the 119,400
  // corner values the fit would otherwise compute (the fit 0.03-0.05 s shorter).
  LatticeCache upper_values;
  // `key`: the corner's key at `depth` (lattice_key with (1 << depth) + 1 a side).
  double corner_value(const std::array<int64_t, 3>& corner, int depth, uint64_t key, const Eigen::Vector3d& q);
  // The key of lattice point i on a lattice of `side` points per axis.
  static uint64_t lattice_key(const std::array<int64_t, 3>& i, uint64_t side) {
    return uint64_t(i[0]) + side * (uint64_t(i[1]) + side * uint64_t(i[2]));
  }
  static constexpr uint64_t kHalfLattice = uint64_t(1) << 62;

 public:
  void make_search(double extent) {
    search_ = std::make_unique<BallSearch>(cloud.positions, std::max(min_radius, 1e-3 * extent));
  }
};

double Fitter::aux_value(const Eigen::Vector3d& q) {
  const BallSearch& search = *search_;
  uint32_t idx[6];
  double d2[6];
  nanoflann::KNNResultSet<double, uint32_t> rs(6);
  // The grid's six nearest, unless two of the seven nearest are equally far: then the
  // k-d tree's (which breaks such ties its own way, and has always decided them).
  thread_local BallSearch::Near near;
  thread_local std::vector<uint32_t> six;
  if (search.nearest_strict(q, 6, min_radius, near, six) || search.nearest_strict(q, 6, 1.5 * min_radius, near, six)) {
    rs.init(idx, d2);
    for (size_t j = 0; j < 6; ++j) rs.addPoint(near.points[j].first, six[j]);
  } else {
    rs.init(idx, d2);
    tree.findNeighbors(rs, q.data(), nanoflann::SearchParams());
  }
  int pos = 0, neg = 0;
  double sum = 0;
  for (size_t j = 0; j < rs.size(); ++j) {
    const double d = (q - cloud.positions[idx[j]]).dot(cloud.normals[idx[j]]);
    (d > 0 ? pos : neg)++;
    sum += d;
  }
  return rs.size() > 0 && (pos == 0 || neg == 0) ? sum / double(rs.size()) : NAN;
}

double Fitter::corner_value(const std::array<int64_t, 3>& corner, int depth, uint64_t key, const Eigen::Vector3d& q) {
  double v;
  if (depth > 0) {
    // As a half-cell lattice point of the level above: the same indices, the same keys.
    if (upper_values.find(key | kHalfLattice, v)) return v;
    if (corner[0] % 2 == 0 && corner[1] % 2 == 0 && corner[2] % 2 == 0) {
      const std::array<int64_t, 3> up = {corner[0] / 2, corner[1] / 2, corner[2] / 2};
      if (upper_values.find(lattice_key(up, (uint64_t(1) << (depth - 1)) + 1), v)) return v;
    }
  }
  return aux_value(q);
}

void Fitter::lattice_points(const Cell& c, std::vector<AuxPoint>& aux) {
  const uint64_t side = (uint64_t(2) << c.depth) + 1;  // half-cell lattice points per axis
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      for (int k = 0; k < 3; ++k) {
        const int odd = (a == 1) + (b == 1) + (k == 1);
        if (odd == 0 || odd == 3) continue;  // corners and the centre are there already
        const std::array<int64_t, 3> h = {2 * c.ijk[0] + a, 2 * c.ijk[1] + b, 2 * c.ijk[2] + k};
        const Eigen::Vector3d q =
            s.box_min + 0.5 * c.size * Eigen::Vector3d(double(h[0]), double(h[1]), double(h[2]));
        const double v = lattice_values.get(lattice_key(h, side) | kHalfLattice, [&] { return aux_value(q); });
        if (!std::isnan(v)) aux.push_back({q, v});
      }
}

std::vector<AuxPoint> Fitter::aux_points(const Cell& c, bool lattice) {
  std::vector<AuxPoint> aux;
  const uint64_t side = (uint64_t(1) << c.depth) + 1;  // corners per axis at this depth
  for (int k = 0; k < 9; ++k) {
    Eigen::Vector3d q = c.centre;
    double v;
    if (k < 8) {
      const std::array<int64_t, 3> corner = {c.ijk[0] + (k & 1), c.ijk[1] + ((k >> 1) & 1), c.ijk[2] + ((k >> 2) & 1)};
      q = s.box_min + c.size * Eigen::Vector3d(double(corner[0]), double(corner[1]), double(corner[2]));
      const uint64_t key = lattice_key(corner, side);
      v = lattice_values.get(key, [&] { return corner_value(corner, c.depth, key, q); });
    } else {
      v = aux_value(q);
    }
    if (!std::isnan(v)) aux.push_back({q, v});
  }
  if (lattice) lattice_points(c, aux);
  return aux;
}

Fitter::Support Fitter::support(const Cell& c) {
  const BallSearch& search = *search_;
  const double natural = opt.alpha * c.size * std::sqrt(3.0);
  Support sup{Ball{c.centre, std::max(natural, min_radius), {}}};
  Ball& ball = sup.ball;
  // A ball held at the smallest radius would stay that size in the children: splitting
  // cannot bring it closer to the data, and on a noisy or two-sheeted patch it would
  // go on to the depth cap (8^depth cells).
  sup.at_min_radius = natural < min_radius;
  search.ball(ball.centre, ball.radius * ball.radius, ball.ids);
  sup.initial = ball.ids.size();
  const size_t initial = sup.initial;
  if (int(initial) < opt.nmin) {
    // The ball grows by λ R until it holds nmin points: until R² exceeds the squared
    // distance of the nmin-th nearest point (the search counts d² < R²), one k-th
    // distance instead of a search per step. For the small balls of the deep levels it
    // comes from the grid, searched from where a surface through the ball would hold
    // nmin points (they grow as the radius squared); for the large balls of the coarse
    // ones from the k-d tree, where the grid would collect thousands of points to find
    // 30.
    thread_local BallSearch::Near near;
    near.points.clear();
    near.radius = 0;
    double need;
    if (ball.radius <= 2 * min_radius) {
      const double guess = std::sqrt(double(opt.nmin) / double(std::max<size_t>(initial, 1)));
      need = search.kth_distance2(ball.centre, size_t(opt.nmin), ball.radius * std::clamp(guess, 1.1, 2.0), near);
    } else {
      std::vector<uint32_t> idx(size_t(opt.nmin));
      std::vector<double> d2(size_t(opt.nmin));
      nanoflann::KNNResultSet<double, uint32_t> rs(size_t(opt.nmin));
      rs.init(idx.data(), d2.data());
      tree.findNeighbors(rs, ball.centre.data(), nanoflann::SearchParams());
      need = d2[rs.size() - 1];
    }
    for (int grow = 0; grow <= 200 && !(need < ball.radius * ball.radius); ++grow) ball.radius *= 1 + opt.lambda;
    sup.grown = true;
    ball.ids.clear();
    const double r2 = ball.radius * ball.radius;
    if (ball.radius <= near.radius) {
      for (const auto& [d2, id] : near.points)
        if (d2 < r2) ball.ids.push_back(id);
    } else {
      search.ball(ball.centre, r2, ball.ids);
    }
  }
  // The ids are in the ball search's grid order, the same for every query: the fit does
  // not depend on which search found them, nor on the threads. (Sorted by id instead,
  // they cost 5% of the fit, and most of the coarse levels' time.)
  return sup;
}

// The local fit of a ball (the kind chosen from its normals).
Fitter::Outcome Fitter::fit_ball(const Cell& c, const Ball& b, bool away) {
  Outcome o;
  // A cell whose ball had to grow from under a quarter of nmin points lies away from
  // the surface; a height field fitted to the nearest patch would be extrapolated
  // across the cell and cross zero there (spurious sheets). Its fit is the general
  // quadric held to the signed distances of auxiliary points (fit_away). (Cells that
  // grew from more points keep the height field: on slice stacks the general quadric
  // there tripled the curvature error.)
  std::vector<AuxPoint> aux;
  if (away && fit_away(c, b, aux, o)) return o;
  const Eigen::Vector3d nbar = mean_normal(b, cloud);
  bool within = nbar.norm() > 0;
  const Eigen::Vector3d n = within ? Eigen::Vector3d(nbar.normalized()) : Eigen::Vector3d::UnitZ();
  for (uint32_t id : b.ids) within = within && cloud.normals[id].dot(n) > 0;
  if (within) {
    o.leaf = opt.local_fit == LocalFit::kOrthopoly
                 ? fit_height_orthopoly(b, cloud, n, opt.max_degree, slope_length, &o.error)
                 : fit_height_quadric(b, cloud, n, &o.error);
  } else {
    // Normals that spread past 90°: both faces of a plate or gap thinner than the ball
    // when they split into two sheets, taken when within eps; else the better of the
    // two sheets and the general quadric. The sheets reach across the ball, also where
    // the plate ends inside it: they must agree with the auxiliary points' signs on the
    // cell's half-cell lattice (inside or outside by more than eps), or they would carry
    // the plate on past its rim.
    double sheets_error;
    const Leaf sheets = fit_two_sheets(b, cloud, &sheets_error);
    if (std::isfinite(sheets_error) && !agrees_with(sheets, aux_points(c, true))) sheets_error = INFINITY;
    if (sheets_error <= eps) {
      o.leaf = sheets;
      o.error = sheets_error;
      return o;
    }
    if (aux.empty()) aux = aux_points(c, false);
    o.leaf = fit_general_quadric(b, cloud, aux, &o.error);
    if (sheets_error < o.error) {
      o.leaf = sheets;
      o.error = sheets_error;
    }
  }
  return o;
}

bool Fitter::fit_away(const Cell& c, const Ball& b, std::vector<AuxPoint>& aux, Outcome& o) {
  aux = aux_points(c, false);
  if (aux.size() >= 5) {
    o.leaf = fit_general_quadric(b, cloud, aux, &o.error);
    if (one_side_on_lattice(o.leaf, aux, c)) return true;
  }
  lattice_points(c, aux);
  if (aux.size() < 5) return false;
  o.leaf = fit_general_quadric(b, cloud, aux, &o.error);
  return true;
}

bool Fitter::one_side_on_lattice(const Leaf& leaf, const std::vector<AuxPoint>& aux, const Cell& c) const {
  if (aux.size() < 9) return false;  // a corner whose six nearest disagree in sign
  const bool outside = aux[0].distance > 0;
  for (const AuxPoint& p : aux)
    if ((p.distance > 0) != outside) return false;
  for (int a = -1; a <= 1; ++a)
    for (int b = -1; b <= 1; ++b)
      for (int k = -1; k <= 1; ++k) {
        const Eigen::Vector3d q = c.centre + 0.5 * c.size * Eigen::Vector3d(a, b, k);
        const Eigen::Vector3d y = leaf.frame * (q - leaf.centre) / leaf.radius;
        double v, g[3], h[6];
        local_poly(leaf.coeffs.data(), y.x(), y.y(), y.z(), v, g, h);
        if ((v > 0) != outside) return false;
      }
  return true;
}

bool Fitter::agrees_with(const Leaf& leaf, const std::vector<AuxPoint>& aux) const {
  for (const AuxPoint& p : aux) {
    if (!(std::abs(p.distance) > eps)) continue;
    const Eigen::Vector3d y = leaf.frame * (p.position - leaf.centre) / leaf.radius;
    double q, g[3], h[6];
    local_poly(leaf.coeffs.data(), y.x(), y.y(), y.z(), q, g, h);
    if ((q > 0) != (p.distance > 0)) return false;
  }
  return true;
}

void Fitter::plane_fallback(const Ball& ball, Outcome& o) {
  const Eigen::Vector3d nbar = mean_normal(ball, cloud);
  const Eigen::Vector3d n = nbar.norm() > 0 ? Eigen::Vector3d(nbar.normalized()) : Eigen::Vector3d::UnitZ();
  Leaf plane = o.leaf;
  plane.kind = FitKind::kHeightOrthopoly;
  plane.degree = 1;
  plane.frame = frame_from_normal(n);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (uint32_t id : ball.ids) mean += cloud.positions[id];
  mean /= double(std::max<size_t>(ball.ids.size(), 1));
  plane.coeffs = {};
  plane.coeffs[15] = 1;
  plane.coeffs[0] = -n.dot(mean - ball.centre) / ball.radius;
  o.leaf = plane;
  o.error = taubin_error(plane, ball, cloud);
}

Fitter::Outcome Fitter::process(const Cell& c) {
  const Support sup = support(c);
  const Ball& ball = sup.ball;
  const bool grown = sup.grown, at_min_radius = sup.at_min_radius;
  const bool away = grown && 4 * sup.initial < size_t(opt.nmin);
  // A ball of over a thousand points (the coarse levels: the root's holds them all) is
  // first fitted to an even subsample of 512 of them; when that fit is already off by
  // more than eps at one of its points, the cell splits without the full fit, which is
  // slow in the coarsest levels (few cells, so on few threads). A subsample of 512
  // decides as a larger one does on the sample CT; a much smaller one splits cells whose
  // full fit is within eps.
  constexpr size_t kProbePoints = 512;
  const bool may_split = c.depth < opt.max_depth && !grown && !at_min_radius;
  if (may_split && ball.ids.size() > 2 * kProbePoints) {
    Ball probe{ball.centre, ball.radius, {}};
    const size_t stride = ball.ids.size() / kProbePoints;
    for (size_t i = 0; i < ball.ids.size(); i += stride) probe.ids.push_back(ball.ids[i]);
    Outcome p = fit_ball(c, probe, away);
    if (p.error > split_bound(c)) {
      p.split = true;
      return p;
    }
  }
  Outcome o = fit_ball(c, ball, away);
  o.leaf.depth = uint8_t(c.depth);
  // A cell whose ball had to grow holds too few points of its own: its children would
  // grow to the same points, so it is not split (Ohtake et al.).
  o.split = may_split && o.error > split_bound(c);
  o.kept_by_held_bound = may_split && o.error > eps && !o.split;
  if (!o.split && !std::isfinite(o.error)) plane_fallback(ball, o);
  return o;
}

void Fitter::fit_levels(FitStats& st, LapTimer& timer) {
  std::vector<Cell> level = {make_cell(0, {0, 0, 0})};
  // Each level's outcomes are built in place by the task that fits the cell, which so
  // first touches their pages (18 MB at the sample CT's deepest level; the kernel zeroes
  // each on first touch): value-initialised beforehand, they would all be touched on one
  // core.
  static_assert(std::is_trivially_destructible_v<Outcome>);
  struct Release {
    void operator()(Outcome* p) const { ::operator delete(p, std::align_val_t(alignof(Outcome))); }
  };
  while (!level.empty()) {
    const std::unique_ptr<Outcome[], Release> out(static_cast<Outcome*>(
        ::operator new(level.size() * sizeof(Outcome), std::align_val_t(alignof(Outcome)))));
    // About four keys a cell: corners are shared, and most cells ask for no half points.
    std::swap(upper_values, lattice_values);
    lattice_values.reset(4 * level.size());
    tbb::parallel_for(size_t(0), level.size(), [&](size_t i) { new (&out[i]) Outcome(process(level[i])); });
    std::vector<Cell> next;
    std::vector<size_t> kept;  // this level's leaves, in cell order
    for (size_t i = 0; i < level.size(); ++i) {
      const Cell& c = level[i];
      if (out[i].split) {
        for (int k = 0; k < 8; ++k)
          next.push_back(make_cell(
              c.depth + 1, {2 * c.ijk[0] + (k & 1), 2 * c.ijk[1] + ((k >> 1) & 1), 2 * c.ijk[2] + ((k >> 2) & 1)}));
        continue;
      }
      st.over_eps += out[i].error > eps;
      st.kept_below_held_bound += out[i].kept_by_held_bound;
      st.max_depth_reached = std::max(st.max_depth_reached, c.depth);
      kept.push_back(i);
    }
    // One allocation and a parallel copy: the deepest level holds most of the leaves
    // (280 B each).
    const size_t first = s.leaves.size();
    s.leaves.resize(first + kept.size());
    tbb::parallel_for(size_t(0), kept.size(), [&](size_t k) { s.leaves[first + k] = out[kept[k]].leaf; });
    level = std::move(next);
    st.seconds_by_depth.push_back(timer.lap());
  }
}

// The points' bounding box, and the octree's box around it with the margin.
void place_box(const PointCloud& cloud, const FitOptions& opt, MpuSurface& s) {
  Eigen::Vector3d lo = cloud.positions[0], hi = lo;
  for (const auto& p : cloud.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double extent = std::max((hi - lo).maxCoeff(), 1e-6);
  s.box_size = extent * (1 + 2 * opt.margin);
  s.box_min = 0.5 * (lo + hi) - Eigen::Vector3d::Constant(0.5 * s.box_size);
  s.data_min = lo;
  s.data_max = hi;
}

// The leaves by kind (and the orthopoly ones by degree).
void count_kinds(const MpuSurface& s, FitStats& st) {
  for (const Leaf& l : s.leaves) {
    if (l.kind == FitKind::kHeightOrthopoly) {
      ++st.height_orthopoly;
      ++st.degree_counts[std::min<size_t>(l.degree, 4)];
    }
    st.height_quadric += l.kind == FitKind::kHeightQuadric;
    st.general_quadric += l.kind == FitKind::kGeneralQuadric;
    st.two_sheets += l.kind == FitKind::kTwoSheets;
  }
  st.leaves = int64_t(s.leaves.size());
}

}  // namespace

MpuSurface fit_mpu(const PointCloud& input, const FitOptions& opt, FitStats* stats, const KdTree* index) {
  validate(opt);
  const auto t0 = std::chrono::steady_clock::now();
  int64_t duplicates = 0;
  const PointCloud cloud = without_duplicates(input, &duplicates);
  if (cloud.size() < size_t(opt.nmin))
    throw InputError("fit: " + std::to_string(cloud.size()) + " distinct points, fewer than " + option_ref("nmin") + " " +
                     std::to_string(opt.nmin));
  check_not_flat(cloud);
  MpuSurface s;
  // Without duplicates the distinct points are the input's, in its order: its tree
  // serves.
  Fitter fitter(cloud, opt, s, duplicates == 0 ? index : nullptr);
  place_box(cloud, opt, s);
  fitter.make_search(std::max((s.data_max - s.data_min).maxCoeff(), 1e-6));
  FitStats st;
  st.eps = fitter.eps;
  st.min_radius = fitter.min_radius;
  st.gap12 = fitter.gap12;
  LapTimer timer(t0);
  st.seconds_setup = timer.lap();
  fitter.fit_levels(st, timer);
  count_kinds(s, st);

  uint32_t cells = uint32_t(opt.grid_cells);
  if (cells == 0) {
    std::vector<double> r;
    for (const Leaf& l : s.leaves) r.push_back(l.radius);
    std::nth_element(r.begin(), r.begin() + ptrdiff_t(r.size() / 2), r.end());
    cells = uint32_t(std::clamp(std::ceil(s.box_size / r[r.size() / 2]), 4.0, 256.0));
  }
  timer.lap();
  build_lookup_grid(s, cells);
  st.seconds_grid = timer.lap();
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  st.duplicates_removed = duplicates;
  if (stats) *stats = st;
  return s;
}

}  // namespace mpumesh::mpu
