#include "render/image.h"

#include <algorithm>

#include "common/error.h"
#include "io/atomic_file.h"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#include <stb/stb_image_write.h>
#include <stb/stb_easy_font.h>

namespace mpumesh::render {

Image downsample(const Image& in, int factor) {
  MPUMESH_ASSERT(factor >= 1 && in.width % factor == 0 && in.height % factor == 0, "downsample factor");
  Image out(in.width / factor, in.height / factor);
  const int n = factor * factor;
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < 4; ++c) {
        int sum = 0;
        for (int dy = 0; dy < factor; ++dy)
          for (int dx = 0; dx < factor; ++dx) sum += in.at(x * factor + dx, y * factor + dy)[c];
        out.at(x, y)[c] = uint8_t((sum + n / 2) / n);
      }
  return out;
}

void fill_rect(Image& img, int x0, int y0, int x1, int y1, const uint8_t rgb[3]) {
  x0 = std::max(x0, 0), y0 = std::max(y0, 0);
  x1 = std::min(x1, img.width), y1 = std::min(y1, img.height);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      uint8_t* p = img.at(x, y);
      p[0] = rgb[0], p[1] = rgb[1], p[2] = rgb[2], p[3] = 255;
    }
}

int text_width(const std::string& text, int scale) {
  return stb_easy_font_width(const_cast<char*>(text.c_str())) * scale;
}

int draw_text(Image& img, int x, int y, const std::string& text, const uint8_t rgb[3], int scale) {
  // stb_easy_font emits axis-aligned quads, 4 vertices of 16 bytes (x, y, z, colour), and
  // stops when the buffer is full: room for 16 quads a character (its glyphs take up to
  // 7; at about 300 bytes a character the last glyph of a short label lost its strokes,
  // a "0" drawn as a "C").
  std::vector<char> buf((text.size() + 1) * 16 * 64);
  const int quads = stb_easy_font_print(0, 0, const_cast<char*>(text.c_str()), nullptr, buf.data(), int(buf.size()));
  for (int q = 0; q < quads; ++q) {
    const float* v0 = reinterpret_cast<const float*>(buf.data() + size_t(q) * 64);
    const float* v2 = reinterpret_cast<const float*>(buf.data() + size_t(q) * 64 + 32);
    fill_rect(img, x + int(v0[0]) * scale, y + int(v0[1]) * scale, x + int(v2[0]) * scale, y + int(v2[1]) * scale,
              rgb);
  }
  return text_width(text, scale);
}

std::string encode_png(const Image& img) {
  std::string out;
  auto sink = [](void* ctx, void* data, int size) {
    static_cast<std::string*>(ctx)->append(static_cast<const char*>(data), size_t(size));
  };
  if (!stbi_write_png_to_func(sink, &out, img.width, img.height, 4, img.rgba.data(), img.width * 4))
    throw std::runtime_error("PNG encoding failed");
  return out;
}

void write_png(const Image& img, const std::string& path) { write_file_atomically(encode_png(img), path); }

}  // namespace mpumesh::render
