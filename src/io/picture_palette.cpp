// The picture's colours: the viridis scale for continuous values, ten
// categorical colours, darkening and #rrggbb.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "io/picture_draw.hpp"

namespace granule::io::picture_detail {

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

Rgb darker(const Rgb& c, double f) {
  return {c.r * f, c.g * f, c.b * f};
}

std::string hex(const Rgb& c) {
  auto b = [](double v) { return static_cast<int>(std::lround(std::clamp(v, 0.0, 255.0))); };
  return fmt::format("#{:02x}{:02x}{:02x}", b(c.r), b(c.g), b(c.b));
}

}  // namespace granule::io::picture_detail
