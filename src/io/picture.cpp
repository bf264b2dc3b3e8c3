#include "io/picture.hpp"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <numeric>

#include "core/errors.hpp"
#include "engine/simulation_base.hpp"

namespace granule::io {

namespace {

struct Rgb {
  double r, g, b;  // 0..255
};

// ---- colours ----

// Viridis (perceptually uniform, readable in grey and by colour-blind
// readers), sampled at nine points and interpolated linearly.
Rgb viridis(double u) {
  static const Rgb stops[] = {{68, 1, 84},    {71, 45, 123},  {59, 82, 139},
                              {44, 114, 142}, {33, 145, 140}, {40, 174, 128},
                              {94, 201, 98},  {173, 220, 48}, {253, 231, 37}};
  if (!(u > 0)) u = 0;
  if (u > 1) u = 1;
  double x = u * 8;
  int k = std::min(7, static_cast<int>(x));
  double f = x - k;
  const Rgb &a = stops[k], &b = stops[k + 1];
  return {a.r + f * (b.r - a.r), a.g + f * (b.g - a.g), a.b + f * (b.b - a.b)};
}

// Ten distinct colours for categories (materials), cycling beyond ten.
Rgb category_colour(int k) {
  static const Rgb palette[] = {{31, 119, 180},  {255, 127, 14}, {44, 160, 44},   {214, 39, 40},
                                {148, 103, 189}, {140, 86, 75},  {227, 119, 194}, {127, 127, 127},
                                {188, 189, 34},  {23, 190, 207}};
  return palette[((k % 10) + 10) % 10];
}

const Rgb fixed_grey{64, 64, 64};
const Rgb wall_colour{30, 30, 30};
const Rgb post_fill{205, 205, 205};
const Rgb text_colour{20, 20, 20};
const Rgb white{255, 255, 255};

Rgb darker(const Rgb& c, double f) {
  return {c.r * f, c.g * f, c.b * f};
}

std::string hex(const Rgb& c) {
  auto b = [](double v) { return static_cast<int>(std::lround(std::clamp(v, 0.0, 255.0))); };
  return fmt::format("#{:02x}{:02x}{:02x}", b(c.r), b(c.g), b(c.b));
}

// ---- a 5x7 bitmap font for the PNG legend (SVG uses real text) ----

struct Glyph {
  char c;
  const char* rows[7];
};

// clang-format off
const Glyph font[] = {
  {' ', {"     ", "     ", "     ", "     ", "     ", "     ", "     "}},
  {'0', {" ### ", "#   #", "#  ##", "# # #", "##  #", "#   #", " ### "}},
  {'1', {"  #  ", " ##  ", "  #  ", "  #  ", "  #  ", "  #  ", " ### "}},
  {'2', {" ### ", "#   #", "    #", "   # ", "  #  ", " #   ", "#####"}},
  {'3', {"#####", "   # ", "  #  ", "   # ", "    #", "#   #", " ### "}},
  {'4', {"   # ", "  ## ", " # # ", "#  # ", "#####", "   # ", "   # "}},
  {'5', {"#####", "#    ", "#### ", "    #", "    #", "#   #", " ### "}},
  {'6', {"  ## ", " #   ", "#    ", "#### ", "#   #", "#   #", " ### "}},
  {'7', {"#####", "    #", "   # ", "  #  ", " #   ", " #   ", " #   "}},
  {'8', {" ### ", "#   #", "#   #", " ### ", "#   #", "#   #", " ### "}},
  {'9', {" ### ", "#   #", "#   #", " ####", "    #", "   # ", " ##  "}},
  {'.', {"     ", "     ", "     ", "     ", "     ", " ##  ", " ##  "}},
  {',', {"     ", "     ", "     ", "     ", " ##  ", "  #  ", " #   "}},
  {'-', {"     ", "     ", "     ", " ### ", "     ", "     ", "     "}},
  {'+', {"     ", "  #  ", "  #  ", "#####", "  #  ", "  #  ", "     "}},
  {'=', {"     ", "     ", "#####", "     ", "#####", "     ", "     "}},
  {'_', {"     ", "     ", "     ", "     ", "     ", "     ", "#####"}},
  {'/', {"    #", "    #", "   # ", "  #  ", " #   ", "#    ", "#    "}},
  {':', {"     ", " ##  ", " ##  ", "     ", " ##  ", " ##  ", "     "}},
  {'(', {"   # ", "  #  ", " #   ", " #   ", " #   ", "  #  ", "   # "}},
  {')', {" #   ", "  #  ", "   # ", "   # ", "   # ", "  #  ", " #   "}},
  {'[', {" ### ", " #   ", " #   ", " #   ", " #   ", " #   ", " ### "}},
  {']', {" ### ", "   # ", "   # ", "   # ", "   # ", "   # ", " ### "}},
  {'^', {"  #  ", " # # ", "#   #", "     ", "     ", "     ", "     "}},
  {'*', {"     ", "  #  ", "# # #", " ### ", "# # #", "  #  ", "     "}},
  {'%', {"##   ", "##  #", "   # ", "  #  ", " #   ", "#  ##", "   ##"}},
  {'?', {" ### ", "#   #", "    #", "   # ", "  #  ", "     ", "  #  "}},
  {'\'', {"  #  ", "  #  ", " #   ", "     ", "     ", "     ", "     "}},
  {'a', {"     ", "     ", " ### ", "    #", " ####", "#   #", " ####"}},
  {'b', {"#    ", "#    ", "# ## ", "##  #", "#   #", "#   #", "#### "}},
  {'c', {"     ", "     ", " ### ", "#    ", "#    ", "#   #", " ### "}},
  {'d', {"    #", "    #", " ## #", "#  ##", "#   #", "#   #", " ####"}},
  {'e', {"     ", "     ", " ### ", "#   #", "#####", "#    ", " ### "}},
  {'f', {"  ## ", " #  #", " #   ", "###  ", " #   ", " #   ", " #   "}},
  {'g', {"     ", " ####", "#   #", "#   #", " ####", "    #", " ### "}},
  {'h', {"#    ", "#    ", "# ## ", "##  #", "#   #", "#   #", "#   #"}},
  {'i', {"  #  ", "     ", " ##  ", "  #  ", "  #  ", "  #  ", " ### "}},
  {'j', {"   # ", "     ", "  ## ", "   # ", "   # ", "#  # ", " ##  "}},
  {'k', {"#    ", "#    ", "#  # ", "# #  ", "##   ", "# #  ", "#  # "}},
  {'l', {" ##  ", "  #  ", "  #  ", "  #  ", "  #  ", "  #  ", " ### "}},
  {'m', {"     ", "     ", "## # ", "# # #", "# # #", "#   #", "#   #"}},
  {'n', {"     ", "     ", "# ## ", "##  #", "#   #", "#   #", "#   #"}},
  {'o', {"     ", "     ", " ### ", "#   #", "#   #", "#   #", " ### "}},
  {'p', {"     ", "     ", "#### ", "#   #", "#### ", "#    ", "#    "}},
  {'q', {"     ", "     ", " ## #", "#  ##", " ####", "    #", "    #"}},
  {'r', {"     ", "     ", "# ## ", "##  #", "#    ", "#    ", "#    "}},
  {'s', {"     ", "     ", " ### ", "#    ", " ### ", "    #", "#### "}},
  {'t', {" #   ", " #   ", "###  ", " #   ", " #   ", " #  #", "  ## "}},
  {'u', {"     ", "     ", "#   #", "#   #", "#   #", "#  ##", " ## #"}},
  {'v', {"     ", "     ", "#   #", "#   #", "#   #", " # # ", "  #  "}},
  {'w', {"     ", "     ", "#   #", "#   #", "# # #", "# # #", " # # "}},
  {'x', {"     ", "     ", "#   #", " # # ", "  #  ", " # # ", "#   #"}},
  {'y', {"     ", "     ", "#   #", "#   #", " ####", "    #", " ### "}},
  {'z', {"     ", "     ", "#####", "   # ", "  #  ", " #   ", "#####"}},
  {'A', {" ### ", "#   #", "#   #", "#####", "#   #", "#   #", "#   #"}},
  {'B', {"#### ", "#   #", "#   #", "#### ", "#   #", "#   #", "#### "}},
  {'C', {" ### ", "#   #", "#    ", "#    ", "#    ", "#   #", " ### "}},
  {'D', {"#### ", "#   #", "#   #", "#   #", "#   #", "#   #", "#### "}},
  {'E', {"#####", "#    ", "#    ", "#### ", "#    ", "#    ", "#####"}},
  {'F', {"#####", "#    ", "#    ", "#### ", "#    ", "#    ", "#    "}},
  {'G', {" ### ", "#   #", "#    ", "# ###", "#   #", "#   #", " ####"}},
  {'H', {"#   #", "#   #", "#   #", "#####", "#   #", "#   #", "#   #"}},
  {'I', {" ### ", "  #  ", "  #  ", "  #  ", "  #  ", "  #  ", " ### "}},
  {'J', {"  ###", "   # ", "   # ", "   # ", "   # ", "#  # ", " ##  "}},
  {'K', {"#   #", "#  # ", "# #  ", "##   ", "# #  ", "#  # ", "#   #"}},
  {'L', {"#    ", "#    ", "#    ", "#    ", "#    ", "#    ", "#####"}},
  {'M', {"#   #", "## ##", "# # #", "# # #", "#   #", "#   #", "#   #"}},
  {'N', {"#   #", "#   #", "##  #", "# # #", "#  ##", "#   #", "#   #"}},
  {'O', {" ### ", "#   #", "#   #", "#   #", "#   #", "#   #", " ### "}},
  {'P', {"#### ", "#   #", "#   #", "#### ", "#    ", "#    ", "#    "}},
  {'Q', {" ### ", "#   #", "#   #", "#   #", "# # #", "#  # ", " ## #"}},
  {'R', {"#### ", "#   #", "#   #", "#### ", "# #  ", "#  # ", "#   #"}},
  {'S', {" ####", "#    ", "#    ", " ### ", "    #", "    #", "#### "}},
  {'T', {"#####", "  #  ", "  #  ", "  #  ", "  #  ", "  #  ", "  #  "}},
  {'U', {"#   #", "#   #", "#   #", "#   #", "#   #", "#   #", " ### "}},
  {'V', {"#   #", "#   #", "#   #", "#   #", "#   #", " # # ", "  #  "}},
  {'W', {"#   #", "#   #", "#   #", "# # #", "# # #", "# # #", " # # "}},
  {'X', {"#   #", "#   #", " # # ", "  #  ", " # # ", "#   #", "#   #"}},
  {'Y', {"#   #", "#   #", " # # ", "  #  ", "  #  ", "  #  ", "  #  "}},
  {'Z', {"#####", "    #", "   # ", "  #  ", " #   ", "#    ", "#####"}},
};
// clang-format on

const Glyph& glyph(char c) {
  static const std::map<char, const Glyph*> index = [] {
    std::map<char, const Glyph*> m;
    for (const auto& g : font) m[g.c] = &g;
    return m;
  }();
  auto it = index.find(c);
  return it != index.end() ? *it->second : *index.at('?');
}

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

Prim primitive(Prim::Kind kind) {
  Prim p;
  p.kind = kind;
  return p;
}

struct Layout {
  int width = 0, height = 0;
  double plot_x0 = 0, plot_y0 = 0, plot_x1 = 0, plot_y1 = 0;  // px
  std::vector<Prim> prims;
};

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

// ---- SVG back end ----

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        // Control characters are not allowed in XML 1.0 text.
        if (static_cast<unsigned char>(c) >= 0x20 || c == '\t') out += c;
    }
  }
  return out;
}

