#include "points/slice_points.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

#include "common/neighbour_grid.h"
#include "points/contours.h"
#include "segment/distance_transform.h"

namespace mpumesh::pts {
namespace {

// The partial volume moves a cap point from the contours' ruled surface by less than this
// (slices); a larger shift says the column is not one surface crossing between two whole
// slabs (a plate, a ridge, a level that varies), and the ruled height stays.
constexpr double kMaxPartialVolumeShift = 0.5;
// Levels that differ by less than this fraction of the contrast are one level.
constexpr double kLevelSlack = 0.1;
// The inside and outside levels are the means over a box of 2 kLevelBox + 1 pixels a side
// in the slabs behind and beyond (the two slabs the surface crosses, over 3 x 3): the
// levels' noise enters a cap's height twice over (g_out twice), and the larger boxes
// average it down (on the torus phantom, 60 HU noise, the fit's normals at the mesh's
// vertices are 1.12° off on average with 7 x 7 boxes, 1.26° with 3 x 3).
constexpr int64_t kLevelBox = 3;

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Points in the volume's scaled index frame (index * spacing): physical = origin + D * p.
struct Part {
  std::vector<Eigen::Vector3d> pos, ref;
  std::vector<uint8_t> cap;
  std::vector<int32_t> slice;
  int64_t contours = 0;
  void add(const Eigen::Vector3d& p, const Eigen::Vector3d& r, bool is_cap, int32_t k) {
    pos.push_back(p);
    ref.push_back(r);
    cap.push_back(is_cap);
    slice.push_back(k);
  }
};

// The padded segmentation field of a volume, slice by slice, in the volume's scaled index
// frame (index * spacing): physical = origin + D * p.
struct SliceStack {
  const float* field;
  int64_t px, py, n, nz;  // padded pixels per row and column, per slice; unpadded slices
  double sx, sy, sz;
  SliceStack(const seg::Segmentation& s, const Volume& geometry)
      : field(s.field.values.data()),
        px(s.field.dims[0]),
        py(s.field.dims[1]),
        n(px * py),
        nz(s.field.dims[2] - 2),
        sx(geometry.spacing.x()),
        sy(geometry.spacing.y()),
        sz(geometry.spacing.z()) {}
  double inside(int64_t pk, int64_t i, int64_t j) const { return field[i + px * (j + py * pk)] >= 0.0f ? 1.0 : 0.0; }
  // The inside indicator of padded slice pk, bilinear at padded pixel coordinates (x, y).
  double indicator(int64_t pk, double x, double y) const {
    const int64_t i = std::clamp<int64_t>(int64_t(std::floor(x)), 0, px - 2);
    const int64_t j = std::clamp<int64_t>(int64_t(std::floor(y)), 0, py - 2);
    const double fx = std::clamp(x - double(i), 0.0, 1.0), fy = std::clamp(y - double(j), 0.0, 1.0);
    return (1 - fy) * ((1 - fx) * inside(pk, i, j) + fx * inside(pk, i + 1, j)) +
           fy * ((1 - fx) * inside(pk, i, j + 1) + fx * inside(pk, i + 1, j + 1));
  }
  Eigen::Vector3d scaled(double x, double y, double k) const {
    return Eigen::Vector3d((x - 1) * sx, (y - 1) * sy, k * sz);
  }
};

// The vertices of every slice's contours, one part per slice, with their orientation
// references: the contour's in-plane outward direction plus ±z where the adjacent slices
// say the surface faces up or down.
std::vector<Part> contour_points(const SliceStack& g) {
  const int64_t px = g.px, py = g.py, n = g.n, nz = g.nz;
  const double sx = g.sx, sy = g.sy;
  const float* field = g.field;
  std::vector<Part> parts(static_cast<size_t>(nz));
  tbb::parallel_for(int64_t(0), nz, [&](int64_t k) {
    Part& part = parts[size_t(k)];
    const int64_t pk = k + 1;
    for (const Contour& c : marching_squares(field + n * pk, px, py)) {
      ++part.contours;
      const size_t m = c.points.size();
      for (size_t v = 0; v < m; ++v) {
        const auto& p = c.points[v];
        const auto& prev = c.points[(v + m - 1) % m];
        const auto& next = c.points[(v + 1) % m];
        const Eigen::Vector2d t((next.x() - prev.x()) * sx, (next.y() - prev.y()) * sy);
        Eigen::Vector2d outward(t.y(), -t.x());  // the inside is on the left
        if (outward.norm() > 0) outward.normalize();
        const double up = g.indicator(pk - 1, p.x(), p.y()) - g.indicator(pk + 1, p.x(), p.y());
        part.add(g.scaled(p.x(), p.y(), double(k)), Eigen::Vector3d(outward.x(), outward.y(), up), false, int32_t(k));
      }
    }
  });
  return parts;
}

// One slice's mask and, computed when first needed, the squared distances to its region
// and to its outside. Consecutive pairs share a slice, so each range of pairs walks up the
// stack and computes every transform once.
struct SliceMaps {
  int64_t pk = -1;
  std::vector<uint8_t> mask;
  std::vector<float> to_region, to_outside;
  bool has_region = false, has_outside = false;
};

// The cap points between padded slices pk and pk + 1 (part pk, k = pk - 1): see the header.
class CapBuilder {
 public:
  CapBuilder(const SliceStack& g, const PointOptions& opt)
      : g_(g), opt_(opt), min_sq_(g.sz * g.sz), half_pixel_(0.5 * std::min(g.sx, g.sy)) {
    // Pixel offsets closer than a slice spacing.
    const int64_t rx = int64_t(std::ceil(g.sz / g.sx)), ry = int64_t(std::ceil(g.sz / g.sy));
    for (int64_t dj = -ry; dj <= ry; ++dj)
      for (int64_t di = -rx; di <= rx; ++di)
        if (std::pow(double(di) * g.sx, 2) + std::pow(double(dj) * g.sy, 2) < min_sq_) disk_.emplace_back(di, dj);
  }

