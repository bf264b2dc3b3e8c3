// The picture's raster back end: a canvas with coverage anti-aliasing that
// draws the display list, and the PNG encoder (zlib deflate, one IDAT chunk).
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "io/picture.hpp"
#include "io/picture_draw.hpp"

namespace granule::io::picture_detail {

namespace {

// ---- raster back end ----

class Canvas {
 public:
  Canvas(int w, int h) : w_(w), h_(h), rgb_(static_cast<std::size_t>(w) * h * 3, 255) {}
  void set_clip(double x0, double y0, double x1, double y1) {
    cx0_ = std::max(0, static_cast<int>(std::floor(x0)));
    cy0_ = std::max(0, static_cast<int>(std::floor(y0)));
    cx1_ = std::min(w_, static_cast<int>(std::ceil(x1)));
    cy1_ = std::min(h_, static_cast<int>(std::ceil(y1)));
  }
  void no_clip() { set_clip(0, 0, w_, h_); }

  void blend(int x, int y, const Rgb& c, double a) {
    if (x < cx0_ || y < cy0_ || x >= cx1_ || y >= cy1_ || !(a > 0)) return;
    a = std::min(a, 1.0);
    std::uint8_t* p = &rgb_[(static_cast<std::size_t>(y) * w_ + x) * 3];
    p[0] = static_cast<std::uint8_t>(std::lround(p[0] + (c.r - p[0]) * a));
    p[1] = static_cast<std::uint8_t>(std::lround(p[1] + (c.g - p[1]) * a));
    p[2] = static_cast<std::uint8_t>(std::lround(p[2] + (c.b - p[2]) * a));
  }

  // Pixels whose centres may be within `reach` of the box, clipped.
  template <typename F>
  void each_pixel(double x0, double y0, double x1, double y1, double reach, F&& f) {
    int ix0 = std::max(cx0_, static_cast<int>(std::floor(std::min(x0, x1) - reach)));
    int iy0 = std::max(cy0_, static_cast<int>(std::floor(std::min(y0, y1) - reach)));
    int ix1 = std::min(cx1_ - 1, static_cast<int>(std::ceil(std::max(x0, x1) + reach)));
    int iy1 = std::min(cy1_ - 1, static_cast<int>(std::ceil(std::max(y0, y1) + reach)));
    for (int y = iy0; y <= iy1; ++y)
      for (int x = ix0; x <= ix1; ++x) f(x, y, x + 0.5, y + 0.5);
  }

  // Coverage of a pixel by a shape whose edge is at signed distance `inside`
  // (> 0 inside) from the pixel centre: a one-pixel linear ramp.
  static double coverage(double inside) { return std::clamp(inside + 0.5, 0.0, 1.0); }

  void disc(const Prim& p) {
    const double r = p.radius;
    each_pixel(p.x0, p.y0, p.x0, p.y0, r + 1, [&](int x, int y, double px, double py) {
      double d = std::hypot(px - p.x0, py - p.y0);
      double a = coverage(r - d);
      if (a <= 0) return;
      Rgb c = p.colour;
      if (p.edge_width > 0) {
        double rim = coverage(d - (r - p.edge_width));
        c = {c.r + (p.edge.r - c.r) * rim, c.g + (p.edge.g - c.g) * rim,
             c.b + (p.edge.b - c.b) * rim};
      }
      blend(x, y, c, a);
    });
  }

  void ring(const Prim& p) {
    const double half = p.width / 2;
    each_pixel(p.x0, p.y0, p.x0, p.y0, p.radius + half + 1,
               [&](int x, int y, double px, double py) {
                 double d = std::hypot(px - p.x0, py - p.y0);
                 blend(x, y, p.colour, coverage(half - std::abs(d - p.radius)));
               });
  }

  void line(const Prim& p) {
    const double half = p.width / 2;
    const double dx = p.x1 - p.x0, dy = p.y1 - p.y0;
    const double len2 = dx * dx + dy * dy;
    each_pixel(p.x0, p.y0, p.x1, p.y1, half + 1, [&](int x, int y, double px, double py) {
      double t = len2 > 0 ? ((px - p.x0) * dx + (py - p.y0) * dy) / len2 : 0;
      t = std::clamp(t, 0.0, 1.0);
      double d = std::hypot(px - (p.x0 + t * dx), py - (p.y0 + t * dy));
      blend(x, y, p.colour, coverage(half - d));
    });
  }