std::string svg(const Layout& layout) {
  std::string out = fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" "
      "viewBox=\"0 0 {0} {1}\">\n"
      "<rect width=\"{0}\" height=\"{1}\" fill=\"#ffffff\"/>\n"
      "<defs><clipPath id=\"plot\"><rect x=\"{2:.2f}\" y=\"{3:.2f}\" width=\"{4:.2f}\" "
      "height=\"{5:.2f}\"/></clipPath></defs>\n",
      layout.width, layout.height, layout.plot_x0, layout.plot_y0, layout.plot_x1 - layout.plot_x0,
      layout.plot_y1 - layout.plot_y0);
  bool in_clip = false;
  for (const Prim& p : layout.prims) {
    if (p.clipped != in_clip) {
      out += p.clipped ? "<g clip-path=\"url(#plot)\">\n" : "</g>\n";
      in_clip = p.clipped;
    }
    switch (p.kind) {
      case Prim::disc:
        out += fmt::format("<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"{:.3f}\" fill=\"{}\"", p.x0,
                           p.y0, p.radius, hex(p.colour));
        if (p.edge_width > 0)
          out += fmt::format(" stroke=\"{}\" stroke-width=\"{:.2f}\"", hex(p.edge), p.edge_width);
        out += "/>\n";
        break;
      case Prim::ring:
        out += fmt::format(
            "<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"{:.3f}\" fill=\"none\" stroke=\"{}\" "
            "stroke-width=\"{:.2f}\"/>\n",
            p.x0, p.y0, p.radius, hex(p.colour), p.width);
        break;
      case Prim::line:
        out += fmt::format(
            "<line x1=\"{:.2f}\" y1=\"{:.2f}\" x2=\"{:.2f}\" y2=\"{:.2f}\" stroke=\"{}\" "
            "stroke-width=\"{:.2f}\"/>\n",
            p.x0, p.y0, p.x1, p.y1, hex(p.colour), p.width);
        break;
      case Prim::rect:
        out += fmt::format(
            "<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" fill=\"{}\"/>\n",
            p.x0, p.y0, p.x1 - p.x0, p.y1 - p.y0, hex(p.colour));
        break;
      case Prim::text:
        // The raster font is 7 units tall from its top; SVG places text by its baseline.
        out += fmt::format(
            "<text x=\"{:.2f}\" y=\"{:.2f}\" font-family=\"sans-serif\" font-size=\"{:.1f}\" "
            "fill=\"{}\">{}</text>\n",
            p.x0, p.y0 + 7 * p.size, 9 * p.size, hex(p.colour), xml_escape(p.label));
        break;
    }
  }
  if (in_clip) out += "</g>\n";
  out += "</svg>\n";
  return out;
}

