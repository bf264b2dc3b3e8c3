// What the picture's parts share (picture.cpp lays a scene out, the back ends
// draw it): colours, the bitmap font's glyph type and the display list of
// primitives in pixel coordinates. Internal to src/io's picture files.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "engine/simulation_base.hpp"
#include "io/picture.hpp"

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

// ---- the view (picture_view.cpp) ----

// Each particle in the picture's coordinates: right, up, towards the viewer
// (m; for the perspective, metres at the target's distance), its drawn
// radius, a shade (1 = full colour, less = farther) and whether it is shown
// (in the slab, in front of the camera).
struct Projected {
  std::vector<double> position;  // 3 per particle
  std::vector<double> radius, shade;
  std::vector<char> shown;
};
Projected project(const SimulationBase::FlatState& s, int dimension, const PictureOptions& o);
// The walls in the picture's coordinates (none in the perspective view).
std::vector<WallSpec> walls_in_view(const SimulationBase& sim, const PictureOptions& o);
// The mesh walls' triangles in the picture's coordinates (none in perspective).
std::vector<MeshView> mesh_views_in_view(const SimulationBase& sim, const PictureOptions& o);
const char* projection_name(Projection p);
// The axis a projection looks along, for `slab`: 2 (z), 1 (y) or 0 (x).
int viewing_axis(Projection p);

// ---- the back ends ----

// The layout's pixels, 8-bit RGB rows top to bottom (picture_raster.cpp).
std::vector<std::uint8_t> rasterise(const Layout& layout);
// The layout as an SVG document (picture_svg.cpp).
std::string svg(const Layout& layout);

}  // namespace granule::io::picture_detail