  void rect(const Prim& p) {
    each_pixel(p.x0, p.y0, p.x1, p.y1, 0, [&](int x, int y, double px, double py) {
      double inside = std::min({px - p.x0, p.x1 - px, py - p.y0, p.y1 - py});
      blend(x, y, p.colour, coverage(inside));
    });
  }

  // Text with its top-left corner at (x0, y0); each font pixel is size x size.
  void text(const Prim& p) {
    const int s = std::max(1, static_cast<int>(std::lround(p.size)));
    int pen = static_cast<int>(std::lround(p.x0));
    const int top = static_cast<int>(std::lround(p.y0));
    for (char c : p.label) {
      const Glyph& g = glyph(c);
      for (int row = 0; row < 7; ++row)
        for (int col = 0; col < 5; ++col)
          if (g.rows[row][col] == '#')
            for (int dy = 0; dy < s; ++dy)
              for (int dx = 0; dx < s; ++dx)
                blend(pen + col * s + dx, top + row * s + dy, p.colour, 1);
      pen += 6 * s;
    }
  }

  const std::vector<std::uint8_t>& pixels() const { return rgb_; }

 private:
  int w_, h_;
  std::vector<std::uint8_t> rgb_;
  int cx0_ = 0, cy0_ = 0, cx1_ = 0, cy1_ = 0;
};

}  // namespace

std::vector<std::uint8_t> rasterise(const Layout& layout) {
  Canvas canvas(layout.width, layout.height);
  for (const Prim& p : layout.prims) {
    if (p.clipped)
      canvas.set_clip(layout.plot_x0, layout.plot_y0, layout.plot_x1, layout.plot_y1);
    else
      canvas.no_clip();
    switch (p.kind) {
      case Prim::disc:
        canvas.disc(p);
        break;
      case Prim::ring:
        canvas.ring(p);
        break;
      case Prim::line:
        canvas.line(p);
        break;
      case Prim::rect:
        canvas.rect(p);
        break;
      case Prim::text:
        canvas.text(p);
        break;
    }
  }
  return canvas.pixels();
}

}  // namespace granule::io::picture_detail

namespace granule::io {

namespace {

void append_chunk(std::vector<std::uint8_t>& out, const char* type,
                  const std::vector<std::uint8_t>& data) {
  auto put32 = [&](std::uint32_t v) {
    for (int k = 3; k >= 0; --k) out.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
  };
  put32(static_cast<std::uint32_t>(data.size()));
  const std::size_t start = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  // The CRC covers the chunk type and data (PNG specification, 5.3).
  uLong crc = crc32(0L, Z_NULL, 0);
  crc = crc32(crc, out.data() + start, static_cast<uInt>(out.size() - start));
  put32(static_cast<std::uint32_t>(crc));
}

}  // namespace

std::vector<std::uint8_t> encode_png(int width, int height, const std::vector<std::uint8_t>& rgb) {
  if (width <= 0 || height <= 0 ||
      rgb.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3)
    throw std::runtime_error("encode_png: the pixel buffer does not match the image size");
  // Each row starts with its filter type (0: none); deflate does the rest.
  const std::size_t row = static_cast<std::size_t>(width) * 3;
  std::vector<std::uint8_t> raw;
  raw.reserve((row + 1) * height);
  for (int y = 0; y < height; ++y) {
    raw.push_back(0);
    raw.insert(raw.end(), rgb.begin() + y * row, rgb.begin() + (y + 1) * row);
  }
  uLongf packed_size = compressBound(static_cast<uLong>(raw.size()));
  std::vector<std::uint8_t> packed(packed_size);
  if (compress2(packed.data(), &packed_size, raw.data(), static_cast<uLong>(raw.size()), 6) != Z_OK)
    throw std::runtime_error("encode_png: zlib could not compress the image");
  packed.resize(packed_size);

  std::vector<std::uint8_t> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::vector<std::uint8_t> header(13, 0);
  for (int k = 0; k < 4; ++k) {
    header[k] = static_cast<std::uint8_t>(static_cast<std::uint32_t>(width) >> (24 - 8 * k));
    header[4 + k] = static_cast<std::uint8_t>(static_cast<std::uint32_t>(height) >> (24 - 8 * k));
  }
  header[8] = 8;  // bits per channel
  header[9] = 2;  // colour type: RGB
  append_chunk(out, "IHDR", header);
  append_chunk(out, "IDAT", packed);
  append_chunk(out, "IEND", {});
  return out;
}

}  // namespace granule::io
