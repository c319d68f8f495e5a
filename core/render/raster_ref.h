// CPU reference of the offscreen renderer (shaders/render_mesh.vert, render_mesh.frag):
// the same orthographic transform, depth test (less, cleared to 1), interpolation and
// shading in float, one sample at each pixel centre. Also what `render --backend cpu`
// draws on a machine without Vulkan.
#pragma once

#include "render/image.h"
#include "render/render_scene.h"

namespace mpumesh::render {

// The drawing at scene.width x scene.height on a white background, before finish().
Image rasterize_ref(const RenderScene& scene);

// Downsampled to the asked size, with the titles and the colour bar drawn over it.
Image finish(const Image& drawing, const RenderScene& scene);

}  // namespace mpumesh::render
