// The local function of one MPU leaf as a polynomial in the leaf's own frame, scaled by its
// radius: y = M (x - c) / R = (u, v, w), with M's rows the frame axes (w along the mean
// normal for a height field). One basis serves every kind of fit, so evaluation is the
// same branchless dot product on both backends (shaders/lib/mpu_eval.glsl mirrors it):
//   0: 1    1: u    2: v    3: u²   4: uv   5: v²   6: u³   7: u²v  8: uv²  9: v³
//  10: u⁴  11: u³v 12: u²v² 13: uv³ 14: v⁴ 15: w   16: w²  17: uw  18: vw
//  19: u²w 20: uvw 21: v²w
// (a full quadric in u, v, w uses 0-5 and 15-18; a height field w - h(u, v) of degree up
// to 4 uses 0-15; two quadratic sheets (w - a(u, v)) (w - b(u, v)) / t use 0-21). The leaf's function in world units is Q(x) = R q(y), so that q's
// gradient of about 1 makes Q about a signed distance in millimetres.
#pragma once

#include <Eigen/Dense>
#include <array>

namespace mpumesh::mpu {

inline constexpr int kTerms = 22;
using Coeffs = std::array<double, kTerms>;

// Number of bivariate monomials of degree <= d (the first terms of the basis).
inline constexpr int bivariate_terms(int d) { return (d + 1) * (d + 2) / 2; }

// Monomials m_k(u, v) for k < bivariate_terms(4), i.e. terms 0..14.
template <class Real>
inline void bivariate_monomials(Real u, Real v, Real* m) {
  const Real u2 = u * u, v2 = v * v;
  m[0] = 1; m[1] = u; m[2] = v;
  m[3] = u2; m[4] = u * v; m[5] = v2;
  m[6] = u2 * u; m[7] = u2 * v; m[8] = u * v2; m[9] = v2 * v;
  m[10] = u2 * u2; m[11] = u2 * u * v; m[12] = u2 * v2; m[13] = u * v2 * v; m[14] = v2 * v2;
}

// q, ∇q and the Hessian of q at y, in the scaled local frame.
// The coefficients are c[0], c[kStride], c[2 kStride], ... (a stride for arrays that hold
// many leaves' coefficients term by term).
template <class Real, int kStride = 1>
inline void local_poly(const Real* cs, Real u, Real v, Real w, Real& q, Real g[3], Real h[6] /* uu uv uw vv vw ww */) {
  struct {
    const Real* p;
    Real operator[](int k) const { return p[k * kStride]; }
  } c{cs};
  const Real u2 = u * u, v2 = v * v, uv = u * v;
  q = c[0] + c[1] * u + c[2] * v + c[3] * u2 + c[4] * uv + c[5] * v2 + c[6] * u2 * u + c[7] * u2 * v +
      c[8] * u * v2 + c[9] * v2 * v + c[10] * u2 * u2 + c[11] * u2 * uv + c[12] * u2 * v2 + c[13] * uv * v2 +
      c[14] * v2 * v2 + c[15] * w + c[16] * w * w + c[17] * u * w + c[18] * v * w + c[19] * u2 * w + c[20] * uv * w +
      c[21] * v2 * w;
  g[0] = c[1] + 2 * c[3] * u + c[4] * v + 3 * c[6] * u2 + 2 * c[7] * uv + c[8] * v2 + 4 * c[10] * u2 * u +
         3 * c[11] * u2 * v + 2 * c[12] * u * v2 + c[13] * v2 * v + c[17] * w + 2 * c[19] * u * w + c[20] * v * w;
  g[1] = c[2] + c[4] * u + 2 * c[5] * v + c[7] * u2 + 2 * c[8] * uv + 3 * c[9] * v2 + c[11] * u2 * u +
         2 * c[12] * u2 * v + 3 * c[13] * u * v2 + 4 * c[14] * v2 * v + c[18] * w + c[20] * u * w + 2 * c[21] * v * w;
  g[2] = c[15] + 2 * c[16] * w + c[17] * u + c[18] * v + c[19] * u2 + c[20] * uv + c[21] * v2;
  h[0] = 2 * c[3] + 6 * c[6] * u + 2 * c[7] * v + 12 * c[10] * u2 + 6 * c[11] * uv + 2 * c[12] * v2 + 2 * c[19] * w;
  h[1] = c[4] + 2 * c[7] * u + 2 * c[8] * v + 3 * c[11] * u2 + 4 * c[12] * uv + 3 * c[13] * v2 + c[20] * w;
  h[2] = c[17] + 2 * c[19] * u + c[20] * v;
  h[3] = 2 * c[5] + 2 * c[8] * u + 6 * c[9] * v + 2 * c[12] * u2 + 6 * c[13] * uv + 12 * c[14] * v2 + 2 * c[21] * w;
  h[4] = c[18] + c[20] * u + 2 * c[21] * v;
  h[5] = 2 * c[16];
}

// The quadratic B-spline of the partition of unity, b(t) for t = 3 r / (2 R): support
// t < 3/2; and its first and second derivatives in r.
template <class Real>
inline void bspline_weight(Real r, Real R, Real& w, Real& dw, Real& d2w) {
  const Real s = Real(1.5) / R, t = s * r;
  const Real inner = Real(0.75) - t * t, outer = Real(0.5) * (t - Real(1.5)) * (t - Real(1.5));
  const bool in = t <= Real(0.5), sup = t < Real(1.5);
  w = sup ? (in ? inner : outer) : Real(0);
  dw = sup ? (in ? -2 * t * s : (t - Real(1.5)) * s) : Real(0);
  d2w = sup ? (in ? -2 * s * s : s * s) : Real(0);
}

}  // namespace mpumesh::mpu
