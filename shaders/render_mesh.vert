#version 450
// Offscreen mesh renderer, vertex stage: clip position from the orthographic matrix; the
// corner's barycentric coordinate from its place in the triangle list.
#extension GL_GOOGLE_include_directive : require
#include "shared/render_abi.h"

layout(push_constant) uniform Push { RenderPush pc; };
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in float in_value;
layout(location = 0) out vec3 v_normal;
layout(location = 1) out float v_value;
layout(location = 2) out vec3 v_bary;

void main() {
  const mat4 mvp = mat4(pc.mvp[0], pc.mvp[1], pc.mvp[2], pc.mvp[3]);
  gl_Position = mvp * vec4(in_position, 1.0);
  v_normal = in_normal;
  v_value = in_value;
  const int corner = gl_VertexIndex % 3;
  v_bary = vec3(corner == 0 ? 1.0 : 0.0, corner == 1 ? 1.0 : 0.0, corner == 2 ? 1.0 : 0.0);
}
