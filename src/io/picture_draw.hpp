// What the picture's parts share (picture.cpp lays a scene out, the back ends
// draw it): colours, the bitmap font's glyph type and the display list of
// primitives in pixel coordinates. Internal to src/io's picture files.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace granule::io::picture_detail {

struct Rgb {
  double r, g, b;  // 0..255
};

// ---- colours (picture_palette.cpp) ----

Rgb viridis(double u);
Rgb category_colour(int k);
const Rgb fixed_grey{64, 64, 64};
const Rgb wall_colour{30, 30, 30};
const Rgb post_fill{205, 205, 205};
const Rgb text_colour{20, 20, 20};
const Rgb white{255, 255, 255};
Rgb darker(const Rgb& c, double f);
std::string hex(const Rgb& c);

// ---- the 5x7 bitmap font (picture_font.cpp) ----

struct Glyph {
  char c;
  const char* rows[7];
};

// The glyph of `c`; characters the font lacks draw as '?'.
const Glyph& glyph(char c);

// ---- the display list ----

struct Prim {
  enum Kind { disc, ring, line, rect, text } kind = disc;
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // centre / start / corner, px
  double radius = 0, width = 0;           // disc and ring radius; ring and line width, px
  Rgb colour{0, 0, 0};
  Rgb edge{0, 0, 0};  // disc rim
  double edge_width = 0;
  double size = 0;  // text: font scale (a glyph is 5 x 7 of these)
  std::string label;
  bool clipped = false;  // limited to the plot area
};

inline Prim primitive(Prim::Kind kind) {
  Prim p;
  p.kind = kind;
  return p;
}

struct Layout {
  int width = 0, height = 0;
  double plot_x0 = 0, plot_y0 = 0, plot_x1 = 0, plot_y1 = 0;  // px
  std::vector<Prim> prims;
};

// ---- the back ends ----

// The layout's pixels, 8-bit RGB rows top to bottom (picture_raster.cpp).
std::vector<std::uint8_t> rasterise(const Layout& layout);
// The layout as an SVG document (picture_svg.cpp).
std::string svg(const Layout& layout);

}  // namespace granule::io::picture_detail
