// The multi-material implicit model (docs/method.md "Several labels"): one fitted MPU
// function per label, and a labelling of space from them. Region 0 is the background and
// regions 1..n the labels, each with a function f_r (negative inside, about the signed
// distance in mm). The labelling is
//     region(p) = argmin_r h_r(p),   r = 0..n,
// the most inside; where two regions touch, their common boundary is the one surface
// h_a = h_b, with no gap and no overlap by construction, and three regions meet along
// the curves h_a = h_b = h_c.
// A label map whose labels touch: U, the union of the labels, is fitted as one more
// label, and it alone bounds the background; the labels compare inside it:
//     h_0 = -f_U / 2,   h_r = f_r(q) - f_m(q) + f_U / 2,
// m the most inside label at q. The most inside label holds f_U / 2, so the background's
// interfaces are U's zero set, smooth across the rims where the labels' shared faces meet
// the outside (each label's own fit rounds them, and two rounded fits leave a notch there
// that the background would fill); two labels meet where f_a(q) = f_b(q). q is p itself
// except in those notches: where p lies within `depth` of the outside (f_U > -depth)
// and outside every label's own fit (o > 0, o the labels' soft minimum at p:
// -eps log sum_r exp(-f_r(p) / eps), eps = depth / 10, whose gradient, unlike the
// minimum's, runs smoothly across an interface between two labels), p is lifted towards
// U's inner offset at `depth`,
//     q = p - w (f_U + depth) grad f_U,   w = min(o / (depth / 2), 1),
// so that there the labels compare as they do at that depth, where their fits have not
// yet rounded off, and the interfaces between them run straight out to the outside. A
// label's own fit holds the points it encloses (w = 0 there): a label that lines the
// outside more thinly than `depth` keeps its place on it.
// A label map whose labels touch nowhere, and the parts of a mesh: h_r = f_r and
//     h_0 = -f_(1) + psi(f_(2)),   psi(s) = (T - s)^2 / T for s < T, else 0,
// f_(1) <= f_(2) the two lowest units' values, T = (1 + sqrt(3)/2) tau and tau the
// contact distance (0 for a label map: h_0 = -min_r f_r). A unit is a part, or a group
// of parts in contact, whose union is fitted as one more function (PartUnions): the
// group's outside is then one smooth fit across the rims where its parts' shared faces
// meet it. Away from other parts (f_(2) >= T) it is -min_r f_r: each part's boundary is
// its own fit's zero set and parts stay apart. Near another part the background yields:
// on a face two parts share (f_(1) = f_(2) = 0) h_0 = T > 0, so the two meet in one
// interface with no background sliver; in a gap between two parts, at its middle
// f_(1) = f_(2) = s, the background holds it while psi(s) < 2 s, that is while
// s > tau / 2: parts whose surfaces come within tau of each other share an interface,
// parts further apart stay apart.
// With a label map's support (multi/region_support.h), only the regions whose voxels lie
// within two voxels of p compete there (a region beyond its support has h = +infinity),
// so that a fit extrapolated far from its points cannot claim space. A label's function
// counts only within its fitted points' box (widened by 0.5% of its cube): beyond it the
// leaves' polynomials are extrapolated and may go negative where no surface is
// (mpu/data_box.h).
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <vector>

#include "mpu/mpu_surface.h"
#include "multi/region_support.h"

namespace mpumesh::multi {

// A label map's labels compare this many in-plane voxels inside the labels' union (the
// header's `depth`): about the reach over which a label's fit rounds off its rim.
inline constexpr double kLabelDepthVoxels = 2.0;

// Groups of a mesh's parts in contact, each with its union's fit: group[r - 1] is region
// r's group (an index into `fits`) or -1 for a part on its own.
struct PartUnions {
  std::vector<int> group;
  std::vector<const mpu::MpuSurface*> fits;
};

class MaterialField {
 public:
  // `fits[r-1]` is region r's function (label `labels[r-1]`); `outside` the union's fit or
  // null; `depth` the header's (mm). The fits must outlive the field.
  MaterialField(std::vector<int64_t> labels, std::vector<const mpu::MpuSurface*> fits,
                const mpu::MpuSurface* outside, const RegionSupport* support = nullptr, double depth = 0);
  // A mesh's parts: parts within `contact` mm of each other share an interface; `unions`:
  // the groups in contact with their unions' fits (none: every part a unit).
  MaterialField(std::vector<int64_t> labels, std::vector<const mpu::MpuSurface*> fits, double contact,
                PartUnions unions = {});

