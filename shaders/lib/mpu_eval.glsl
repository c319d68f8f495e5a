// MPU evaluation in GLSL: f, ∇f and a second derivative (the blended Hessian
// Hb = Σ w ∇²Q / Σ w, the leaves' own Hessians weighted, from which the surface's
// curvature is taken, or the Hessian of f: see core/mpu/mpu_eval_ref.h) at a point, the
// leaves found through the lookup grid, each
// leaf's polynomial evaluated in its own frame scaled by its radius. Mirrors
// core/mpu/mpu_eval_ref.cpp (evaluate) and core/mpu/local_poly.h; the includer declares
// the `leaves`, `offsets` and `leaf_ids` buffers and either the push block `pc` or, with
// MPU_GRID_FROM_TABLE defined, its own table of surfaces.
// Sums are taken about the first leaf's value f0, so that Σ w (Q - f0) does not cancel
// the large terms that Σ w Q would: f = f0 + N / D.

struct MpuSample {
  float f;
  vec3 g;
  mat3 H;  // MPU_BLENDED_HESSIAN: Hb; MPU_HESSIAN: the Hessian of f; MPU_NO_HESSIAN: 0
  uint leaves;
};

// The second derivative evaluated with f and ∇f: none (what Newton steps need), the
// blended Hessian (the surface's curvature: mpu_eval.comp) or the Hessian of f (the
// particles' curvature weights: particle_step_project.comp; core/particles/particle_step_ref.h
// says why). A uniform value (a push constant or a literal), so the branches do not
// diverge.
const uint MPU_NO_HESSIAN = 0u, MPU_BLENDED_HESSIAN = 1u, MPU_HESSIAN = 2u;

// Where one surface lies in the buffers and its lookup grid: a kernel of one surface
// takes it from the push block (mpu_evaluate_opt), a kernel of several surfaces
// (complex_step.comp) from a table, their leaves, offsets and leaf ids concatenated.
struct MpuGridRef {
  vec3 box_min;
  float inv_cell;
  uvec3 dims;
  float far_value;
  uint leaf_base;    // the surface's first leaf (in leaves)
  uint offset_base;  // its first offset (in offsets); offsets count from its first leaf id
  uint id_base;      // its first leaf id (in leaf_ids); leaf ids count from its first leaf
};

