// The offscreen renderer: the Vulkan pipeline (render_mesh.vert/.frag) against its CPU
// reference on known meshes, and the pictures themselves checked: not blank, the object
// where the camera puts it and of the expected size, the colour bar drawn, the same bytes
// on a second run.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/error.h"
#include "cpu/cpu_backend.h"
#include "mesh/surface_attributes.h"
#include "render/mesh_render_vk.h"
#include "render/raster_ref.h"
#include "test_support.h"

namespace mpumesh {
namespace {

using render::ColorBy;
using render::Image;

bool is_white(const uint8_t* p) { return p[0] == 255 && p[1] == 255 && p[2] == 255; }

double covered_fraction(const Image& img, int x0, int y0, int x1, int y1) {
  size_t n = 0, on = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) ++n, on += !is_white(img.at(x, y));
  return double(on) / double(n);
}

struct ImageDiff {
  double mean_abs = 0;  // per channel, 0..255
  double over_16 = 0;   // fraction of pixels with a channel more than 16 apart
};

ImageDiff compare(const Image& a, const Image& b) {
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  ImageDiff d;
  size_t over = 0;
  const size_t px = size_t(a.width) * size_t(a.height);
  for (size_t i = 0; i < px; ++i) {
    int worst = 0;
    for (int c = 0; c < 3; ++c) {
      const int e = std::abs(int(a.rgba[i * 4 + size_t(c)]) - int(b.rgba[i * 4 + size_t(c)]));
      d.mean_abs += e;
      worst = std::max(worst, e);
    }
    over += worst > 16;
  }
  d.mean_abs /= double(px * 3);
  d.over_16 = double(over) / double(px);
  return d;
}

// A sphere of radius 10 mm at (5, -3, 2) with its exact normals and curvature attached.
TriangleMesh sphere_mesh() {
  TriangleMesh m = test::icosphere(10, 4);
  for (auto& v : m.vertices) v += Eigen::Vector3d(5, -3, 2);
  estimate_mesh_curvature(m);
  return m;
}

struct Case {
  ColorBy color;
  bool wireframe;
  const char* name;
};

class RenderBackends : public ::testing::TestWithParam<Case> {};

TEST_P(RenderBackends, ShaderMatchesTheCpuReference) {
  MPUMESH_VULKAN_OR_SKIP(gpu);
  const TriangleMesh mesh = sphere_mesh();
  render::RenderOptions ro;
  ro.width = 320, ro.height = 240;
  ro.color = GetParam().color;
  ro.wireframe = GetParam().wireframe;
  ro.view = render::parse_view("iso");
  const render::RenderScene scene = render::build_scene(mesh, ro);
  const Image ref = render::rasterize_ref(scene);
  const Image vk1 = vk::render_mesh(gpu->context(), scene);
  const ImageDiff d = compare(ref, vk1);
  std::printf("%s: mean |diff| %.3f / 255, pixels off by > 16: %.4f%%\n", GetParam().name, d.mean_abs,
              100 * d.over_16);
  // The same triangles, transform and shading; they differ only where the two rasterisers
  // break ties on shared edges and in the last bit of rounding.
  EXPECT_LT(d.mean_abs, 0.5);
  EXPECT_LT(d.over_16, 0.005);
  // A second run gives the same bytes.
  const Image vk2 = vk::render_mesh(gpu->context(), scene);
  EXPECT_TRUE(vk1.rgba == vk2.rgba);
  test::expect_no_validation_messages(*gpu);
}

INSTANTIATE_TEST_SUITE_P(Colours, RenderBackends,
                         ::testing::Values(Case{ColorBy::kNone, false, "plain"},
                                           Case{ColorBy::kCurvature, true, "curvature_edges"},
                                           Case{ColorBy::kMinAngle, true, "min_angle_edges"},
                                           Case{ColorBy::kEdgeLength, false, "edge_length"}),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(Render, SphereFillsTheDiskTheCameraPredicts) {
  const TriangleMesh mesh = sphere_mesh();
  render::RenderOptions ro;
  ro.width = 400, ro.height = 300;
  ro.view = render::parse_view("front");
  CpuBackend cpu;
  const render::RenderScene scene = render::build_scene(mesh, ro);
  const Image img = vk::render_image(cpu, scene);
  ASSERT_EQ(img.width, 400);
  ASSERT_EQ(img.height, 300);
  // The centre projects inside, the radius from the pixel of a point on the rim.
  const Eigen::Vector2d c = scene.pixel_of({5, -3, 2});
  const double r_px = (scene.pixel_of({15, -3, 2}) - c).norm();
  EXPECT_GT(r_px, 100);  // fills most of the height (300 px less margins)
  EXPECT_FALSE(is_white(img.at(int(c.x()), int(c.y()))));
  EXPECT_TRUE(is_white(img.at(2, 2)));
  size_t on = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) on += !is_white(img.at(x, y));
  const double disk = std::numbers::pi * r_px * r_px;
  EXPECT_NEAR(double(on) / disk, 1.0, 0.03);  // the icosphere's polygon is a little smaller
  // Shaded: lit on the light's side (upper left), darker on the other.
  const uint8_t* lit = img.at(int(c.x() - 0.4 * r_px), int(c.y() - 0.4 * r_px));
  const uint8_t* dark = img.at(int(c.x() + 0.6 * r_px), int(c.y() + 0.6 * r_px));
  EXPECT_GT(int(lit[0]), int(dark[0]) + 40);
}

TEST(Render, ZoomFramesTheBallAndColourBarIsDrawn) {
  const TriangleMesh mesh = sphere_mesh();
  render::RenderOptions ro;
  ro.width = 400, ro.height = 300;
  ro.color = ColorBy::kMinAngle;
  ro.view = render::parse_view("front");
  ro.zoom = std::make_pair(Eigen::Vector3d(5, -13, 2), 3.0);  // the sphere's front point
  CpuBackend cpu;
  const render::RenderScene scene = render::build_scene(mesh, ro);
  const Image img = vk::render_image(cpu, scene);
  // 3 mm fill the picture: the whole drawing area is surface.
  EXPECT_GT(covered_fraction(img, 40, 80, 200, 260), 0.99);
  ASSERT_TRUE(scene.legend.shown);
  EXPECT_EQ(scene.legend.lo, 0);
  EXPECT_EQ(scene.legend.hi, 60);
  // The colour bar: viridis from dark purple (bottom) to yellow (top), in the right margin.
  int top = -1, bottom = -1;
  const int x = img.width - scene.legend.width + 16 + 11;
  for (int y = 0; y < img.height; ++y)
    if (!is_white(img.at(x, y))) (top < 0 ? top : bottom) = y, bottom = y;
  ASSERT_GT(bottom - top, 150);
  const uint8_t* hi = img.at(x, top + 3);
  const uint8_t* lo = img.at(x, bottom - 3);
  EXPECT_GT(hi[0], 200);  // yellow
  EXPECT_GT(hi[1], 200);
  EXPECT_LT(hi[2], 100);
  EXPECT_LT(lo[1], 40);  // purple
  EXPECT_GT(lo[2], 60);
}

TEST(Render, TextDrawsEveryStrokeOfItsLastCharacter) {
  // Each character alone and followed by spaces (which add no strokes): the same pixels.
  for (const char c : std::string("0123456789.-+eE^KmM()")) {
    Image alone(40, 40), padded(40, 40);
    const uint8_t ink[3] = {0, 0, 0};
    render::draw_text(alone, 4, 4, std::string(1, c), ink, 2);
    render::draw_text(padded, 4, 4, std::string(1, c) + "        ", ink, 2);
    EXPECT_EQ(alone.rgba, padded.rgba) << "'" << c << "' drawn alone lost strokes";
  }
}

TEST(Render, ColourBarLabelsFitInsideThePicture) {
  // Labels as wide as a curvature range gives ("-0.0629"): the strip widens for them, and
  // no label touches the picture's right edge.
  const TriangleMesh mesh = sphere_mesh();
  CpuBackend cpu;
  for (const auto& [w, h] : {std::pair{240, 180}, std::pair{400, 300}, std::pair{1024, 768}})
  for (const auto& [lo, hi] : {std::pair{-0.0629, 0.0629}, std::pair{0.0, 60.0}, std::pair{-123456.0, 0.00123}}) {
    render::RenderOptions ro;
    ro.width = w, ro.height = h;
    ro.color = ColorBy::kCurvature;
    ro.range = std::make_pair(lo, hi);
    const render::RenderScene scene = render::build_scene(mesh, ro);
    ASSERT_TRUE(scene.legend.shown);
    EXPECT_GE(scene.legend.width, 150);
    const Image img = vk::render_image(cpu, scene);
    int rightmost = -1;
    for (int y = 0; y < img.height; ++y)
      for (int x = img.width - scene.legend.width; x < img.width; ++x)
        if (!is_white(img.at(x, y))) rightmost = std::max(rightmost, x);
    EXPECT_GT(rightmost, img.width - scene.legend.width + 40) << "the labels are drawn";
    EXPECT_LT(rightmost, img.width - 8) << "a label runs into the picture's edge, range " << lo << ":" << hi << ", "
                                         << w << " x " << h;
  }
}

TEST(Render, CurvatureColoursFollowTheSign) {
  // A torus: K > 0 on the outer equator, < 0 on the inner; the diverging map puts red on
  // the outside and blue inside.
  TriangleMesh m;
  const int nu = 96, nv = 48;
  const double R = 20, r = 7;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * std::numbers::pi * i / nu, v = 2 * std::numbers::pi * j / nv;
      m.vertices.push_back({(R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)});
    }
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const uint32_t a = uint32_t(i * nv + j), b = uint32_t(((i + 1) % nu) * nv + j),
                     c = uint32_t(((i + 1) % nu) * nv + (j + 1) % nv), d = uint32_t(i * nv + (j + 1) % nv);
      m.triangles.push_back({a, b, c});
      m.triangles.push_back({a, c, d});
    }
  render::RenderOptions ro;
  ro.width = 400, ro.height = 300;
  ro.color = ColorBy::kCurvature;
  ro.view = render::parse_view("top");
  CpuBackend cpu;
  const render::RenderScene scene = render::build_scene(m, ro);
  EXPECT_NE(scene.legend.title.find("estimated from the mesh"), std::string::npos);
  const Image img = vk::render_image(cpu, scene);
  const Eigen::Vector2d outer = scene.pixel_of({R + r * 0.9, 0, r}), inner = scene.pixel_of({R - r * 0.9, 0, r});
  const uint8_t* po = img.at(int(outer.x()), int(outer.y()));
  const uint8_t* pi = img.at(int(inner.x()), int(inner.y()));
  EXPECT_GT(int(po[0]), int(po[2]) + 30) << "outer rim should be red";
  EXPECT_GT(int(pi[2]), int(pi[0]) + 30) << "inner rim should be blue";
}

