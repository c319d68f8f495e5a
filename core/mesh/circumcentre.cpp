#include "mesh/circumcentre.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/Robust_circumcenter_traits_3.h>
#include <CGAL/Simple_cartesian.h>

#include <optional>

namespace mpumesh {
namespace {

using IK = CGAL::Simple_cartesian<CGAL::Interval_nt<false>>;

std::optional<Eigen::Vector3d> from_intervals(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                              const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  IK::Point_3 x;
  {
    CGAL::Protect_FPU_rounding<true> upward;  // as the lazy kernel computes its intervals
    auto in = [](const Eigen::Vector3d& p) { return IK::Point_3(p.x(), p.y(), p.z()); };
    x = IK().construct_circumcenter_3_object()(in(a), in(b), in(c), in(d));
  }
  // Lazy_exact_nt's to_double, short of its exact computation.
  const double precision = CGAL::Epeck::FT::get_relative_precision_of_to_double();
  Eigen::Vector3d out;
  for (int k = 0; k < 3; ++k) {
    const CGAL::Interval_nt<false>& iv = x[k];
    double r;
    if (CGAL::fit_in_double(iv, r))
      out[k] = r;
    else if (CGAL::has_smaller_relative_precision(iv, precision))
      out[k] = CGAL::to_double(iv);
    else
      return std::nullopt;
  }
  return out;
}

}  // namespace

Eigen::Vector3d robust_circumcentre(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                    const Eigen::Vector3d& d) {
  if (const auto x = from_intervals(a, b, c, d)) return *x;
  using K = CGAL::Robust_circumcenter_traits_3<CGAL::Epick>;
  auto in = [](const Eigen::Vector3d& p) { return K::Point_3(p.x(), p.y(), p.z()); };
  const K::Point_3 x = K().construct_circumcenter_3_object()(in(a), in(b), in(c), in(d));
  return {x.x(), x.y(), x.z()};
}

}  // namespace mpumesh