// ---- laying out the scene ----

bool ends_with(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  for (std::size_t k = 0; k < suffix.size(); ++k)
    if (std::tolower(static_cast<unsigned char>(s[s.size() - suffix.size() + k])) != suffix[k])
      return false;
  return true;
}

// A cylinder whose axis is (nearly) the viewing direction z draws as a circle.
bool axis_along_z(const WallSpec& w, int dimension) {
  if (dimension == 2) return true;
  double n = std::hypot(w.axis[0], w.axis[1], w.axis[2]);
  return n > 0 && std::abs(w.axis[2]) / n > 1 - 1e-9;
}

// The part of the infinite line through p along u inside the rectangle, or nothing.
bool clip_line(double px, double py, double ux, double uy, double x0, double x1, double y0,
               double y1, std::array<double, 4>& seg) {
  double lo = -1e300, hi = 1e300;
  const double p[2] = {px, py}, u[2] = {ux, uy}, bmin[2] = {x0, y0}, bmax[2] = {x1, y1};
  for (int k = 0; k < 2; ++k) {
    if (std::abs(u[k]) < 1e-300) {
      if (p[k] < bmin[k] || p[k] > bmax[k]) return false;
      continue;
    }
    double t0 = (bmin[k] - p[k]) / u[k], t1 = (bmax[k] - p[k]) / u[k];
    if (t0 > t1) std::swap(t0, t1);
    lo = std::max(lo, t0);
    hi = std::min(hi, t1);
  }
  if (lo > hi) return false;
  seg = {px + lo * ux, py + lo * uy, px + hi * ux, py + hi * uy};
  return true;
}