// A complex coloured by label: its outer faces drawn, turned outward, each with the label
// it bounds; an inner interface not drawn; a mesh without labels refused.
TEST(Render, ComplexColouredByLabel) {
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 10}};
  // A tetrahedron whose three faces at the origin bound label 3 and whose far face bounds
  // label 5 (from the background, 0, into the label), and one inner face (3, 5).
  m.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}, {1, 2, 3}};
  m.face_labels = {{0, 3}, {0, 3}, {0, 3}, {0, 5}, {3, 5}};
  render::RenderOptions ro;
  ro.color = render::ColorBy::kLabel;
  ro.width = 160, ro.height = 120, ro.supersample = 1;
  EXPECT_EQ(render::parse_color("label"), render::ColorBy::kLabel);
  const render::RenderScene scene = render::build_scene(m, ro);
  ASSERT_EQ(scene.vertices.size(), 12u);
  EXPECT_EQ(scene.legend.lo, 3);
  EXPECT_EQ(scene.legend.hi, 5);
  EXPECT_EQ(scene.vertices[9].value, 5.0f);
  // Turned toward the background: the far face's normal points away from the origin.
  const Eigen::Vector3f a(scene.vertices[9].px, scene.vertices[9].py, scene.vertices[9].pz);
  const Eigen::Vector3f b(scene.vertices[10].px, scene.vertices[10].py, scene.vertices[10].pz);
  const Eigen::Vector3f c(scene.vertices[11].px, scene.vertices[11].py, scene.vertices[11].pz);
  EXPECT_GT((b - a).cross(c - a).dot(Eigen::Vector3f(1, 1, 1)), 0);
  m.face_labels.clear();
  EXPECT_THROW(render::build_scene(m, ro), InputError);
}

TEST(Render, BadOptionsAreRefused) {
  EXPECT_THROW(render::parse_view("sideways"), InputError);
  EXPECT_THROW(render::parse_view("0,0,0"), InputError);
  EXPECT_THROW(render::parse_zoom("1,2,3"), InputError);
  EXPECT_THROW(render::parse_zoom("1,2,3,-1"), InputError);
  EXPECT_THROW(render::parse_size("0x100"), InputError);
  EXPECT_THROW(render::parse_size("640"), InputError);
  EXPECT_EQ(render::parse_size("640x480"), std::make_pair(640, 480));
  EXPECT_THROW(render::parse_color("rainbow"), InputError);
  EXPECT_THROW(render::build_scene(TriangleMesh{}, {}), InputError);
}

}  // namespace
}  // namespace mpumesh
