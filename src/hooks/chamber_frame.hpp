// The frame the Mechanofusion diagnostics measure in (dissertation 4.2.3,
// 4.4.2): the chamber's axis, radius and spin, read from its wall, and the
// direction of the inner piece, from which the four areas' angles count.
// Shared by the zones, areas and contact_peaks diagnostics.
#pragma once

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "hooks/diagnostic.hpp"

namespace granule {

template <int D>
struct ChamberFrame {
  using V = Vec<D>;
  std::string chamber_name = "chamber";
  std::string inner_name = "inner_piece";  // empty: angles count from +x
  bool resolved = false;
  V center = V::Zero();
  double radius = 0;     // m
  double omega = 0;      // rad/s, chamber spin about +z
  double reference = 0;  // rad, direction of the inner piece's centre
  int chamber_wall = -1;

  static OptionDocs option_docs(bool needs_inner) {
    return {
        {"chamber", "", "chamber", "the chamber's cylinder wall (particles inside; its axis z)"},
        {"inner_piece", "", needs_inner ? "inner_piece" : "",
         needs_inner ? "the inner piece's cylinder wall; angles count from its direction"
                     : "the inner piece's cylinder wall ('': angles count from +x)"}};
  }
  // Reads the wall names from the options (chamber = '...', inner_piece = '...').
  void read(DiagnosticOptions& o, bool needs_inner) {
    chamber_name = o.string("chamber", "chamber");
    inner_name = o.string("inner_piece", needs_inner ? "inner_piece" : "");
  }

  // Finds the walls on the first step; the chamber's spin is re-read every
  // call so a scene may change it between runs (sim:set_wall).
  void resolve(const std::vector<Wall<D>>& walls, const char* who) {
    if (!resolved) {
      chamber_wall = find(walls, chamber_name, who);
      const Wall<D>& c = walls[chamber_wall];
      if (c.type != WallType::cylinder || !c.inside)
        throw InputError(
            fmt::format("diagnostic '{}': wall '{}' must be a cylinder with the "
                        "particles inside (the chamber)",
                        who, chamber_name));
      if constexpr (D == 3) {
        if (std::abs(std::abs(c.axis.z()) - 1) > 1e-12)
          throw InputError(fmt::format(
              "diagnostic '{}': the chamber '{}' must turn about the z axis", who, chamber_name));
      }
      center = c.center;
      if constexpr (D == 3) center.z() = 0;
      radius = c.radius;
      if (!inner_name.empty()) {
        const Wall<D>& in = walls[find(walls, inner_name, who)];
        // A polyline's or a mesh's direction is its axis point's (the inner piece's centre).
        if (in.type != WallType::cylinder && in.type != WallType::polyline &&
            in.type != WallType::mesh)
          throw InputError(
              fmt::format("diagnostic '{}': wall '{}' must be a cylinder, a polyline or a mesh "
                          "(the inner piece)",
                          who, inner_name));
        const V d = in.center - center;
        if (d.x() * d.x() + d.y() * d.y() > 0) reference = std::atan2(d.y(), d.x());
      }
      resolved = true;
    }
    if (chamber_wall < 0 || chamber_wall >= static_cast<int>(walls.size()))
      throw InputError(
          fmt::format("diagnostic '{}': the chamber's wall index {} is out of range "
                      "(a checkpoint of another scene?)",
                      who, chamber_wall));
    const Wall<D>& c = walls[chamber_wall];
    omega = c.angular_velocity;
    if constexpr (D == 3) omega *= c.axis.z() > 0 ? 1 : -1;
  }

  // Checkpoints: what the first step found (the inner piece may have moved since).
  void save(DiagnosticStateWriter& w) const {
    w.put_integers("frame.resolved", {resolved ? 1 : 0, chamber_wall});
    std::vector<double> g(center.data(), center.data() + D);
    g.insert(g.end(), {radius, omega, reference});
    w.put("frame.geometry", std::move(g));
  }
  void load(const DiagnosticStateReader& r) {
    const auto flags = r.integers("frame.resolved", 2);
    if ((flags[0] != 0 && flags[0] != 1) || (flags[0] == 1 && flags[1] < 0))
      r.invalid("frame.resolved", "is not a resolved flag and a wall index");
    const auto g = r.doubles("frame.geometry", D + 3);
    resolved = flags[0] == 1;
    chamber_wall = static_cast<int>(flags[1]);
    for (int k = 0; k < D; ++k) center[k] = g[k];
    radius = g[D], omega = g[D + 1], reference = g[D + 2];
  }

