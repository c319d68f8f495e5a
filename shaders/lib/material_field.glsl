// The multi-material field in GLSL: each region's function and the labelling of space.
// Mirrors core/multi/material_field.cpp (values, values_and_gradients, ranked,
// project_interface, project_junction, junction_tangent, interface_normal) and
// core/multi/region_support.cpp (allows). The includer declares the `fits`, `regions_`
// and `support` buffers beside lib/mpu_eval.glsl's, and the push block `pc`
// (a ComplexPush).

// A region beyond its support: never the most inside.
const float CX_UNSUPPORTED = 1e30;
// Newton converges to this fraction of the largest move. The reference stops at 1e-7 of
// it; float32 resolves about 1e-5 mm 100 mm from the origin, the reach is 1-8 mm, so this
// is the finest a float step tells apart from its noise.
const float CX_TOLERANCE = 1e-4;
const int CX_STEPS = 12;
// The notch lift grows from none to the whole over this fraction of the depth, the labels'
// soft minimum's scale this fraction (kNotchRamp, kNotchSoftness in material_field.cpp).
const float CX_NOTCH_RAMP = 0.5;
const float CX_NOTCH_SOFTNESS = 0.1;

MpuGridRef fit_grid(CxFit F) {
  MpuGridRef G;
  G.box_min = F.grid_min.xyz;
  G.inv_cell = F.grid_min.w;
  G.dims = F.dims.xyz;
  G.far_value = F.data_min.w;
  G.leaf_base = F.dims.w;
  G.offset_base = F.bases.x;
  G.id_base = F.bases.y;
  return G;
}

// Fit k's value over its gradient's length (far outside beyond where it holds), with the
// unit gradient in g: distance_of in material_field.cpp.
float fit_distance(uint k, vec3 p, out vec3 g) {
  CxFit F = fits[k];
  if (any(lessThan(p, F.data_min.xyz)) || any(greaterThan(p, F.data_max.xyz))) {
    g = vec3(0.0);
    return F.data_min.w;
  }
  MpuSample s = mpu_evaluate_in(fit_grid(F), p, MPU_NO_HESSIAN);
  float len = length(s.g);
  g = len > 1e-9 ? s.g / len : s.g;
  return len > 1e-9 ? s.f / len : s.f;
}

float round_half_away(float x) { return sign(x) * floor(abs(x) + 0.5); }

// Whether region r may be at p (RegionSupport::allows); every region where no support is
// bound.
bool allows(uint r, vec3 p) {
  if (pc.support == 0u) return true;
  vec3 d = p - vec3(pc.map_origin[0], pc.map_origin[1], pc.map_origin[2]);
  vec3 ijk = vec3(dot(vec3(pc.to_index[0], pc.to_index[1], pc.to_index[2]), d),
                  dot(vec3(pc.to_index[3], pc.to_index[4], pc.to_index[5]), d),
                  dot(vec3(pc.to_index[6], pc.to_index[7], pc.to_index[8]), d));
  uvec3 dims = uvec3(pc.map_dims[0], pc.map_dims[1], pc.map_dims[2]);
  uvec3 idx;
  for (int a = 0; a < 3; ++a) {
    float x = round_half_away(ijk[a]);
    if (!(x >= 0.0 && x < float(dims[a]))) return r == 0u;
    idx[a] = uint(x);
  }
  CxRegion R = regions_[r];
  if (any(lessThan(idx, R.lo.xyz)) || any(greaterThanEqual(idx, R.hi.xyz))) return false;
  uvec3 box = R.hi.xyz - R.lo.xyz;
  uvec3 q = idx - R.lo.xyz;
  uint v = q.x + box.x * (q.y + box.y * q.z);
  return ((support[R.lo.w + v / 32u] >> (v % 32u)) & 1u) != 0u;
}

// The two lowest units of a mesh's parts (parts_background in material_field.cpp): the
// parts' contact unions and the parts in contact with none.
struct Units {
  float f1, f2;
  vec3 g1, g2;
};

void consider(inout Units u, float f, vec3 g) {
  if (f < u.f1) {
    u.f2 = u.f1;
    u.g2 = u.g1;
    u.f1 = f;
    u.g1 = g;
  } else if (f < u.f2) {
    u.f2 = f;
    u.g2 = g;
  }
}

Units no_units() {
  Units u;
  u.f1 = 1.0 / 0.0;
  u.f2 = 1.0 / 0.0;
  u.g1 = vec3(0.0);
  u.g2 = vec3(0.0);
  return u;
}

bool ungrouped(uint r) { return regions_[r].hi.w == 0u; }

