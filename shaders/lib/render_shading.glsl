// Colour maps and shading of the mesh renderer; core/render/raster_ref.cpp repeats every
// line in C++ (the CPU reference), so a change here is a change there.
#ifndef MPUMESH_RENDER_SHADING_GLSL
#define MPUMESH_RENDER_SHADING_GLSL
#include "shared/render_abi.h"

// Viridis as a degree-6 polynomial in t (Matt Zucker's fit, public domain).
vec3 viridis(float t) {
  const vec3 c0 = vec3(0.2777273272234177, 0.005407344544966578, 0.3340998053353061);
  const vec3 c1 = vec3(0.1050930431085774, 1.404613529898575, 1.384590162594685);
  const vec3 c2 = vec3(-0.3308618287255563, 0.214847559468213, 0.09509516302823659);
  const vec3 c3 = vec3(-4.634230498983486, -5.799100973351585, -19.33244095627987);
  const vec3 c4 = vec3(6.228269936347081, 14.17993336680509, 56.69055260068105);
  const vec3 c5 = vec3(4.776384997670288, -13.74514537774601, -65.35303263337234);
  const vec3 c6 = vec3(-5.435455855934631, 4.645852612178535, 26.3124352495832);
  return c0 + t * (c1 + t * (c2 + t * (c3 + t * (c4 + t * (c5 + t * c6)))));
}

// Blue, light grey at the middle, red (Moreland's cool-warm end points).
vec3 diverging(float t) {
  const vec3 lo = vec3(0.230, 0.299, 0.754), mid = vec3(0.865, 0.865, 0.865), hi = vec3(0.706, 0.016, 0.150);
  return t < 0.5 ? mix(lo, mid, t * 2.0) : mix(mid, hi, t * 2.0 - 1.0);
}

vec3 base_colour(float value, vec4 range) {
  if (range.z == float(RENDER_CMAP_NONE)) return vec3(0.90, 0.86, 0.78);
  float t = clamp((value - range.x) / (range.y - range.x), 0.0, 1.0);
  return range.z == float(RENDER_CMAP_SEQUENTIAL) ? viridis(t) : diverging(t);
}

// Two-sided Blinn-Phong under one light, plus a dark line where the fragment lies within
// `half_width` pixels of its triangle's edge (bary / fw: the distance to each edge in
// pixels, fw the screen-space rate |d/dx| + |d/dy| of each barycentric coordinate).
vec3 shade(vec3 base, vec3 normal, vec4 light, vec4 eye, vec3 bary, vec3 fw) {
  vec3 n = normalize(normal);
  if (dot(n, eye.xyz) < 0.0) n = -n;
  float diffuse = max(dot(n, light.xyz), 0.0);
  vec3 h = normalize(light.xyz + eye.xyz);
  float spec = pow(max(dot(n, h), 0.0), 32.0);
  vec3 c = base * (0.28 + 0.72 * diffuse) + vec3(0.12 * spec);
  if (light.w > 0.5) {
    vec3 d = bary / max(fw, vec3(1e-6));
    float m = min(d.x, min(d.y, d.z));
    float line = 1.0 - smoothstep(eye.w - 0.5, eye.w + 0.5, m);
    c = mix(c, vec3(0.08, 0.08, 0.10), 0.85 * line);
  }
  return clamp(c, 0.0, 1.0);
}
#endif
