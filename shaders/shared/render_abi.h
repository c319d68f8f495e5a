// Data contract of the offscreen mesh renderer (render_mesh.vert / render_mesh.frag) and
// its CPU reference (core/render/raster_ref.cpp). The mesh is drawn as a plain triangle
// list, three vertices per triangle (no index buffer), so that a corner's barycentric
// coordinate follows from gl_VertexIndex % 3 and per-triangle values need no geometry
// shader. Each vertex: position (mm, relative to the scene's centre), unit normal, value.
#ifndef MPUMESH_RENDER_ABI_H
#define MPUMESH_RENDER_ABI_H
#include "shared/abi_prelude.h"

#define RENDER_CMAP_NONE 0      // bone white
#define RENDER_CMAP_SEQUENTIAL 1  // viridis, lo..hi
#define RENDER_CMAP_DIVERGING 2   // blue - white - red, lo..hi with white at the middle

ABI_BEGIN
struct RenderVertex {
  float px, py, pz;
  float nx, ny, nz;
  float value;
};
struct RenderPush {
  vec4 mvp[4];  // columns of the clip-from-world matrix (orthographic)
  vec4 light;   // xyz: unit direction toward the light; w: 1 draws the edges
  vec4 eye;     // xyz: unit direction toward the viewer; w: edge half-width, pixels
  vec4 range;   // x: value at the low end, y: at the high end, z: colour map, w: unused
};
ABI_END

#ifdef __cplusplus
static_assert(sizeof(mpumesh::abi::RenderVertex) == 28, "RenderVertex is 7 floats");
static_assert(sizeof(mpumesh::abi::RenderPush) == 112, "RenderPush must match the GLSL push block");
#endif
#endif