std::string number(double v) {
  return fmt::format("{:.3g}", v);
}

const char* color_by_name(ColorBy c) {
  switch (c) {
    case ColorBy::speed:
      return "speed";
    case ColorBy::material:
      return "material";
    case ColorBy::fixed:
      return "fixed";
    case ColorBy::radius:
      return "radius";
    case ColorBy::spin:
      return "spin";
  }
  return "?";
}

}  // namespace

ColorBy parse_color_by(const std::string& name) {
  for (ColorBy c :
       {ColorBy::speed, ColorBy::material, ColorBy::fixed, ColorBy::radius, ColorBy::spin})
    if (name == color_by_name(c)) return c;
  throw InputError(fmt::format(
      "picture: color_by = '{}' is not one of speed, material, fixed, radius, spin", name));
}

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

PictureInfo write_picture(const SimulationBase& sim, const PictureOptions& o) {
  // ---- options ----
  const bool png = ends_with(o.path, ".png");
  if (!png && !ends_with(o.path, ".svg"))
    throw InputError(fmt::format("picture: file '{}' must end in .png or .svg", o.path));
  if (o.width < 16 || o.width > 8192)
    throw InputError(fmt::format("picture: width must be 16..8192 pixels, got {}", o.width));
  if (o.height != 0 && (o.height < 16 || o.height > 8192))
    throw InputError(fmt::format("picture: height must be 16..8192 pixels, got {}", o.height));
  if (o.range && !(std::isfinite((*o.range)[0]) && std::isfinite((*o.range)[1]) &&
                   (*o.range)[0] < (*o.range)[1]))
    throw InputError("picture: range must be { min, max } with finite min < max");
  if (o.view) {
    const auto& v = *o.view;
    for (double x : v)
      if (!std::isfinite(x)) throw InputError("picture: view must be finite");
    if (!(v[0] < v[1] && v[2] < v[3])) throw InputError("picture: view needs lo < hi in x and y");
  }

  // ---- the particles and what colours them ----
  const int d = sim.dimension();
  const SimulationBase::FlatState s = sim.flat_state();
  const std::size_t n = s.id.size();
  const int sc = d == 2 ? 1 : 3;
  std::vector<double> value(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    switch (o.color_by) {
      case ColorBy::speed: {
        double v2 = 0;
        for (int k = 0; k < d; ++k) v2 += s.velocity[i * d + k] * s.velocity[i * d + k];
        value[i] = std::sqrt(v2);
        break;
      }
      case ColorBy::radius:
        value[i] = s.radius[i];
        break;
      case ColorBy::spin:
        // 2D: the signed spin about z; 3D: its magnitude.
        if (sc == 1) {
          value[i] = s.spin[i];
        } else {
          value[i] = std::hypot(s.spin[i * 3], s.spin[i * 3 + 1], s.spin[i * 3 + 2]);
        }
        break;
      case ColorBy::material:
        value[i] = s.material[i];
        break;
      case ColorBy::fixed:
        value[i] = s.fixed[i];
        break;
    }
  }
  const bool continuous =
      o.color_by == ColorBy::speed || o.color_by == ColorBy::radius || o.color_by == ColorBy::spin;
  double vmin = 0, vmax = 0;
  if (continuous) {
    if (o.range) {
      vmin = (*o.range)[0];
      vmax = (*o.range)[1];
    } else {
      bool any = false;
      for (std::size_t i = 0; i < n; ++i) {
        if (s.fixed[i] && o.color_by != ColorBy::radius) continue;  // drawn grey
        if (!any) vmin = vmax = value[i];
        vmin = std::min(vmin, value[i]);
        vmax = std::max(vmax, value[i]);
        any = true;
      }
      if (o.color_by == ColorBy::speed) vmin = 0;
      if (o.color_by == ColorBy::spin && sc == 1) {  // symmetric about zero
        double m = std::max(std::abs(vmin), std::abs(vmax));
        vmin = -m;
        vmax = m;
      }
      if (!(vmax > vmin)) {  // one value: a scale around it
        double pad = std::abs(vmax) > 0 ? 0.01 * std::abs(vmax) : 1e-12;
        vmin -= pad;
        vmax += pad;
      }
    }
  }

  // ---- the view ----
  std::vector<WallSpec> walls;
  if (o.walls)
    for (int w = 0; w < sim.wall_count(); ++w) walls.push_back(sim.wall(w));
  std::array<double, 4> view{0, 0, 0, 0};
  if (o.view) {
    view = *o.view;
  } else {
    bool any = false;
    auto include = [&](double x0, double x1, double y0, double y1) {
      if (!any) view = {x0, x1, y0, y1};
      view = {std::min(view[0], x0), std::max(view[1], x1), std::min(view[2], y0),
              std::max(view[3], y1)};
      any = true;
    };
    for (std::size_t i = 0; i < n; ++i) {
      double x = s.position[i * d], y = s.position[i * d + 1], r = s.radius[i];
      include(x - r, x + r, y - r, y + r);
    }
    for (const auto& w : walls)
      if (w.type == WallType::cylinder && axis_along_z(w, d))
        include(w.center[0] - w.radius, w.center[0] + w.radius, w.center[1] - w.radius,
                w.center[1] + w.radius);
    if (!any) view = {-1e-3, 1e-3, -1e-3, 1e-3};
    double span = std::max({view[1] - view[0], view[3] - view[2], 1e-12});
    double pad = 0.03 * span;
    view = {view[0] - pad, view[1] + pad, view[2] - pad, view[3] + pad};
  }

  // ---- pixel geometry: equal scale in x and y ----
  Layout L;
  L.width = o.width;
  const double text = std::max(1.0, std::round(o.width / 500.0));  // font pixel size
  const double legend_height = o.legend ? 26 * text : 0;
  const double dx = view[1] - view[0], dy = view[3] - view[2];
  double scale = o.width / dx;  // px per metre
  double plot_height = dy * scale;
  if (o.height > 0) {
    plot_height = o.height - legend_height;
    if (plot_height < 8) throw InputError("picture: height leaves no room below the legend");
    scale = std::min(o.width / dx, plot_height / dy);
  } else if (plot_height + legend_height > 8192) {
    plot_height = 8192 - legend_height;
    scale = plot_height / dy;
  }
  L.height = o.height > 0 ? o.height
                          : std::max(16, static_cast<int>(std::ceil(plot_height + legend_height)));
  if (static_cast<double>(L.width) * L.height > 40e6)
    throw InputError(fmt::format("picture: {} x {} pixels is too large", L.width, L.height));
  L.plot_x0 = 0;
  L.plot_y0 = 0;
  L.plot_x1 = L.width;
  L.plot_y1 = plot_height;
  // Centre the view in the plot area (it may be narrower than the picture).
  const double off_x = (L.width - dx * scale) / 2, off_y = (plot_height - dy * scale) / 2;
  auto px = [&](double x) { return off_x + (x - view[0]) * scale; };
  auto py = [&](double y) { return off_y + (view[3] - y) * scale; };  // y up

  const double wall_width = std::max(1.5, 1.5 * text);
  auto add = [&](Prim p, bool clipped) {
    p.clipped = clipped;
    if (p.kind == Prim::text) {  // cut what would run off the right edge
      const double room = (L.width - p.x0) / (6 * p.size);
      if (room < 1) return;
      if (p.label.size() > room) p.label = p.label.substr(0, static_cast<std::size_t>(room));
    }
    L.prims.push_back(std::move(p));
  };

  // Posts (particles outside a cylinder) are filled, under the particles.
  for (const auto& w : walls)
    if (w.type == WallType::cylinder && !w.inside && axis_along_z(w, d)) {
      Prim p = primitive(Prim::disc);
      p.x0 = px(w.center[0]);
      p.y0 = py(w.center[1]);
      p.radius = w.radius * scale;
      p.colour = post_fill;
      add(p, true);
    }

  // Particles, lowest z first in 3D so that the nearest (highest) are on top.
  std::size_t drawn = 0;
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  if (d == 3)
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return s.position[a * 3 + 2] < s.position[b * 3 + 2];
    });
  for (std::size_t i : order) {
    Prim p = primitive(Prim::disc);
    p.x0 = px(s.position[i * d]);
    p.y0 = py(s.position[i * d + 1]);
    p.radius = s.radius[i] * scale;
    if (p.x0 + p.radius < 0 || p.x0 - p.radius > L.width || p.y0 + p.radius < 0 ||
        p.y0 - p.radius > plot_height)
      continue;
    if (o.color_by == ColorBy::material) {
      p.colour = category_colour(s.material[i]);
    } else if (o.color_by == ColorBy::fixed) {
      p.colour = s.fixed[i] ? fixed_grey : category_colour(0);
    } else if (s.fixed[i] && o.color_by != ColorBy::radius) {
      p.colour = fixed_grey;
    } else {
      p.colour = viridis((value[i] - vmin) / (vmax - vmin));
    }
    // A darker rim tells touching particles apart once they are a few pixels wide.
    if (p.radius > 2) {
      p.edge = darker(p.colour, 0.6);
      p.edge_width = std::min(1.0, 0.2 * p.radius);
    }
    add(p, true);
    ++drawn;
  }

  // Walls on top.
  for (const auto& w : walls) {
    if (w.type == WallType::cylinder && axis_along_z(w, d)) {
      Prim p = primitive(Prim::ring);
      p.x0 = px(w.center[0]);
      p.y0 = py(w.center[1]);
      p.radius = w.radius * scale;
      p.width = wall_width;
      p.colour = wall_colour;
      add(p, true);
      continue;
    }
    // Lines: a plane seen edge-on, or the two sides of a cylinder lying across the view.
    double ux, uy;  // direction of the line(s) in the x-y plane
    std::vector<std::array<double, 2>> through;
    if (w.type == WallType::plane) {
      double nx = w.normal[0], ny = w.normal[1];
      double nn = std::hypot(nx, ny);
      if (nn < 1e-9 * std::max(1.0, std::hypot(nx, ny, w.normal[2])))
        continue;  // parallel to the picture
      ux = -ny / nn;
      uy = nx / nn;
      through.push_back({w.point[0], w.point[1]});
    } else {
      double ax = w.axis[0], ay = w.axis[1];
      double an = std::hypot(ax, ay);
      ux = ax / an;
      uy = ay / an;
      // An infinite cylinder projects along z onto a band of half-width R about its axis.
      through.push_back({w.center[0] - uy * w.radius, w.center[1] + ux * w.radius});
      through.push_back({w.center[0] + uy * w.radius, w.center[1] - ux * w.radius});
    }
    for (const auto& q : through) {
      std::array<double, 4> seg;
      if (!clip_line(q[0], q[1], ux, uy, view[0], view[1], view[2], view[3], seg)) continue;
      Prim p = primitive(Prim::line);
      p.x0 = px(seg[0]);
      p.y0 = py(seg[1]);
      p.x1 = px(seg[2]);
      p.y1 = py(seg[3]);
      p.width = wall_width;
      p.colour = wall_colour;
      add(p, true);
    }
  }

  // ---- legend: time, step, count, and the colour scale ----
  if (o.legend) {
    Prim rule = primitive(Prim::rect);
    rule.x0 = 0;
    rule.x1 = L.width;
    rule.y0 = plot_height;
    rule.y1 = plot_height + std::max(1.0, text * 0.5);
    rule.colour = {180, 180, 180};
    add(rule, false);
    const double margin = 6 * text;
    const double line1 = plot_height + 4 * text;
    const double line2 = line1 + 11 * text;
    Prim t = primitive(Prim::text);
    t.size = text;
    t.colour = text_colour;
    t.x0 = margin;
    t.y0 = line1;
    t.label = fmt::format("t = {:.6g} s   step {}   {} particles", sim.time(), sim.step_count(), n);
    add(t, false);
    if (continuous) {
      const char* unit = o.color_by == ColorBy::speed    ? "m/s"
                         : o.color_by == ColorBy::radius ? "m"
                                                         : "rad/s";
      std::string low = number(vmin), high = number(vmax);
      Prim lo = t;
      lo.y0 = line2;
      lo.label = low;
      add(lo, false);
      const double bar_x0 = margin + (low.size() + 1) * 6 * text;
      const double bar_x1 = bar_x0 + std::min(0.4 * L.width, 200 * text);
      const int steps = 64;
      for (int k = 0; k < steps; ++k) {
        Prim b = primitive(Prim::rect);
        b.x0 = bar_x0 + (bar_x1 - bar_x0) * k / steps;
        b.x1 = bar_x0 + (bar_x1 - bar_x0) * (k + 1) / steps + 0.5;  // no seams between slices
        b.y0 = line2;
        b.y1 = line2 + 7 * text;
        b.colour = viridis((k + 0.5) / steps);
        add(b, false);
      }
      Prim hi = t;
      hi.x0 = bar_x1 + 6 * text;
      hi.y0 = line2;
      std::string what =
          o.color_by == ColorBy::spin && sc == 3 ? "|spin|" : color_by_name(o.color_by);
      hi.label = fmt::format("{}   {} [{}]", high, what, unit);
      add(hi, false);
    } else {
      std::vector<std::pair<std::string, Rgb>> keys;
      if (o.color_by == ColorBy::fixed) {
        keys = {{"free", category_colour(0)}, {"fixed", fixed_grey}};
      } else {
        const auto& mats = sim.materials();
        for (std::size_t k = 0; k < mats.size(); ++k)
          keys.push_back({mats[k].name, category_colour(static_cast<int>(k))});
      }
      double pen = margin;
      for (const auto& [label, colour] : keys) {
        Prim sw = primitive(Prim::rect);
        sw.x0 = pen;
        sw.x1 = pen + 7 * text;
        sw.y0 = line2;
        sw.y1 = line2 + 7 * text;
        sw.colour = colour;
        add(sw, false);
        Prim name = t;
        name.x0 = pen + 9 * text;
        name.y0 = line2;
        name.label = label;
        add(name, false);
        pen += (label.size() + 4) * 6 * text;
      }
    }
  }

  // ---- write ----
  std::ofstream file(o.path, std::ios::binary | std::ios::trunc);
  if (!file) throw std::runtime_error(fmt::format("picture: cannot write '{}'", o.path));
  if (png) {
    std::vector<std::uint8_t> bytes = encode_png(L.width, L.height, rasterise(L));
    file.write(reinterpret_cast<const char*>(bytes.data()),
               static_cast<std::streamsize>(bytes.size()));
  } else {
    file << svg(L);
  }
  file.close();
  if (!file) throw std::runtime_error(fmt::format("picture: writing '{}' failed", o.path));
  PictureInfo info;
  info.width = L.width;
  info.height = L.height;
  info.particles = drawn;
  info.value_min = vmin;
  info.value_max = vmax;
  return info;
}

}  // namespace granule::io
