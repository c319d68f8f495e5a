#include "render/render_scene.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/error.h"
#include "common/option_names.h"
#include "mesh/quality.h"
#include "mesh/surface_attributes.h"

namespace mpumesh::render {
namespace {

constexpr int kMargin = 16;
constexpr int kLegendWidth = 150;
constexpr int kTextScale = 2;
constexpr int kLineHeight = 20;
// The colour bar: its left edge this far inside the legend strip, its width, and the gap
// from its ticks to their labels.
constexpr int kBarInset = 16, kBarWidth = 22, kLabelGap = 10;

// The colour bar's five tick labels, bottom to top.
std::vector<std::string> tick_labels(const Legend& lg) {
  std::vector<std::string> out;
  for (int i = 0; i <= 4; ++i) {
    const double v = lg.lo + i / 4.0 * (lg.hi - lg.lo);
    out.push_back(fmt::format("{:.3g}", std::abs(v) < 1e-12 ? 0.0 : v));
  }
  return out;
}

// A line of text in at most `width` pixels: at kTextScale, else at half that, else cut
// short with "..." at half.
std::pair<std::string, int> fitted(const std::string& text, int width) {
  if (text_width(text, kTextScale) <= width) return {text, kTextScale};
  std::string t = text;
  while (!t.empty() && text_width(t == text ? t : t + "...", 1) > width) t.pop_back();
  return {t == text ? t : t + "...", 1};
}

// The legend strip: kLegendWidth, or wider when a label needs it (with a margin after it).
int legend_width(const Legend& lg) {
  int widest = 0;
  for (const std::string& t : tick_labels(lg)) widest = std::max(widest, text_width(t, kTextScale));
  return std::max(kLegendWidth, kBarInset + kBarWidth + kLabelGap + widest + kMargin);
}

std::vector<double> split_numbers(const std::string& s, char sep, const std::string& what) {
  std::vector<double> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, sep)) {
    try {
      size_t used = 0;
      out.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw InputError(what + ": '" + s + "' is not a list of numbers");
    }
    if (!std::isfinite(out.back())) throw InputError(what + ": '" + s + "' holds a value that is not finite");
  }
  return out;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  const size_t k = std::min(v.size() - 1, size_t(q * double(v.size())));
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
  return v[k];
}

}  // namespace

Eigen::Vector3d parse_view(const std::string& s) {
  if (s == "iso") return Eigen::Vector3d(1, -1, 1).normalized();
  if (s == "front") return {0, -1, 0};
  if (s == "side") return {1, 0, 0};
  if (s == "top") return {0, 0, 1};
  const std::vector<double> v = split_numbers(s, ',', option_ref("view"));
  if (v.size() != 3) throw InputError(option_ref("view") + ": '" + s + "' is neither iso, front, side, top nor x,y,z");
  const Eigen::Vector3d d(v[0], v[1], v[2]);
  if (!(d.norm() > 0)) throw InputError(option_ref("view") + ": the direction " + s + " has zero length");
  return d.normalized();
}

std::pair<Eigen::Vector3d, double> parse_zoom(const std::string& s) {
  const std::vector<double> v = split_numbers(s, ',', option_ref("zoom"));
  if (v.size() != 4) throw InputError(option_ref("zoom") + ": '" + s + "' is not x,y,z,r (mm)");
  if (!(v[3] > 0)) throw InputError(option_ref("zoom") + ": the radius must be positive, got " + fmt::format("{}", v[3]));
  return {Eigen::Vector3d(v[0], v[1], v[2]), v[3]};
}

std::pair<int, int> parse_size(const std::string& s) {
  std::string t = s;
  const std::string times = "\u00d7";
  if (const size_t at = t.find(times); at != std::string::npos) t = s.substr(0, at) + 'x' + s.substr(at + times.size());
  const std::vector<double> v = split_numbers(t, 'x', option_ref("size"));
  if (v.size() != 2 || v[0] != std::floor(v[0]) || v[1] != std::floor(v[1]) || v[0] < 64 || v[1] < 64 ||
      v[0] > 8192 || v[1] > 8192)
    throw InputError(option_ref("size") + ": '" + s + "' is not WxH with whole numbers from 64 to 8192");
  return {int(v[0]), int(v[1])};
}

ColorBy parse_color(const std::string& s) {
  if (s == "none") return ColorBy::kNone;
  if (s == "curvature") return ColorBy::kCurvature;
  if (s == "min-angle") return ColorBy::kMinAngle;
  if (s == "edge-length") return ColorBy::kEdgeLength;
  if (s == "label") return ColorBy::kLabel;
  throw InputError(option_ref("color") + ": '" + s + "' is none of none, curvature, min-angle, edge-length, label");
}