// The parts' background from its two lowest units: -f_(1) + psi(f_(2)).
float parts_background(Units u, out vec3 g0) {
  float f0 = -u.f1;
  g0 = -u.g1;
  float T = (1.0 + sqrt(3.0) / 2.0) * pc.contact;
  if (pc.contact > 0.0 && u.f2 < T) {
    float gap = T - u.f2;
    f0 += gap * gap / T;
    g0 -= 2.0 * gap / T * u.g2;
  }
  return f0;
}

// The functions below call the fits (and so the MPU evaluation) from as few places as
// they can, in loops: a shader compiler inlines every call, and each place the
// evaluation is inlined costs the driver's compiler time and the kernel registers.

// The four most inside regions at p, in order (ties by index), with their values; fewer
// where the field has fewer regions (unused entries CX_NONE, +inf).
struct Ranked {
  uint r[4];
  float f[4];
};

void insert_ranked(inout Ranked k, uint r, float f) {
  for (int i = 0; i < 4; ++i) {
    if (f < k.f[i] || (f == k.f[i] && r < k.r[i])) {
      for (int j = 3; j > i; --j) {
        k.r[j] = k.r[j - 1];
        k.f[j] = k.f[j - 1];
      }
      k.r[i] = r;
      k.f[i] = f;
      return;
    }
  }
}

void clear_labels(inout Ranked k, inout float f[4], inout vec3 g[4]) {
  for (int i = 0; i < 4; ++i) {
    k.r[i] = CX_NONE;
    k.f[i] = 1.0 / 0.0;
    f[i] = CX_UNSUPPORTED;
    g[i] = vec3(0.0);
  }
}

// The field at p (MaterialField::evaluate): the values and gradients of regions
// regs[0 .. n) in f and g, and the four most inside regions in k. Every fit in one loop:
// for a label map whose labels touch, the labels' union first (at p), then the labels at
// p and, where the union's notch lift moves p to q, the labels again at q, each shifted
// so that the most inside holds half the union's value; for a label map whose labels
// touch nowhere and a mesh's parts, the labels (at p) and the parts' contact unions.
void field_at(vec3 p, uvec4 regs, uint n, out Ranked k, out float f[4], out vec3 g[4]) {
  clear_labels(k, f, g);
  bool parts = pc.outside == CX_NONE;
  uint labels = pc.regions - 1u;
  uint count = parts ? labels + pc.unions : 1u + 2u * labels;
  Units u = no_units();
  float fu = 0.0, fm = CX_UNSUPPORTED;
  vec3 gu = vec3(0.0), gm = vec3(0.0), q = p, grad_lift = vec3(0.0);
  // The labels' soft minimum at p (MaterialField::notch_lift), summed as they come.
  float eps = CX_NOTCH_SOFTNESS * pc.depth, lo = 1.0 / 0.0, sum = 0.0;
  vec3 grad_lo = vec3(0.0);
  for (uint s = 0u; s < count; ++s) {
    bool again = !parts && s > labels;  // the labels at q
    if (again && s == labels + 1u) {
      // The notch lift (MaterialField::notch_lift).
      if (!(pc.depth > 0.0 && fu > -pc.depth && sum > 0.0)) break;
      float ramp = CX_NOTCH_RAMP * pc.depth, outside = lo - eps * log(sum);
      if (!(outside > 0.0)) break;
      float w = min(outside / ramp, 1.0);
      vec3 grad_w = outside < ramp ? grad_lo / (sum * ramp) : vec3(0.0);
      q = p - w * (fu + pc.depth) * gu;
      grad_lift = w * gu + (fu + pc.depth) * grad_w;
      clear_labels(k, f, g);
      fm = CX_UNSUPPORTED;
    }
    uint fit = parts ? s : (s == 0u ? pc.outside : (again ? s - labels - 1u : s - 1u));
    vec3 gj;
    float fj = fit_distance(fit, again ? q : p, gj);
    if (!parts && s == 0u) {
      fu = fj;
      gu = gj;
      continue;
    }
    if (fit >= labels) {  // a contact union
      consider(u, fj, gj);
      continue;
    }
    uint r = fit + 1u;
    if (parts && ungrouped(r)) consider(u, fj, gj);
    if (again) gj -= grad_lift * dot(gu, gj);
    bool ok = allows(r, p);
    float v = ok ? fj : CX_UNSUPPORTED;
    if (!parts && ok && fj < fm) {
      fm = fj;
      gm = gj;
    }
    if (!parts && !again && ok) {
      if (fj < lo) {
        float scale = lo < 1.0 / 0.0 ? exp(-(lo - fj) / eps) : 0.0;
        sum = sum * scale + 1.0;
        grad_lo = grad_lo * scale + gj;
        lo = fj;
      } else {
        float e = exp(-(fj - lo) / eps);
        sum += e;
        grad_lo += e * gj;
      }
    }
    insert_ranked(k, r, v);
    for (uint i = 0u; i < 4u; ++i)
      if (i < n && regs[i] == r) {
        f[i] = v;
        g[i] = gj;
      }
  }
  float f0;
  vec3 g0;
  if (parts) {
    f0 = parts_background(u, g0);
  } else {
    f0 = -0.5 * fu;
    g0 = -0.5 * gu;
    if (fm < CX_UNSUPPORTED) {  // the labels under the union
      float shift = 0.5 * fu - fm;
      vec3 shift_g = 0.5 * gu - gm;
      for (int i = 0; i < 4; ++i)
        if (k.r[i] != CX_NONE && k.f[i] < CX_UNSUPPORTED) k.f[i] += shift;
      for (uint i = 0u; i < 4u; ++i)
        if (i < n && regs[i] != 0u && f[i] < CX_UNSUPPORTED) {
          f[i] += shift;
          g[i] += shift_g;
        }
    }
  }
  float v0 = allows(0u, p) ? f0 : CX_UNSUPPORTED;
  insert_ranked(k, 0u, v0);
  for (uint i = 0u; i < 4u; ++i)
    if (i < n && regs[i] == 0u) {
      f[i] = v0;
      g[i] = g0;
    }
}