  std::vector<Part> build() const {
    std::vector<Part> caps(size_t(g_.nz + 1));
    if (!opt_.caps) return caps;
    tbb::parallel_for(tbb::blocked_range<int64_t>(0, g_.nz + 1, 8), [&](const tbb::blocked_range<int64_t>& r) {
      SliceMaps lo, hi;
      load(lo, r.begin());
      for (int64_t pk = r.begin(); pk != r.end(); ++pk) {
        load(hi, pk + 1);
        add_caps(lo, hi, 1.0, caps[size_t(pk)], int32_t(pk - 1));   // the region ends going up: faces +z
        add_caps(hi, lo, -1.0, caps[size_t(pk)], int32_t(pk - 1));  // the region starts going up: faces -z
        std::swap(lo, hi);
      }
    });
    return caps;
  }

 private:
  void load(SliceMaps& m, int64_t pk) const {
    m.pk = pk;
    m.mask.resize(size_t(g_.n));
    for (int64_t p = 0; p < g_.n; ++p) m.mask[size_t(p)] = g_.field[p + g_.n * pk] >= 0.0f;
    m.has_region = m.has_outside = false;
  }
  const std::vector<float>& region_d2(SliceMaps& m) const {
    if (!m.has_region) seg::squared_distance_2d(m.mask.data(), g_.px, g_.py, 1, g_.sx, g_.sy, m.to_region);
    m.has_region = true;
    return m.to_region;
  }
  const std::vector<float>& outside_d2(SliceMaps& m) const {
    if (!m.has_outside) seg::squared_distance_2d(m.mask.data(), g_.px, g_.py, 0, g_.sx, g_.sy, m.to_outside);
    m.has_outside = true;
    return m.to_outside;
  }
  // The in-plane pixel indices (a + px b) of the 3 x 3 box at (i, j), cut at the border.
  std::pair<std::array<int64_t, 9>, size_t> box(int64_t i, int64_t j) const {
    std::array<int64_t, 9> ids{};
    size_t n_ids = 0;
    for (int64_t b = std::max<int64_t>(j - 1, 0); b <= std::min(j + 1, g_.py - 1); ++b)
      for (int64_t a = std::max<int64_t>(i - 1, 0); a <= std::min(i + 1, g_.px - 1); ++a) ids[n_ids++] = a + g_.px * b;
    return {ids, n_ids};
  }
  // The field's 3 x 3 in-plane mean at padded slice pk (the field is the intensity
  // relative to the threshold; the mean cuts the noise by three).
  double box_mean(int64_t pk, int64_t i, int64_t j) const {
    const auto [ids, n_ids] = box(i, j);
    double sum = 0;
    for (size_t k = 0; k < n_ids; ++k) sum += g_.field[ids[k] + g_.n * pk];
    return sum / double(n_ids);
  }
  bool real_slice(int64_t pk) const { return pk >= 1 && pk <= g_.nz; }
  // A level's mean over the (2 kLevelBox + 1)² box at (i, j), cut at the border.
  double level_mean(int64_t pk, int64_t i, int64_t j) const {
    double sum = 0;
    int count = 0;
    for (int64_t b = std::max<int64_t>(j - kLevelBox, 0); b <= std::min(j + kLevelBox, g_.py - 1); ++b)
      for (int64_t a = std::max<int64_t>(i - kLevelBox, 0); a <= std::min(i + kLevelBox, g_.px - 1); ++a, ++count)
        sum += g_.field[a + g_.px * b + g_.n * pk];
    return sum / double(count);
  }
  double partial_volume_rise(const SliceMaps& from, const SliceMaps& to, int64_t i, int64_t j) const;
  // Pixel p's signed in-plane distance to slice m's contour (mm; positive inside), or NaN
  // when the slice holds no region.
  double signed_distance(SliceMaps& m, int64_t p) const {
    if (m.mask[size_t(p)]) return std::sqrt(double(outside_d2(m)[size_t(p)])) - half_pixel_;
    const double d = double(region_d2(m)[size_t(p)]);
    return std::isinf(d) ? std::nan("") : -(std::sqrt(d) - half_pixel_);
  }
  // A dome's top between two slices, from its slice's contour at in-plane distance d: up at
  // 45 degrees to the mid-plane (slices).
  double dome_rise(double d) const { return 0.5 * std::min(1.0, d / g_.sz); }
  double curved_rise(SliceMaps& behind, SliceMaps* behind2, int64_t p, double d_from, double d_to) const;
  std::vector<uint8_t> closing_holes(const SliceMaps& from, const SliceMaps& to) const;
  double bowl_rise(SliceMaps* beyond, SliceMaps* beyond2, int64_t p, double d_to) const;
  bool any_cap(const SliceMaps& from, const SliceMaps& to) const;
  void add_caps(SliceMaps& from, SliceMaps& to, double dir, Part& part, int32_t k) const;

