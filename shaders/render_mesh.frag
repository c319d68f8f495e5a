#version 450
// Offscreen mesh renderer, fragment stage: colour map, shading and edges
// (lib/render_shading.glsl).
#extension GL_GOOGLE_include_directive : require
#include "lib/render_shading.glsl"

layout(push_constant) uniform Push { RenderPush pc; };
layout(location = 0) in vec3 v_normal;
layout(location = 1) in float v_value;
layout(location = 2) in vec3 v_bary;
layout(location = 0) out vec4 out_colour;

void main() {
  const vec3 fw = abs(dFdx(v_bary)) + abs(dFdy(v_bary));
  out_colour = vec4(shade(base_colour(v_value, pc.range), v_normal, pc.light, pc.eye, v_bary, fw), 1.0);
}