Ranked ranked(vec3 p) {
  Ranked k;
  float f[4];
  vec3 g[4];
  field_at(p, uvec4(0u), 0u, k, f, g);
  return k;
}

// The gradients of regions regs[0 .. n).
void gradients(vec3 p, uvec4 regs, uint n, out vec3 g[4]) {
  Ranked k;
  float f[4];
  field_at(p, regs, n, k, f, g);
}

// p onto where regions regs[0 .. n) (n = 2, 3 or 4) have equal functions: Newton steps on
// the n - 1 differences f_0 - f_i, the least-norm step (project_interface,
// project_junction, and the corner's square system in complex_step_ref.cpp), at most
// max_move in all.
bool project_equal(inout vec3 p, uvec4 regs, uint n, float max_move) {
  vec3 start = p;
  for (int it = 0; it < CX_STEPS; ++it) {
    Ranked k;
    float f[4];
    vec3 g[4];
    field_at(p, regs, n, k, f, g);
    for (uint i = n; i < 4u; ++i) f[i] = 0.0;
    vec3 r0 = g[0] - g[1], r1 = g[0] - g[2], r2 = g[0] - g[3];
    vec3 d = vec3(f[0] - f[1], f[0] - f[2], f[0] - f[3]);
    vec3 step;
    if (n == 2u) {
      float g2 = dot(r0, r0);
      if (!(g2 > 1e-12)) return false;
      step = d.x / g2 * r0;
    } else if (n == 3u) {
      float j00 = dot(r0, r0), j01 = dot(r0, r1), j11 = dot(r1, r1);
      float det = j00 * j11 - j01 * j01;
      if (!(abs(det) > 1e-10)) return false;
      vec2 y = vec2(j11 * d.x - j01 * d.y, j00 * d.y - j01 * d.x) / det;
      step = r0 * y.x + r1 * y.y;
    } else {
      mat3 Jt = mat3(r0, r1, r2);  // columns: the rows of J
      if (!(abs(determinant(Jt)) > 1e-12)) return false;
      step = transpose(inverse(Jt)) * d;
    }
    p -= step;
    if (length(p - start) > max_move) return false;
    if (length(step) < CX_TOLERANCE * max_move) return true;
  }
  return false;
}

uvec2 sorted_pair(uint a, uint b) { return uvec2(min(a, b), max(a, b)); }

// p onto the interface of its two most inside regions, at most three times while the
// two change as it moves (onto_interface in complex_step_ref.cpp).
bool onto_interface(inout vec3 p, float reach, out uvec2 pair) {
  pair = uvec2(CX_NONE);
  for (int pass = 0; pass < 4; ++pass) {
    Ranked k = ranked(p);
    uvec2 top = sorted_pair(k.r[0], k.r[1]);
    if (pass > 0 && top == pair) return true;
    if (pass == 3) return false;
    pair = top;
    if (!project_equal(p, uvec4(pair, 0u, 0u), 2u, reach)) return false;
  }
  return false;
}
