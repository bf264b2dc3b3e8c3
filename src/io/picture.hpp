// Pictures of a particle pattern straight from the engine, as PNG or SVG, for
// the REPL and quick looks without Python: particles as discs of their true
// radius (3D: projected on x-y, x-z or y-z, the nearest drawn last, or a slab
// of them; or a perspective view with depth shading), walls (cylinders as
// circles or bands, planes as lines), and a legend with the simulated time and
// the colour scale. Publication figures come from tools/ and the HDF5 output.
//
// Everything is first laid out as a list of primitives in pixel coordinates
// (discs, rings, lines, rectangles, text); one small back end rasterises them
// with coverage anti-aliasing into a PNG (zlib), the other writes them as SVG
// elements, so both formats show the same picture.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace granule {
class SimulationBase;
}

namespace granule::io {

enum class ColorBy { speed, material, fixed, radius, spin };

// How a 3D scene is seen: along -z (x right, y up), along +y (x right, z up),
// along -x (y right, z up), or through a pinhole camera.
enum class Projection { xy, xz, yz, perspective };

struct PictureOptions {
  std::string path;  // ends in .png or .svg
  int width = 800;   // px
  int height = 0;    // px; 0 = from the view's aspect ratio
  ColorBy color_by = ColorBy::speed;
  std::optional<std::array<double, 2>> range;  // colour scale, in the unit of color_by
  std::optional<std::array<double, 4>> view;   // x_min, x_max, y_min, y_max [m]
  bool walls = true;
  bool legend = true;
  Projection projection = Projection::xy;  // 3D only; a 2D scene is always x-y
  // Only the particles whose centre lies in [lo, hi] along the viewing axis
  // (z for xy, y for xz, x for yz) [m].
  std::optional<std::array<double, 2>> slab;
  // Perspective: the camera's position and the point it looks at [m]; by default
  // from the side and above, at 2.5 times the particles' extent from its centre.
  std::optional<std::array<double, 3>> eye, target;
};

// "speed" -> ColorBy::speed ...; throws InputError listing the choices.
ColorBy parse_color_by(const std::string& name);
// "xy", "xz", "yz", "perspective"; throws InputError listing the choices.
Projection parse_projection(const std::string& name);

struct PictureInfo {
  int width = 0, height = 0;            // px
  std::size_t particles = 0;            // drawn
  double value_min = 0, value_max = 0;  // colour scale used (continuous colourings)
};

// Throws InputError for invalid options and std::runtime_error if the file
// cannot be written.
PictureInfo write_picture(const SimulationBase& sim, const PictureOptions& options);

// An 8-bit RGB image as PNG bytes (zlib deflate, one IDAT chunk).
std::vector<std::uint8_t> encode_png(int width, int height, const std::vector<std::uint8_t>& rgb);

}  // namespace granule::io
