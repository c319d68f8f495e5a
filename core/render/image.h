// An 8-bit RGBA image, row 0 at the top, and its PNG encoding (stb_image_write).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace mpumesh::render {

struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;  // width * height * 4
  Image() = default;
  Image(int w, int h, uint8_t fill = 255) : width(w), height(h), rgba(size_t(w) * size_t(h) * 4, fill) {}
  uint8_t* at(int x, int y) { return &rgba[(size_t(y) * size_t(width) + size_t(x)) * 4]; }
  const uint8_t* at(int x, int y) const { return &rgba[(size_t(y) * size_t(width) + size_t(x)) * 4]; }
};

// Each output pixel the mean of a factor x factor block (the renderers draw at a multiple
// of the asked size: this is their anti-aliasing).
Image downsample(const Image& in, int factor);

// Fills the rectangle [x0, x1) x [y0, y1), clipped to the image.
void fill_rect(Image& img, int x0, int y0, int x1, int y1, const uint8_t rgb[3]);

// ASCII text (stb_easy_font), top-left at (x, y), each font pixel drawn `scale` pixels
// wide. Returns the width drawn, in pixels.
int draw_text(Image& img, int x, int y, const std::string& text, const uint8_t rgb[3], int scale);
int text_width(const std::string& text, int scale);

std::string encode_png(const Image& img);
// Through AtomicFile: a failed write leaves no file and never a half-written one.
void write_png(const Image& img, const std::string& path);

}  // namespace mpumesh::render
