// Laying a scene out as a picture: the view, the particles as discs coloured
// by the chosen quantity, the walls, the legend; the back ends (picture_raster.cpp,
// picture_svg.cpp) draw the layout.
#include "io/picture.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <numeric>
#include <set>

#include "core/errors.hpp"
#include "engine/simulation_base.hpp"
#include "io/finite_wall_outline.hpp"
#include "io/picture_draw.hpp"
#include "io/rank_files.hpp"

namespace granule::io {

using namespace picture_detail;

namespace {

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

  const int d = sim.dimension();
  if (d == 2 && o.projection != Projection::xy)
    throw InputError(fmt::format("picture: projection = '{}' needs a 3D scene (2D is x-y)",
                                 projection_name(o.projection)));
  const bool perspective = o.projection == Projection::perspective;
  if (o.slab) {
    const auto& b = *o.slab;
    if (!(std::isfinite(b[0]) && std::isfinite(b[1]) && b[0] < b[1]))
      throw InputError("picture: slab must be { lo, hi } with finite lo < hi [m]");
    if (perspective) throw InputError("picture: slab is for the xy, xz and yz projections");
  }
  if ((o.eye || o.target) && !perspective)
    throw InputError("picture: eye and target are for projection = 'perspective'");

  // ---- the particles and what colours them ----
  const SimulationBase::FlatState s = sim.flat_state();
  const std::size_t n = s.id.size();
  // Each particle in the picture's coordinates (picture_view.cpp).
  const Projected view_of = project(s, d, o);
  const std::vector<double>& pos = view_of.position;
  const std::vector<double>& drawn_radius = view_of.radius;
  const std::vector<double>& shade = view_of.shade;
  const std::vector<char>& shown = view_of.shown;
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
  // Walls in the picture's coordinates; the perspective view draws none.
  const std::vector<WallSpec> walls = walls_in_view(sim, o);
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
      if (!shown[i]) continue;
      double x = pos[3 * i], y = pos[3 * i + 1], r = drawn_radius[i];
      include(x - r, x + r, y - r, y + r);
    }
    for (const auto& w : walls)
      if (w.finite()) {
        for (const auto& seg : finite_wall_outline(w, d))
          include(std::min(seg[0], seg[2]), std::max(seg[0], seg[2]), std::min(seg[1], seg[3]),
                  std::max(seg[1], seg[3]));
      } else if (w.type == WallType::cylinder && axis_along_z(w, d))
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

  // Particles, farthest first in 3D so that the nearest are on top.
  std::size_t drawn = 0;
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  if (d == 3)
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return pos[a * 3 + 2] < pos[b * 3 + 2]; });
  for (std::size_t i : order) {
    if (!shown[i]) continue;
    Prim p = primitive(Prim::disc);
    p.x0 = px(pos[3 * i]);
    p.y0 = py(pos[3 * i + 1]);
    p.radius = drawn_radius[i] * scale;
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
    if (shade[i] < 1) p.colour = darker(p.colour, shade[i]);
    // A darker rim tells touching particles apart once they are a few pixels wide.
    if (p.radius > 2) {
      p.edge = darker(p.colour, 0.6);
      p.edge_width = std::min(1.0, 0.2 * p.radius);
    }
    add(p, true);
    ++drawn;
  }

  // Walls on top: a mesh as its edges seen along z, each edge once; a
  // polyline as its outline (arcs in short pieces).
  for (const MeshView& m : mesh_views_in_view(sim, o)) {
    std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
    for (const auto& t : m.triangles)
      for (int k = 0; k < 3; ++k) edges.insert(std::minmax(t[k], t[(k + 1) % 3]));
    for (const auto& l : m.lines) edges.insert(std::minmax(l[0], l[1]));
    for (const auto& [a, b] : edges) {
      Prim p = primitive(Prim::line);
      p.x0 = px(m.vertices[a][0]);
      p.y0 = py(m.vertices[a][1]);
      p.x1 = px(m.vertices[b][0]);
      p.y1 = py(m.vertices[b][1]);
      p.width = 0.5 * wall_width;
      p.colour = wall_colour;
      add(p, true);
    }
  }
  for (const auto& w : walls) {
    if (is_surface_wall(w.type)) continue;  // drawn above
    if (w.finite()) {
      for (const auto& seg : finite_wall_outline(w, d)) {
        Prim p = primitive(Prim::line);
        p.x0 = px(seg[0]), p.y0 = py(seg[1]), p.x1 = px(seg[2]), p.y1 = py(seg[3]);
        p.width = wall_width;
        p.colour = wall_colour;
        add(p, true);
      }
      continue;
    }
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
    if (d == 3) {
      static const char* axis_name = "xyz";
      t.label += fmt::format("   view {}", projection_name(o.projection));
      if (o.slab)
        t.label += fmt::format(", {} {}..{} m", axis_name[viewing_axis(o.projection)],
                               number((*o.slab)[0]), number((*o.slab)[1]));
    }
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
  std::ofstream file(writable_path(o.path), std::ios::binary | std::ios::trunc);
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