  int regions() const { return int(fits_.size()) + 1; }
  // A number no other field of this process has (a device keeps a field's copy by it).
  uint64_t id() const { return id_; }
  // What the field is made of, for a device's copy of it.
  const std::vector<const mpu::MpuSurface*>& fits() const { return fits_; }
  const mpu::MpuSurface* outside() const { return outside_; }
  const RegionSupport* support() const { return support_; }
  double contact() const { return contact_; }
  double depth() const { return depth_; }
  const PartUnions& unions() const { return unions_; }
  // The label of region r (0 for the background).
  int64_t label(int r) const { return r == 0 ? 0 : labels_[size_t(r - 1)]; }

  // Every region's function at p (size regions()).
  void values(const Eigen::Vector3d& p, std::vector<double>& f) const;
  // The same with gradients.
  void values_and_gradients(const Eigen::Vector3d& p, std::vector<double>& f, std::vector<Eigen::Vector3d>& g) const;
  // The region at p.
  int region_at(const Eigen::Vector3d& p) const;
  // The regions in order of their value at p, most inside first (ties by index).
  std::vector<int> ranked(const Eigen::Vector3d& p) const;
  // The same from the values at a point (values()).
  static std::vector<int> ranked(const std::vector<double>& f);

  // p moved onto the interface f_a = f_b (Newton steps on f_a - f_b along its gradient,
  // at most `max_move` in all); false when it does not converge there.
  bool project_interface(Eigen::Vector3d& p, int a, int b, double max_move) const;
  // p moved onto the curve f_a = f_b = f_c (the least-norm Newton step of the two
  // differences); false when it does not converge within `max_move`.
  bool project_junction(Eigen::Vector3d& p, const std::array<int, 3>& abc, double max_move) const;
  // The junction curve's unit tangent at p (zero where the three gradients are parallel).
  Eigen::Vector3d junction_tangent(const Eigen::Vector3d& p, const std::array<int, 3>& abc) const;
  // The interface's unit normal at p, pointing from a into b.
  Eigen::Vector3d interface_normal(const Eigen::Vector3d& p, int a, int b) const;

 private:
  double f_of(int r, const Eigen::Vector3d& p, Eigen::Vector3d* g) const;
  // The parts' background (the header's rule) from the regions' values `f` (and
  // gradients, whose g[0] it writes when given).
  double parts_background(const Eigen::Vector3d& p, const std::vector<double>& f,
                          std::vector<Eigen::Vector3d>* g) const;
  // Every region's function at p (and gradients when `g` is given).
  void evaluate(const Eigen::Vector3d& p, std::vector<double>& f, std::vector<Eigen::Vector3d>* g) const;
  // The same for a label map whose labels' union bounds the background (the header's h).
  void evaluate_under_union(const Eigen::Vector3d& p, std::vector<double>& f, std::vector<Eigen::Vector3d>* g) const;
  // How far p goes to q along the union's normal (the header's w (f_U + depth)), from the
  // union's value `fu` at p and the regions' values `f` (and gradients `g`) there, with w
  // and its gradient.
  struct Lift {
    double length = 0, w = 0;
    Eigen::Vector3d grad_w = Eigen::Vector3d::Zero();
  };
  Lift notch_lift(double fu, const std::vector<double>& f, const std::vector<Eigen::Vector3d>* g) const;
  // Each region beyond its support at p never the most inside.
  void mask_unsupported(const Eigen::Vector3d& p, std::vector<double>& f) const;
  std::vector<int64_t> labels_;
  std::vector<const mpu::MpuSurface*> fits_;
  const mpu::MpuSurface* outside_;
  const RegionSupport* support_;
  double contact_ = 0;
  double depth_ = 0;
  PartUnions unions_;
  uint64_t id_;
};

}  // namespace mpumesh::multi