  const SliceStack& g_;
  const PointOptions& opt_;
  const double min_sq_, half_pixel_;
  std::vector<std::pair<int64_t, int64_t>> disk_;
};

// The height from the partial volume, in slices from `from`'s plane toward `to`'s: the
// slab of `from` spans [-1/2, 1/2] and `to`'s [1/2, 3/2]; the column is inside from below
// -1/2 up to the surface, so the grey of the two slabs says how far: the inside
// fractions' sum is (g_from + g_to - 2 g_out) / (g_in - g_out). The levels are local: g_in
// from the slice behind `from`, g_out from the one beyond `to`. Exact for a plane over the
// pixel when the slices are as thick as their spacing; the ruled surface between the
// contours lies inside every convex dome by its sagitta (0.3-1 mm on a 12 mm cap in
// 2.5 mm slices). -1 (not known, the ruled height stays) unless the column is what that
// reading assumes: the pixel and its neighbours inside `from` and outside `to`; one level
// for two slabs behind `from` and one beyond `to` (not a plate or gap thinner than that,
// nor bright cortex over dim marrow); the two slabs between those levels; and not both
// whole (a mask has no partial volume).
double CapBuilder::partial_volume_rise(const SliceMaps& from, const SliceMaps& to, int64_t i, int64_t j) const {
  const int64_t step = to.pk - from.pk, behind = from.pk - step, beyond = to.pk + step;
  if (!real_slice(behind) || !real_slice(behind - step) || !real_slice(beyond)) return -1.0;
  const auto [ids, n_ids] = box(i, j);
  for (size_t k = 0; k < n_ids; ++k)
    if (!from.mask[size_t(ids[k])] || to.mask[size_t(ids[k])]) return -1.0;
  const double g_from = box_mean(from.pk, i, j), g_to = box_mean(to.pk, i, j);
  const double g_in = level_mean(behind, i, j), g_out = level_mean(beyond, i, j);
  const double contrast = g_in - g_out, slack = kLevelSlack * contrast;
  if (!(g_in > 0 && g_out < 0)) return -1.0;
  // One level behind (two slabs alike), one beyond, and the two slabs between them.
  if (std::abs(box_mean(behind - step, i, j) - g_in) > slack) return -1.0;
  if (real_slice(beyond + step) && std::abs(box_mean(beyond + step, i, j) - g_out) > slack) return -1.0;
  if (g_from > g_in + slack || g_to < g_out - slack) return -1.0;
  // Both slabs whole (a mask, or a surface on the slabs' boundary): the grey adds nothing.
  if (g_from > g_in - kLevelSlack * slack && g_to < g_out + kLevelSlack * slack) return -1.0;
  return std::clamp((g_from + g_to - 2 * g_out) / contrast - 0.5, 0.0, 1.0);
}

// The zero between 0 and 1 of the parabola through (t, d) for t = t0, t0 + 1, t0 + 2, the
// one nearest `guess`; `guess` when there is none.
double parabola_zero(double t0, const std::array<double, 3>& d, double guess) {
  // d(t) = d1 + b (t - t1) + a (t - t1)², t1 = t0 + 1.
  const double t1 = t0 + 1, b = 0.5 * (d[2] - d[0]), a = 0.5 * (d[2] + d[0]) - d[1];
  if (!std::isfinite(a) || !std::isfinite(b)) return guess;
  double best = guess, best_gap = INFINITY;
  auto consider = [&](double u) {
    const double t = t1 + u;
    if (t >= 0 && t <= 1 && std::abs(t - guess) < best_gap) best = t, best_gap = std::abs(t - guess);
  };
  if (std::abs(a) < 1e-9 * (std::abs(b) + 1e-12)) {
    if (b != 0) consider(-d[1] / b);
    return best;
  }
  const double disc = b * b - 4 * a * d[1];
  if (disc < 0) return guess;
  consider((-b + std::sqrt(disc)) / (2 * a));
  consider((-b - std::sqrt(disc)) / (2 * a));
  return best;
}

// Label maps: the height where the in-plane signed distance to the slices' contours,
// as a parabola in z through the slice behind `from`, `from` and `to`, crosses zero (the
// ruled surface is that distance linear in z, a chord inside every convex dome); where
// `to` holds no region (a dome top), the parabola through the two slices behind and
// `from`, extrapolated.
double CapBuilder::curved_rise(SliceMaps& behind, SliceMaps* behind2, int64_t p, double d_from, double d_to) const {
  const double db = signed_distance(behind, p);
  if (std::isfinite(d_to)) {
    const double linear = d_from / (d_from + d_to);
    if (std::isnan(db)) return linear;
    return parabola_zero(-1, {db, d_from, -d_to}, linear);
  }
  const double dome = dome_rise(d_from);
  if (!behind2 || std::isnan(db)) return dome;
  const double db2 = signed_distance(*behind2, p);
  if (std::isnan(db2)) return dome;
  return parabola_zero(-2, {db2, db, d_from}, dome);
}

// The pixels of `to`'s outside whose piece of it (8-connected, as an outside is where the
// inside is 4-connected) meets no outside of `from`: a hole of the region that closes
// between the two slices, the bottom of a bowl. There `from`'s nearest contour is another
// surface (the bowl's outer wall), and the height is the hole's, as a dome's is.
std::vector<uint8_t> CapBuilder::closing_holes(const SliceMaps& from, const SliceMaps& to) const {
  std::vector<uint8_t> seen(size_t(g_.n), 0), out(size_t(g_.n), 0);
  std::vector<int64_t> stack, members;
  for (int64_t start = 0; start < g_.n; ++start) {
    if (to.mask[size_t(start)] || seen[size_t(start)]) continue;
    bool opens = false;
    members.clear();
    stack.assign(1, start);
    seen[size_t(start)] = 1;
    while (!stack.empty()) {
      const int64_t p = stack.back();
      stack.pop_back();
      members.push_back(p);
      opens = opens || !from.mask[size_t(p)];
      const int64_t i = p % g_.px, j = p / g_.px;
      for (int64_t b = std::max<int64_t>(j - 1, 0); b <= std::min(j + 1, g_.py - 1); ++b)
        for (int64_t a = std::max<int64_t>(i - 1, 0); a <= std::min(i + 1, g_.px - 1); ++a) {
          const int64_t q = a + g_.px * b;
          if (to.mask[size_t(q)] || seen[size_t(q)]) continue;
          seen[size_t(q)] = 1;
          stack.push_back(q);
        }
    }
    if (!opens)
      for (const int64_t p : members) out[size_t(p)] = 1;
  }
  return out;
}

// The bottom of a bowl (closing_holes), in slices from `from` toward `to`: the hole's
// in-plane signed distance as a parabola in z through the two slices beyond `to` and `to`,
// extrapolated to its zero toward `from`; else from `to` down at 45 degrees to the
// mid-plane, as a dome top rises.
double CapBuilder::bowl_rise(SliceMaps* beyond, SliceMaps* beyond2, int64_t p, double d_to) const {
  const double bowl = dome_rise(d_to);
  double down = bowl;
  if (beyond && beyond2) {
    const double hb = -signed_distance(*beyond, p), hb2 = -signed_distance(*beyond2, p);
    if (std::isfinite(hb) && std::isfinite(hb2)) down = parabola_zero(-2, {hb2, hb, d_to}, bowl);
  }
  return 1.0 - down;
}

// Whether any pixel inside `from` and outside `to` lies a slice spacing or more from
// `to`'s region (a disk test on the few changed pixels, before any distance transform).
bool CapBuilder::any_cap(const SliceMaps& from, const SliceMaps& to) const {
  for (int64_t j = 0; j < g_.py; ++j)
    for (int64_t i = 0; i < g_.px; ++i) {
      const int64_t p = i + g_.px * j;
      if (!from.mask[size_t(p)] || to.mask[size_t(p)]) continue;
      bool near = false;
      for (const auto& [di, dj] : disk_) {
        const int64_t a = i + di, b = j + dj;
        if (a >= 0 && b >= 0 && a < g_.px && b < g_.py && to.mask[size_t(a + g_.px * b)]) {
          near = true;
          break;
        }
      }
      if (!near) return true;
    }
  return false;
}

// Inside `from`, outside `to`, and at least a slice spacing from `to`'s region. The height
// from the partial volume where the levels are known; else rising from `from`'s contour
// toward `to`'s: in proportion to the distances to the two contours where `to` has a
// region, else at 45 degrees up to the mid-plane (a dome top between slices).
void CapBuilder::add_caps(SliceMaps& from, SliceMaps& to, double dir, Part& part, int32_t k) const {
  if (!any_cap(from, to)) return;
  const auto& d_region = region_d2(to);
  const auto& d_edge = outside_d2(from);
  const double z_from = double(from.pk - 1);
  // The slices behind `from` (away from `to`), for curved caps.
  const int64_t step = to.pk - from.pk;
  SliceMaps behind, behind2;
  const bool curved = opt_.curved_caps && from.pk - step >= 0 && from.pk - step <= g_.nz + 1;
  const bool curved2 = curved && from.pk - 2 * step >= 0 && from.pk - 2 * step <= g_.nz + 1;
  if (curved) load(behind, from.pk - step);
  if (curved2) load(behind2, from.pk - 2 * step);
  // A bowl's bottom (curved caps only): the slices beyond `to`, for its hole's height.
  std::vector<uint8_t> bowl;
  SliceMaps beyond, beyond2;
  const bool bowls = curved && to.pk + 2 * step >= 0 && to.pk + 2 * step <= g_.nz + 1;
  if (curved) {
    bowl = closing_holes(from, to);
    if (bowls && std::find(bowl.begin(), bowl.end(), uint8_t(1)) != bowl.end()) {
      load(beyond, to.pk + step);
      load(beyond2, to.pk + 2 * step);
    }
  }
  for (int64_t j = 0; j < g_.py; ++j)
    for (int64_t i = 0; i < g_.px; ++i) {
      const int64_t p = i + g_.px * j;
      if (!from.mask[size_t(p)] || d_region[size_t(p)] < min_sq_) continue;
      const double d_from = std::max(std::sqrt(double(d_edge[size_t(p)])) - half_pixel_, 0.0);
      const double d_to = std::sqrt(double(d_region[size_t(p)])) - half_pixel_;
      double rise = 0;
      if (curved && bowl[size_t(p)] && std::isfinite(d_to))
        rise = bowl_rise(beyond.pk >= 0 ? &beyond : nullptr, beyond2.pk >= 0 ? &beyond2 : nullptr, p, d_to);
      else if (curved)
        rise = curved_rise(behind, curved2 ? &behind2 : nullptr, p, d_from, d_to);
      else
        rise = std::isinf(d_to) ? dome_rise(d_from) : d_from / (d_from + d_to);
      const double pv = opt_.partial_volume_caps ? partial_volume_rise(from, to, i, j) : -1.0;
      if (pv >= 0 && std::abs(pv - rise) < kMaxPartialVolumeShift) rise = pv;
      if (opt_.caps_to_field_crossing) {
        const double f_from = g_.field[p + g_.n * from.pk], f_to = g_.field[p + g_.n * to.pk];
        if (f_from > 0 && f_to < -f_from) rise = std::min(rise, f_from / (f_from - f_to));
      }
      part.add(g_.scaled(double(i), double(j), z_from + dir * rise), Eigen::Vector3d(0, 0, dir), true, k);
    }
}

std::vector<Part> cap_points(const SliceStack& g, const PointOptions& opt) { return CapBuilder(g, opt).build(); }

// PCA normals, oriented by the reference, within `radius`; degenerate ones flagged.
std::vector<Eigen::Vector3d> pca_normals(const std::vector<Eigen::Vector3d>& pos,
                                         const std::vector<Eigen::Vector3d>& ref, double radius,
                                         const PointOptions& opt, std::vector<uint8_t>& degenerate) {
  std::vector<Eigen::Vector3d> normals(pos.size());
  degenerate.assign(pos.size(), 0);
  if (pos.empty()) return normals;
  const NeighbourGrid grid(pos, radius);
  const auto& order = grid.order();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pos.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    std::vector<uint32_t> found;
    for (size_t o = r.begin(); o != r.end(); ++o) {
      const size_t i = order[o];
      found.clear();
      // Neighbours whose orientation reference agrees: not the far face of a thin wall.
      grid.for_each_within(pos[i], [&](uint32_t j) {
        if (ref[j].dot(ref[i]) > 0) found.push_back(j);
      });
      Eigen::Vector3d normal = ref[i].normalized();
      bool degen = true;
      if (int(found.size()) >= opt.min_neighbours) {
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        for (uint32_t j : found) mean += pos[j];
        mean /= double(found.size());
        Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
        for (uint32_t j : found) {
          const Eigen::Vector3d d = pos[j] - mean;
          cov += d * d.transpose();
        }
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
        es.computeDirect(cov);
        const Eigen::Vector3d ev = es.eigenvalues();  // ascending
        if (ev[1] >= opt.collinear_ratio * ev[2]) {
          normal = es.eigenvectors().col(0).normalized();
          if (normal.dot(ref[i]) < 0) normal = -normal;
          degen = false;
        }
      }
      normals[i] = normal;
      degenerate[i] = degen;
    }
  });
  return normals;
}

}  // namespace

