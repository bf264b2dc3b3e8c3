// The picture's SVG back end: each primitive of the display list as an SVG
// element (text as real text).
#include <fmt/format.h>

#include <string>

#include "io/picture_draw.hpp"

namespace granule::io::picture_detail {

namespace {

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

}  // namespace

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

}  // namespace granule::io::picture_detail
