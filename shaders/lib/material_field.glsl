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

// Region r's function at p with its gradient (values_and_gradients, one region): a walk
// over the fits it is made of, its own for a label, the labels' union for a label map's
// background, every unit (the contact unions, then the parts in contact with none) for a
// mesh's parts' background.
float region_f(uint r, vec3 p, out vec3 g) {
  bool parts = r == 0u && pc.outside == CX_NONE;
  uint n = parts ? pc.unions + pc.regions - 1u : 1u;
  Units u = no_units();
  for (uint k = 0u; k < n; ++k) {
    uint fit = r > 0u ? r - 1u : pc.outside;
    if (parts) fit = k < pc.unions ? pc.regions - 1u + k : k - pc.unions;
    if (parts && k >= pc.unions && !ungrouped(fit + 1u)) continue;
    vec3 gk;
    float fk = fit_distance(fit, p, gk);
    consider(u, fk, gk);
  }
  float f = u.f1;
  g = u.g1;
  if (parts) {
    f = parts_background(u, g);
  } else if (r == 0u) {
    f = -f;
    g = -g;
  }
  return allows(r, p) ? f : CX_UNSUPPORTED;
}

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

// Every fit once: the labels' (ranked as they come), the contact unions and the labels'
// union (the background's function, ranked last).
Ranked ranked(vec3 p) {
  Ranked k;
  for (int i = 0; i < 4; ++i) {
    k.r[i] = CX_NONE;
    k.f[i] = 1.0 / 0.0;
  }
  bool parts = pc.outside == CX_NONE;
  uint labels = pc.regions - 1u;
  uint fits = labels + pc.unions + (parts ? 0u : 1u);
  Units u = no_units();
  float f0 = 0.0;
  for (uint j = 0u; j < fits; ++j) {
    vec3 g;
    float f = fit_distance(j, p, g);
    if (j >= labels) {
      if (parts) consider(u, f, g);
      else f0 = -f;
      continue;
    }
    if (parts && ungrouped(j + 1u)) consider(u, f, g);
    insert_ranked(k, j + 1u, allows(j + 1u, p) ? f : CX_UNSUPPORTED);
  }
  vec3 g0;
  if (parts) f0 = parts_background(u, g0);
  insert_ranked(k, 0u, allows(0u, p) ? f0 : CX_UNSUPPORTED);
  return k;
}

// The gradients of regions regs[0 .. n).
void gradients(vec3 p, uvec4 regs, uint n, out vec3 g[4]) {
  for (uint i = 0u; i < 4u; ++i) {
    g[i] = vec3(0.0);
    if (i < n) region_f(regs[i], p, g[i]);
  }
}

// p onto where regions regs[0 .. n) (n = 2, 3 or 4) have equal functions: Newton steps on
// the n - 1 differences f_0 - f_i, the least-norm step (project_interface,
// project_junction, and the corner's square system in complex_step_ref.cpp), at most
// max_move in all.
bool project_equal(inout vec3 p, uvec4 regs, uint n, float max_move) {
  vec3 start = p;
  for (int it = 0; it < CX_STEPS; ++it) {
    float f[4];
    vec3 g[4];
    for (uint i = 0u; i < 4u; ++i) {
      f[i] = 0.0;
      g[i] = vec3(0.0);
      if (i < n) f[i] = region_f(regs[i], p, g[i]);
    }
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