SlicePoints extract_points(const seg::Segmentation& s, const Volume& geometry, const PointOptions& opt) {
  const SliceStack g(s, geometry);
  SlicePoints out;
  auto t0 = Clock::now();
  const std::vector<Part> parts = contour_points(g);
  out.stats.contour_seconds = seconds_since(t0);

  t0 = Clock::now();
  const std::vector<Part> caps = cap_points(g, opt);
  std::vector<Eigen::Vector3d> pos, ref;
  for (const std::vector<Part>* list : {&parts, &caps})
    for (const Part& p : *list) {
      pos.insert(pos.end(), p.pos.begin(), p.pos.end());
      ref.insert(ref.end(), p.ref.begin(), p.ref.end());
      out.is_cap.insert(out.is_cap.end(), p.cap.begin(), p.cap.end());
      out.slice.insert(out.slice.end(), p.slice.begin(), p.slice.end());
      out.stats.contours += p.contours;
      (p.cap.empty() || !p.cap[0] ? out.stats.contour_points : out.stats.cap_points) += int64_t(p.pos.size());
    }
  out.stats.cap_seconds = seconds_since(t0);

  t0 = Clock::now();
  const double radius = std::max(opt.radius_slices * g.sz, opt.radius_pixels * std::max(g.sx, g.sy));
  out.stats.pca_radius_mm = radius;
  std::vector<uint8_t> degenerate;
  const std::vector<Eigen::Vector3d> normals = pca_normals(pos, ref, radius, opt, degenerate);
  out.stats.degenerate_normals = std::count(degenerate.begin(), degenerate.end(), uint8_t(1));
  out.stats.normal_seconds = seconds_since(t0);

  out.cloud.positions.resize(pos.size());
  out.cloud.normals.resize(pos.size());
  for (size_t i = 0; i < pos.size(); ++i) {
    out.cloud.positions[i] = geometry.origin + geometry.direction * pos[i];
    out.cloud.normals[i] = (geometry.direction * normals[i]).normalized();
  }
  return out;
}

}  // namespace mpumesh::pts
