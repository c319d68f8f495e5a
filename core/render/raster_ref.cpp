#include "render/raster_ref.h"

#include <algorithm>
#include <cmath>

namespace mpumesh::render {
namespace {

using Eigen::Vector3f;

float smoothstep(float e0, float e1, float x) {
  const float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

// lib/render_shading.glsl, shade().
Vector3f shade(const Vector3f& base, const Vector3f& normal, const abi::vec4& light, const abi::vec4& eye,
               const Vector3f& bary, const Vector3f& fw) {
  const Vector3f L(light.x, light.y, light.z), E(eye.x, eye.y, eye.z);
  Vector3f n = normal.normalized();
  if (n.dot(E) < 0.0f) n = -n;
  const float diffuse = std::max(n.dot(L), 0.0f);
  const Vector3f h = (L + E).normalized();
  const float spec = std::pow(std::max(n.dot(h), 0.0f), 32.0f);
  Vector3f c = base * (0.28f + 0.72f * diffuse) + Vector3f::Constant(0.12f * spec);
  if (light.w > 0.5f) {
    const Vector3f d = bary.cwiseQuotient(fw.cwiseMax(Vector3f::Constant(1e-6f)));
    const float m = d.minCoeff();
    const float line = 1.0f - smoothstep(eye.w - 0.5f, eye.w + 0.5f, m);
    c = c + (Vector3f(0.08f, 0.08f, 0.10f) - c) * (0.85f * line);
  }
  return c.cwiseMax(0.0f).cwiseMin(1.0f);
}

}  // namespace

Image rasterize_ref(const RenderScene& sc) {
  const int W = sc.width, H = sc.height;
  Image img(W, H, 255);
  std::vector<float> depth(size_t(W) * size_t(H), 1.0f);
  const abi::RenderPush& pc = sc.push;
  auto transform = [&](const abi::RenderVertex& v, float out[3]) {
    float clip[4];
    for (int r = 0; r < 4; ++r) {
      clip[r] = (&pc.mvp[0].x)[r] * v.px + (&pc.mvp[1].x)[r] * v.py + (&pc.mvp[2].x)[r] * v.pz + (&pc.mvp[3].x)[r];
    }
    out[0] = (clip[0] / clip[3] + 1.0f) * 0.5f * float(W);
    out[1] = (clip[1] / clip[3] + 1.0f) * 0.5f * float(H);
    out[2] = clip[2] / clip[3];
  };
  const int map = int(pc.range.z);
  for (size_t t = 0; t + 2 < sc.vertices.size(); t += 3) {
    const abi::RenderVertex* v = &sc.vertices[t];
    float s[3][3];
    for (int c = 0; c < 3; ++c) transform(v[c], s[c]);
    const float area = (s[1][0] - s[0][0]) * (s[2][1] - s[0][1]) - (s[2][0] - s[0][0]) * (s[1][1] - s[0][1]);
    if (!(std::abs(area) > 0.0f)) continue;
    // λ_c(x, y) = edge function opposite corner c / area: linear, so its screen rates are
    // constant over the triangle (what dFdx, dFdy give the shader).
    Vector3f ddx, ddy;
    for (int c = 0; c < 3; ++c) {
      const float* a = s[(c + 1) % 3];
      const float* b = s[(c + 2) % 3];
      ddx[c] = (a[1] - b[1]) / area;
      ddy[c] = (b[0] - a[0]) / area;
    }
    const Vector3f fw = ddx.cwiseAbs() + ddy.cwiseAbs();
    const int x0 = std::max(0, int(std::floor(std::min({s[0][0], s[1][0], s[2][0]}) - 0.5f)));
    const int x1 = std::min(W - 1, int(std::ceil(std::max({s[0][0], s[1][0], s[2][0]}) - 0.5f)));
    const int y0 = std::max(0, int(std::floor(std::min({s[0][1], s[1][1], s[2][1]}) - 0.5f)));
    const int y1 = std::min(H - 1, int(std::ceil(std::max({s[0][1], s[1][1], s[2][1]}) - 0.5f)));
    for (int py = y0; py <= y1; ++py)
      for (int px = x0; px <= x1; ++px) {
        const float x = float(px) + 0.5f, y = float(py) + 0.5f;
        Vector3f l;
        for (int c = 0; c < 3; ++c) {
          const float* a = s[(c + 1) % 3];
          const float* b = s[(c + 2) % 3];
          l[c] = ((b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0])) / area;
        }
        if (l.minCoeff() < 0.0f) continue;
        const float z = l[0] * s[0][2] + l[1] * s[1][2] + l[2] * s[2][2];
        float& dz = depth[size_t(py) * size_t(W) + size_t(px)];
        if (!(z < dz) || z < 0.0f) continue;
        dz = z;
        Vector3f n = Vector3f::Zero();
        float value = 0;
        for (int c = 0; c < 3; ++c) {
          n += l[c] * Vector3f(v[c].nx, v[c].ny, v[c].nz);
          value += l[c] * v[c].value;
        }
        const float tt = map == RENDER_CMAP_NONE ? 0.0f : (value - pc.range.x) / (pc.range.y - pc.range.x);
        const Vector3f col = shade(colormap(map, tt), n, pc.light, pc.eye, l, fw);
        uint8_t* p = img.at(px, py);
        for (int c = 0; c < 3; ++c) p[c] = uint8_t(std::lround(col[c] * 255.0f));
        p[3] = 255;
      }
  }
  return img;
}

Image finish(const Image& drawing, const RenderScene& scene) {
  Image out = downsample(drawing, scene.supersample);
  draw_legend(out, scene);
  return out;
}

}  // namespace mpumesh::render