MpuSample mpu_evaluate_in(MpuGridRef G, vec3 x, uint second) {
  MpuSample s;
  s.f = G.far_value;
  s.g = vec3(0.0);
  s.H = mat3(0.0);
  s.leaves = 0u;
  vec3 rel = (x - G.box_min) * G.inv_cell;
  ivec3 c = ivec3(floor(rel));
  if (any(lessThan(c, ivec3(0))) || any(greaterThanEqual(c, ivec3(G.dims)))) return s;
  uint cell = G.offset_base + uint(c.x) + G.dims.x * (uint(c.y) + G.dims.y * uint(c.z));
  uint first = G.id_base + offsets[cell], last = G.id_base + offsets[cell + 1u];
  float f0 = 0.0;
  bool have_f0 = false;
  float N = 0.0, D = 0.0;
  vec3 gN = vec3(0.0), gD = vec3(0.0);
  mat3 HN = mat3(0.0), HD = mat3(0.0);
  for (uint k = first; k < last; ++k) {
    uint b = MPU_LEAF_VEC4 * (G.leaf_base + leaf_ids[k]);
    vec4 cr = leaves[b];
    vec3 d = x - cr.xyz;
    float R = cr.w;
    float r2 = dot(d, d);
    if (r2 >= R * R) continue;
    float r = sqrt(r2);
    vec4 fu = leaves[b + 1u], fv = leaves[b + 2u], fw = leaves[b + 3u];
    float invR = fu.w;
    // Quadratic B-spline weight of t = 3r / 2R and its radial derivatives.
    float sc = 1.5 * invR, t = sc * r;
    bool inner = t <= 0.5;
    float w = inner ? 0.75 - t * t : 0.5 * (t - 1.5) * (t - 1.5);
    float dw = inner ? -2.0 * t * sc : (t - 1.5) * sc;
    float d2w = inner ? -2.0 * sc * sc : sc * sc;
    // ∇w = k1 d, Hw = k1 I + k2 d dᵀ (k1 finite at r = 0 on the inner piece).
    float k1 = inner ? -2.0 * sc * sc : dw / r;
    float k2 = inner ? 0.0 : (d2w - k1) / r2;
    vec3 y = vec3(dot(fu.xyz, d), dot(fv.xyz, d), dot(fw.xyz, d)) * invR;
    vec4 c0 = leaves[b + 4u], c1 = leaves[b + 5u], c2 = leaves[b + 6u], c3 = leaves[b + 7u], c4 = leaves[b + 8u];
    float u = y.x, v = y.y, ww = y.z;
    float u2 = u * u, v2 = v * v, uv = u * v;
    // Coefficients: c0 = (1 u v u²), c1 = (uv v² u³ u²v), c2 = (uv² v³ u⁴ u³v),
    // c3 = (u²v² uv³ v⁴ w), c4 = (w² uw vw v²w); fv.w = u²w, fw.w = uvw.
    float e19 = fv.w, e20 = fw.w, e21 = c4.w;
    float q = c0.x + c0.y * u + c0.z * v + c0.w * u2 + c1.x * uv + c1.y * v2 + c1.z * u2 * u + c1.w * u2 * v +
              c2.x * u * v2 + c2.y * v2 * v + c2.z * u2 * u2 + c2.w * u2 * uv + c3.x * u2 * v2 + c3.y * uv * v2 +
              c3.z * v2 * v2 + c3.w * ww + c4.x * ww * ww + c4.y * u * ww + c4.z * v * ww + e19 * u2 * ww +
              e20 * uv * ww + e21 * v2 * ww;
    float gu = c0.y + 2.0 * c0.w * u + c1.x * v + 3.0 * c1.z * u2 + 2.0 * c1.w * uv + c2.x * v2 +
               4.0 * c2.z * u2 * u + 3.0 * c2.w * u2 * v + 2.0 * c3.x * u * v2 + c3.y * v2 * v + c4.y * ww +
               2.0 * e19 * u * ww + e20 * v * ww;
    float gv = c0.z + c1.x * u + 2.0 * c1.y * v + c1.w * u2 + 2.0 * c2.x * uv + 3.0 * c2.y * v2 +
               c2.w * u2 * u + 2.0 * c3.x * u2 * v + 3.0 * c3.y * u * v2 + 4.0 * c3.z * v2 * v + c4.z * ww +
               e20 * u * ww + 2.0 * e21 * v * ww;
    float gw = c3.w + 2.0 * c4.x * ww + c4.y * u + c4.z * v + e19 * u2 + e20 * uv + e21 * v2;
    // World units: Q = R q, ∇Q = Mᵀ ∇q, HQ = Mᵀ Hq M / R (M's rows are fu, fv, fw; GLSL
    // matrices are column-major, so mat3(fu, fv, fw) is Mᵀ).
    mat3 Mt = mat3(fu.xyz, fv.xyz, fw.xyz);
    float Q = R * q;
    vec3 gQ = Mt * vec3(gu, gv, gw);
    if (!have_f0) {
      f0 = Q;
      have_f0 = true;
    }
    float Qs = Q - f0;
    vec3 gw3 = k1 * d;
    N += w * Qs;
    D += w;
    gN += Qs * gw3 + w * gQ;
    gD += gw3;
    if (second != MPU_NO_HESSIAN) {
      float huu = 2.0 * c0.w + 6.0 * c1.z * u + 2.0 * c1.w * v + 12.0 * c2.z * u2 + 6.0 * c2.w * uv + 2.0 * c3.x * v2 +
                  2.0 * e19 * ww;
      float huv = c1.x + 2.0 * c1.w * u + 2.0 * c2.x * v + 3.0 * c2.w * u2 + 4.0 * c3.x * uv + 3.0 * c3.y * v2 + e20 * ww;
      float hvv = 2.0 * c1.y + 2.0 * c2.x * u + 6.0 * c2.y * v + 2.0 * c3.x * u2 + 6.0 * c3.y * uv + 12.0 * c3.z * v2 +
                  2.0 * e21 * ww;
      float huw = c4.y + 2.0 * e19 * u + e20 * v, hvw = c4.z + e20 * u + 2.0 * e21 * v;
      mat3 Hq = mat3(huu, huv, huw, huv, hvv, hvw, huw, hvw, 2.0 * c4.x);
      mat3 HQ = Mt * Hq * transpose(Mt) * invR;
      if (second == MPU_BLENDED_HESSIAN) {
        HN += w * HQ;
      } else {
        mat3 Hw = mat3(k1) + k2 * outerProduct(d, d);
        HN += Qs * Hw + outerProduct(gw3, gQ) + outerProduct(gQ, gw3) + w * HQ;
        HD += Hw;
      }
    }
    s.leaves += 1u;
  }
  if (!(D > 0.0)) {
    s.leaves = 0u;
    return s;
  }
  float fs = N / D;
  s.f = f0 + fs;
  s.g = (gN - fs * gD) / D;
  if (second == MPU_BLENDED_HESSIAN) s.H = HN / D;
  if (second == MPU_HESSIAN) s.H = (HN - fs * HD - outerProduct(s.g, gD) - outerProduct(gD, s.g)) / D;
  return s;
}

#ifndef MPU_GRID_FROM_TABLE
// The surface of the push block `pc` (an MpuPush's first fields).
MpuSample mpu_evaluate_opt(vec3 x, uint second) {
  MpuGridRef G;
  G.box_min = vec3(pc.box_min_x, pc.box_min_y, pc.box_min_z);
  G.inv_cell = pc.inv_cell;
  G.dims = uvec3(pc.nx, pc.ny, pc.nz);
  G.far_value = pc.far_value;
  G.leaf_base = 0u;
  G.offset_base = 0u;
  G.id_base = 0u;
  return mpu_evaluate_in(G, x, second);
}

MpuSample mpu_evaluate(vec3 x) { return mpu_evaluate_opt(x, MPU_BLENDED_HESSIAN); }
#endif

// Principal curvatures after Kindlmann et al. (2003): κ1, κ2, K, mean.
vec4 mpu_curvature(vec3 g, mat3 H) {
  float len = length(g);
  if (!(len > 0.0)) return vec4(0.0);
  vec3 n = g / len;
  mat3 P = mat3(1.0) - outerProduct(n, n);
  mat3 G = -(P * H * P) / len;
  float T = G[0][0] + G[1][1] + G[2][2];
  float F2 = dot(G[0], G[0]) + dot(G[1], G[1]) + dot(G[2], G[2]);
  float disc = sqrt(max(2.0 * F2 - T * T, 0.0));
  float k1 = 0.5 * (T + disc), k2 = 0.5 * (T - disc);
  return vec4(k1, k2, k1 * k2, 0.5 * (k1 + k2));
}
