// The offscreen mesh renderer on a Vulkan device: a graphics pipeline (render_mesh.vert,
// render_mesh.frag) drawing the scene's triangle list into a colour and a depth image, no
// window and no display server, then a copy back to the host. CPU reference:
// core/render/raster_ref.
#pragma once

#include "compute/compute_backend.h"
#include "render/image.h"
#include "render/render_scene.h"
#include "vk/context.h"

namespace mpumesh::vk {

// The drawing at scene.width x scene.height, before render::finish(). Throws
// NoVulkanDevice when the device's queue cannot draw.
render::Image render_mesh(Context& ctx, const render::RenderScene& scene);

// The finished image (downsampled, titles and colour bar drawn) on the backend given: this
// pipeline on a VulkanBackend's device, the CPU reference on the CPU backend.
render::Image render_image(ComputeBackend& backend, const render::RenderScene& scene);

}  // namespace mpumesh::vk