Eigen::Vector3f colormap(int map, float t) {
  // Line for line lib/render_shading.glsl.
  t = std::clamp(t, 0.0f, 1.0f);
  if (map == RENDER_CMAP_NONE) return {0.90f, 0.86f, 0.78f};
  if (map == RENDER_CMAP_SEQUENTIAL) {
    const Eigen::Vector3f c0(0.2777273272234177f, 0.005407344544966578f, 0.3340998053353061f);
    const Eigen::Vector3f c1(0.1050930431085774f, 1.404613529898575f, 1.384590162594685f);
    const Eigen::Vector3f c2(-0.3308618287255563f, 0.214847559468213f, 0.09509516302823659f);
    const Eigen::Vector3f c3(-4.634230498983486f, -5.799100973351585f, -19.33244095627987f);
    const Eigen::Vector3f c4(6.228269936347081f, 14.17993336680509f, 56.69055260068105f);
    const Eigen::Vector3f c5(4.776384997670288f, -13.74514537774601f, -65.35303263337234f);
    const Eigen::Vector3f c6(-5.435455855934631f, 4.645852612178535f, 26.3124352495832f);
    return c0 + t * (c1 + t * (c2 + t * (c3 + t * (c4 + t * (c5 + t * c6)))));
  }
  const Eigen::Vector3f lo(0.230f, 0.299f, 0.754f), mid(0.865f, 0.865f, 0.865f), hi(0.706f, 0.016f, 0.150f);
  return t < 0.5f ? Eigen::Vector3f(lo + (mid - lo) * (t * 2.0f)) : Eigen::Vector3f(mid + (hi - mid) * (t * 2.0f - 1.0f));
}

Eigen::Vector2d RenderScene::pixel_of(const Eigen::Vector3d& p) const {
  const Eigen::Vector4d c = clip_from_world * (p - centre).homogeneous();
  return {(c.x() + 1) / 2 * (width / supersample), (c.y() + 1) / 2 * (height / supersample)};
}

namespace {

// The value at each triangle's corners that colours it, and the colour bar's range.
std::vector<float> corner_values(const TriangleMesh& mesh, const RenderOptions& opt, const std::vector<double>& gauss,
                                 bool mesh_curvature, Legend& lg) {
  std::vector<float> corner(mesh.triangles.size() * 3, 0.0f);
  std::vector<double> sample;
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto& t = mesh.triangles[f];
    const Eigen::Vector3d p[3] = {mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]};
    if (opt.color == ColorBy::kCurvature) {
      for (int c = 0; c < 3; ++c) corner[f * 3 + size_t(c)] = float(gauss[t[size_t(c)]]);
    } else if (opt.color == ColorBy::kMinAngle) {
      const double m = triangle_min_angle_deg(p[0], p[1], p[2]);
      for (int c = 0; c < 3; ++c) corner[f * 3 + size_t(c)] = float(m);
    } else if (opt.color == ColorBy::kEdgeLength) {
      const double e = ((p[1] - p[0]).norm() + (p[2] - p[1]).norm() + (p[0] - p[2]).norm()) / 3;
      for (int c = 0; c < 3; ++c) corner[f * 3 + size_t(c)] = float(e);
      sample.push_back(e);
    } else if (opt.color == ColorBy::kLabel) {
      const double l = mesh.face_labels[f][1];
      for (int c = 0; c < 3; ++c) corner[f * 3 + size_t(c)] = float(l);
      sample.push_back(l);
    }
  }
  if (opt.color == ColorBy::kCurvature) {
    for (double k : gauss) sample.push_back(std::abs(k));
    const double q = std::max(percentile(sample, 0.95), 1e-9);
    lg = {true,
          std::string("Gaussian curvature K (1/mm^2) at the spacing") + (mesh_curvature ? "" : ", estimated from the mesh"),
          -q, q, RENDER_CMAP_DIVERGING};
  } else if (opt.color == ColorBy::kMinAngle) {
    lg = {true, "smallest angle of each triangle (degrees)", 0, 60, RENDER_CMAP_SEQUENTIAL};
  } else if (opt.color == ColorBy::kEdgeLength) {
    double lo = percentile(sample, 0.01), hi = percentile(sample, 0.99);
    if (!(hi > lo)) hi = lo + 1e-6;
    lg = {true, "mean edge length of each triangle (mm)", lo, hi, RENDER_CMAP_SEQUENTIAL};
  } else if (opt.color == ColorBy::kLabel) {
    const double lo = *std::min_element(sample.begin(), sample.end());
    const double hi = std::max(*std::max_element(sample.begin(), sample.end()), lo + 1);
    lg = {true, "label of the region each outer face bounds", lo, hi, RENDER_CMAP_SEQUENTIAL};
  }
  if (opt.range && lg.shown) lg.lo = opt.range->first, lg.hi = opt.range->second;
  return corner;
}

