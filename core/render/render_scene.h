// What the mesh renderer draws, built once on the CPU and drawn by either renderer (the
// Vulkan pipeline in host/render/mesh_render_vk, or the CPU reference in raster_ref):
// the triangle list with one value per corner for the colour map, the orthographic
// camera, the light, and the colour bar's legend drawn over the result.
#pragma once

#include <Eigen/Dense>
#include <optional>
#include <string>
#include <vector>

#include "geometry/triangle_mesh.h"
#include "render/image.h"
#include "shared/render_abi.h"

namespace mpumesh::render {

enum class ColorBy { kNone, kCurvature, kMinAngle, kEdgeLength, kLabel };

struct RenderOptions {
  int width = 1024, height = 768;  // the PNG's size
  int supersample = 2;             // drawn at this multiple, then averaged
  ColorBy color = ColorBy::kNone;
  // View direction: the unit vector from the object toward the viewer. Presets in patient
  // coordinates (DICOM LPS: +x left, +y posterior, +z head): front (0,-1,0), side (1,0,0),
  // top (0,0,1), iso (1,-1,1)/sqrt 3.
  Eigen::Vector3d view{1, -1, 1};
  // Frame only this ball (centre, radius in mm) instead of the whole mesh.
  std::optional<std::pair<Eigen::Vector3d, double>> zoom;
  bool wireframe = false;
  std::string title;  // drawn at the top left, with the legend's
  // Fixed colour range [lo, hi] instead of the automatic one (to compare meshes).
  std::optional<std::pair<double, double>> range;
};

// Parses "iso", "front", "side", "top" or "x,y,z"; throws InputError naming the option.
Eigen::Vector3d parse_view(const std::string& s);
// Parses "x,y,z,r" (mm).
std::pair<Eigen::Vector3d, double> parse_zoom(const std::string& s);
// Parses "WxH" (or "W×H").
std::pair<int, int> parse_size(const std::string& s);
ColorBy parse_color(const std::string& s);

struct Legend {
  bool shown = false;
  std::string title;  // e.g. "Gaussian curvature K (1/mm^2), from the MPU surface"
  double lo = 0, hi = 1;
  int colormap = RENDER_CMAP_NONE;
  int width = 0;  // pixels at the right for the bar and its labels (wide enough for the widest)
};

struct RenderScene {
  int width = 0, height = 0;  // the drawing's size (the PNG's times supersample)
  int supersample = 1;
  std::vector<abi::RenderVertex> vertices;  // three per triangle
  abi::RenderPush push{};
  Legend legend;
  std::string title;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // subtracted from every position
  // Inverse of the camera, for tests: the pixel of a world point in the final image.
  Eigen::Vector2d pixel_of(const Eigen::Vector3d& p) const;
  Eigen::Matrix4d clip_from_world = Eigen::Matrix4d::Identity();
};

// The values per corner: curvature from mesh.curvature when present (else estimated from
// the mesh, and the legend says so), the triangle's smallest angle (degrees), its mean
// edge length (mm), or, for a multi-material complex (face_labels), the label of the
// region each outer face bounds: only the faces against the background are drawn, turned
// toward it. Throws InputError for an empty mesh, or for kLabel without face labels.
RenderScene build_scene(const TriangleMesh& mesh, const RenderOptions& opt);

// The colour bar with its ticks and the titles, drawn onto the final (downsampled) image.
void draw_legend(Image& img, const RenderScene& scene);

// The colour map of the shaders (lib/render_shading.glsl), in C++, for the legend.
Eigen::Vector3f colormap(int map, float t);

}  // namespace mpumesh::render