  // Radial distance from the axis, m.
  double radial_distance(const V& x) const {
    const double dx = x.x() - center.x(), dy = x.y() - center.y();
    return std::sqrt(dx * dx + dy * dy);
  }
  // Angle of x about the axis, counted from the inner piece counter-clockwise
  // (the sense of a positive chamber spin), in degrees in [0, 360).
  double angle_deg(const V& x) const {
    double a = std::atan2(x.y() - center.y(), x.x() - center.x()) - reference;
    a *= 180 / pi;
    a = std::fmod(a, 360.0);
    if (a < 0) a += 360;
    return a;
  }

 private:
  static int find(const std::vector<Wall<D>>& walls, const std::string& name, const char* who) {
    for (std::size_t w = 0; w < walls.size(); ++w)
      if (walls[w].name == name) return static_cast<int>(w);
    throw InputError(fmt::format("diagnostic '{}': no wall named '{}'", who, name));
  }
};

// The four areas of 4.4.2 as angular sectors about the chamber axis, counted
// in degrees from the inner piece, counter-clockwise (SPEC 4.2).
// Sectors may leave gaps but must not overlap; a point in no sector is in
// none of the areas.
struct AreaSectors {
  static constexpr int count = 4;
  static constexpr std::array<const char*, count> names = {"inner_piece", "scraper", "input",
                                                           "free_diffusion"};
  std::array<double, count> from{}, to{};  // deg, to > from, to - from <= 360

  static OptionDocs option_docs() {
    return {{"area_inner_piece", "deg", "{-45, 45}", "{from, to}: the inner piece's area (4.4.2)"},
            {"area_scraper", "deg", "{45, 150}", "{from, to}: the scraper's area"},
            {"area_input", "deg", "{250, 315}", "{from, to}: the input area"},
            {"area_free_diffusion", "deg", "{150, 250}", "{from, to}: the free-diffusion area"}};
  }

  void read(DiagnosticOptions& o) {
    // Defaults: the gap +-45 deg; the scraper's region to 150 deg; the free
    // diffusion to 250 deg; the input area from there back to the gap.
    const std::array<std::vector<double>, count> fallback = {
        std::vector<double>{-45, 45}, {45, 150}, {250, 315}, {150, 250}};
    for (int k = 0; k < count; ++k) {
      const std::string key = std::string("area_") + names[k];
      auto v = o.list(key, fallback[k]);
      if (v.size() != 2 || !(v[1] > v[0]) || v[1] - v[0] > 360)
        throw InputError(
            fmt::format("{}: '{}' must be {{from, to}} in degrees with from < to <= from + 360",
                        o.context(), key));
      from[k] = v[0], to[k] = v[1];
    }
    // Refuse overlaps: sample the circle finely (sectors are whole degrees or so).
    for (int s = 0; s < 3600; ++s) {
      const double a = (s + 0.5) / 10;
      int hits = 0;
      for (int k = 0; k < count; ++k) hits += contains(k, a);
      if (hits > 1)
        throw InputError(fmt::format("{}: the area sectors overlap near {} degrees", o.context(),
                                     std::round(a)));
    }
  }
  bool contains(int k, double angle_deg) const {
    double rel = std::fmod(angle_deg - from[k], 360.0);
    if (rel < 0) rel += 360;
    return rel < to[k] - from[k];
  }
  // The area holding an angle, or -1.
  int area_of(double angle_deg) const {
    for (int k = 0; k < count; ++k)
      if (contains(k, angle_deg)) return k;
    return -1;
  }
  std::vector<double> bounds() const {
    std::vector<double> b;
    for (int k = 0; k < count; ++k) b.push_back(from[k]), b.push_back(to[k]);
    return b;
  }
};

// Columns "time", then one per area.
inline std::vector<std::string> area_columns() {
  std::vector<std::string> c{"time"};
  for (const char* n : AreaSectors::names) c.push_back(n);
  return c;
}

}  // namespace granule