// The camera: E toward the viewer, R to the right, U up in the picture; the mesh's extent
// across the picture (a, b) and along the view (s); the picture's layout, titles on top
// and the colour bar on the right; and from them the clip transform and the push constants.
void place_camera(const TriangleMesh& mesh, const RenderOptions& opt, RenderScene& sc) {
  Legend& lg = sc.legend;
  const Eigen::Vector3d E = opt.view.normalized();
  const Eigen::Vector3d up0 = std::abs(E.z()) > 0.99 ? Eigen::Vector3d(0, -1, 0) : Eigen::Vector3d(0, 0, 1);
  const Eigen::Vector3d R = up0.cross(E).normalized(), U = E.cross(R);
  Eigen::Vector3d lo_box = mesh.vertices[0], hi_box = mesh.vertices[0];
  for (const auto& v : mesh.vertices) lo_box = lo_box.cwiseMin(v), hi_box = hi_box.cwiseMax(v);
  sc.centre = opt.zoom ? opt.zoom->first : Eigen::Vector3d((lo_box + hi_box) / 2);
  double amin = 1e300, amax = -1e300, bmin = 1e300, bmax = -1e300, smin = 1e300, smax = -1e300;
  for (const auto& v : mesh.vertices) {
    const Eigen::Vector3d d = v - sc.centre;
    amin = std::min(amin, d.dot(R)), amax = std::max(amax, d.dot(R));
    bmin = std::min(bmin, d.dot(U)), bmax = std::max(bmax, d.dot(U));
    smin = std::min(smin, d.dot(E)), smax = std::max(smax, d.dot(E));
  }
  if (opt.zoom) amin = bmin = -opt.zoom->second, amax = bmax = opt.zoom->second;
  const double pad = 0.01 * std::max(smax - smin, 1e-6);
  smin -= pad, smax += pad;
  const int W = opt.width, H = opt.height;
  const int lines = int(!opt.title.empty()) + int(lg.shown);
  const int top = lines * kLineHeight + (lines ? 8 : 0);
  if (lg.shown) lg.width = legend_width(lg);
  const int right = lg.shown ? lg.width : 0;
  const double avail_w = std::max(W - right - 2 * kMargin, 8), avail_h = std::max(H - top - 2 * kMargin, 8);
  const double k = std::min(avail_w / std::max(amax - amin, 1e-9), avail_h / std::max(bmax - bmin, 1e-9));
  const double cx = kMargin + avail_w / 2, cy = top + kMargin + avail_h / 2;
  const double amid = (amin + amax) / 2, bmid = (bmin + bmax) / 2;
  Eigen::Matrix4d M = Eigen::Matrix4d::Zero();
  M.block<1, 3>(0, 0) = (2 * k / W) * R.transpose();
  M(0, 3) = 2 * (cx - k * amid) / W - 1;
  M.block<1, 3>(1, 0) = -(2 * k / H) * U.transpose();
  M(1, 3) = 2 * (cy + k * bmid) / H - 1;
  M.block<1, 3>(2, 0) = -(1 / (smax - smin)) * E.transpose();
  M(2, 3) = smax / (smax - smin);
  M(3, 3) = 1;
  sc.clip_from_world = M;
  for (int c = 0; c < 4; ++c) sc.push.mvp[c] = {float(M(0, c)), float(M(1, c)), float(M(2, c)), float(M(3, c))};
  const Eigen::Vector3d L = (E + 0.5 * U - 0.35 * R).normalized();
  sc.push.light = {float(L.x()), float(L.y()), float(L.z()), opt.wireframe ? 1.0f : 0.0f};
  sc.push.eye = {float(E.x()), float(E.y()), float(E.z()), 0.55f * float(opt.supersample)};
  sc.push.range = {float(lg.lo), float(lg.hi), float(lg.colormap), 0.0f};
}

}  // namespace

namespace {

// A complex's faces against the background, turned toward it (a complex's faces point
// from the lower label into the higher), with their labels.
TriangleMesh outer_faces(const TriangleMesh& complex) {
  if (complex.face_labels.size() != complex.triangles.size())
    throw InputError(option_ref("color") + " label: the mesh's faces carry no label_a, label_b (not a complex)");
  TriangleMesh out;
  out.vertices = complex.vertices;
  for (size_t f = 0; f < complex.triangles.size(); ++f) {
    if (complex.face_labels[f][0] != 0) continue;
    const auto& t = complex.triangles[f];
    out.triangles.push_back({t[0], t[2], t[1]});
    out.face_labels.push_back(complex.face_labels[f]);
  }
  return out;
}

}  // namespace

RenderScene build_scene(const TriangleMesh& input, const RenderOptions& opt) {
  TriangleMesh outer;
  if (opt.color == ColorBy::kLabel) outer = outer_faces(input);
  const TriangleMesh& mesh = opt.color == ColorBy::kLabel ? outer : input;
  if (mesh.triangles.empty()) throw InputError("the mesh has no triangles to render");
  MPUMESH_ASSERT(opt.supersample >= 1 && opt.width > 0 && opt.height > 0, "render size");
  RenderScene sc;
  sc.supersample = opt.supersample;
  sc.width = opt.width * opt.supersample;
  sc.height = opt.height * opt.supersample;
  sc.title = opt.title;
  // Per-vertex normals and curvature: the mesh's own, or estimated.
  TriangleMesh est;
  const bool have_normals = mesh.normals.size() == mesh.vertices.size();
  const bool have_curv = mesh.curvature.size() == mesh.vertices.size();
  const bool need_estimate = !have_normals || (opt.color == ColorBy::kCurvature && !have_curv);
  if (need_estimate) {
    est.vertices = mesh.vertices;
    est.triangles = mesh.triangles;
    estimate_mesh_curvature(est);
  }
  const auto& normals = have_normals ? mesh.normals : est.normals;
  // K at the mesh's own scale (surface_attributes.h): the bends its spacing follows.
  std::vector<double> gauss;
  if (opt.color == ColorBy::kCurvature) gauss = gauss_at_mesh_scale(have_curv ? mesh : est);
  const std::vector<float> corner = corner_values(mesh, opt, gauss, have_curv, sc.legend);
  place_camera(mesh, opt, sc);
  sc.vertices.resize(mesh.triangles.size() * 3);
  for (size_t f = 0; f < mesh.triangles.size(); ++f)
    for (int c = 0; c < 3; ++c) {
      const uint32_t i = mesh.triangles[f][size_t(c)];
      const Eigen::Vector3d d = mesh.vertices[i] - sc.centre;
      const Eigen::Vector3f& n = normals[i];
      sc.vertices[f * 3 + size_t(c)] = {float(d.x()), float(d.y()), float(d.z()), n.x(), n.y(), n.z(),
                                        corner[f * 3 + size_t(c)]};
    }
  return sc;
}

void draw_legend(Image& img, const RenderScene& sc) {
  const uint8_t ink[3] = {20, 20, 24}, paper[3] = {255, 255, 255};
  // A zoomed surface runs under the margins: clear them first.
  const int lines = int(!sc.title.empty()) + int(sc.legend.shown);
  if (lines) fill_rect(img, 0, 0, img.width, lines * kLineHeight + 8, paper);
  if (sc.legend.shown) fill_rect(img, img.width - sc.legend.width, 0, img.width, img.height, paper);
  int y = 8;
  const int line_width = img.width - 2 * kMargin;
  if (!sc.title.empty()) {
    const auto [text, scale] = fitted(sc.title, line_width);
    draw_text(img, kMargin, y, text, ink, scale), y += kLineHeight;
  }
  const Legend& lg = sc.legend;
  if (!lg.shown) return;
  {
    const auto [text, scale] = fitted(lg.title, line_width);
    draw_text(img, kMargin, y, text, ink, scale);
  }
  const int x0 = img.width - lg.width + kBarInset, x1 = x0 + kBarWidth;
  const int y0 = y + kLineHeight + 16, y1 = img.height - kMargin - 8;
  if (y1 - y0 < 20) return;
  fill_rect(img, x0 - 1, y0 - 1, x1 + 1, y1 + 1, ink);
  for (int yy = y0; yy < y1; ++yy) {
    const float t = 1.0f - float(yy - y0) / float(y1 - 1 - y0);
    const Eigen::Vector3f c = colormap(lg.colormap, t);
    const uint8_t rgb[3] = {uint8_t(std::lround(std::clamp(c.x(), 0.f, 1.f) * 255)),
                            uint8_t(std::lround(std::clamp(c.y(), 0.f, 1.f) * 255)),
                            uint8_t(std::lround(std::clamp(c.z(), 0.f, 1.f) * 255))};
    fill_rect(img, x0, yy, x1, yy + 1, rgb);
  }
  const std::vector<std::string> labels = tick_labels(lg);
  for (int i = 0; i <= 4; ++i) {
    const double t = i / 4.0;
    const int yy = y1 - 1 - int(std::lround(t * (y1 - 1 - y0)));
    fill_rect(img, x1, yy, x1 + 6, yy + 1, ink);
    draw_text(img, x1 + kLabelGap, yy - 6, labels[size_t(i)], ink, kTextScale);
  }
}

}  // namespace mpumesh::render
