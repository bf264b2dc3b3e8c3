// The finite walls' input checks and the meridian segments they become.
#include "engine/finite_wall_setup.hpp"

#include <fmt/format.h>

#include <cmath>

#include "core/errors.hpp"

namespace granule {

namespace {
template <int D>
Vec<D> vec(const Triple& t) {
  Vec<D> v;
  for (int k = 0; k < D; ++k) v[k] = t[k];
  return v;
}
// A unit vector from `t`, refused when zero or not finite; `what` names it.
template <int D>
Vec<D> unit(const Triple& t, const std::string& ctx, const char* what) {
  if (!finite3(t)) throw InputError(fmt::format("{}: {} must be finite", ctx, what));
  const Vec<D> v = vec<D>(t);
  if (!(v.norm() > 0)) throw InputError(fmt::format("{}: {} must be non-zero", ctx, what));
  return v.normalized();
}
void positive(double x, const std::string& ctx, const char* what) {
  if (!std::isfinite(x) || !(x > 0))
    throw InputError(fmt::format("{}: {} must be > 0 [m], got {}", ctx, what, x));
}
void bounds(const WallSpec& s, const std::string& ctx) {
  if (!std::isfinite(s.z_lo) || !std::isfinite(s.z_hi) || !(s.z_lo < s.z_hi))
    throw InputError(fmt::format(
        "{}: bounds = {{lo, hi}} must be finite with lo < hi [m along the axis], got {{{}, {}}}",
        ctx, s.z_lo, s.z_hi));
}
}  // namespace

template <int D>
Wall<D> make_finite_wall(const WallSpec& s, const std::string& ctx) {
  Wall<D> w;
  w.name = s.name;
  w.type = s.type;
  w.material = s.material;
  w.bounded = s.bounded;
  if (!finite3(s.velocity)) throw InputError(fmt::format("{}: velocity must be finite", ctx));
  w.velocity = vec<D>(s.velocity);
  if (!std::isfinite(s.angular_velocity))
    throw InputError(fmt::format("{}: angular_velocity must be finite", ctx));
  w.angular_velocity = s.angular_velocity;
  if (D == 2 && s.angular_velocity != 0)
    throw InputError(fmt::format(
        "{}: a finite wall in 2D has an axis in the plane and cannot turn about it; leave "
        "angular_velocity out",
        ctx));
  if (s.type == WallType::plane) {
    if (!finite3(s.point)) throw InputError(fmt::format("{}: point must be finite", ctx));
    w.point = w.center = vec<D>(s.point);
    w.normal = w.axis = unit<D>(s.normal, ctx, "normal");
    positive(s.size_a, ctx, D == 2 ? "size" : "size[1]");
    w.half_a = s.size_a / 2;
    if constexpr (D == 2) {
      w.side = Vec<2>(-w.normal.y(), w.normal.x());
    } else {
      positive(s.size_b, ctx, "size[2]");
      w.half_b = s.size_b / 2;
      Vec<3> u;
      if (s.side == Triple{0, 0, 0}) {
        u = std::abs(w.normal.x()) < 0.9 ? Vec<3>::UnitX() : Vec<3>::UnitY();
      } else {
        u = unit<3>(s.side, ctx, "side");
      }
      u -= w.normal * w.normal.dot(u);
      if (!(u.norm() > 1e-6))
        throw InputError(fmt::format("{}: side must not be parallel to the normal", ctx));
      w.side = u.normalized();
    }
    return w;
  }
  if (!finite3(s.center)) throw InputError(fmt::format("{}: center must be finite", ctx));
  w.point = w.center = vec<D>(s.center);
  if (s.type == WallType::disk) {
    w.normal = w.axis = unit<D>(s.normal, ctx, "normal");
    positive(s.radius, ctx, "radius");
    if (!std::isfinite(s.inner_radius) || s.inner_radius < 0 || !(s.inner_radius < s.radius))
      throw InputError(
          fmt::format("{}: inner_radius must be >= 0 and less than radius ({} m), got {}", ctx,
                      s.radius, s.inner_radius));
    w.radius = s.radius;
    w.rho0 = s.inner_radius, w.rho1 = s.radius;
    return w;
  }
  if (D == 2 && s.type == WallType::cylinder)
    throw InputError(fmt::format(
        "{}: a cylinder in 2D is a circle about z and has no bounds; draw a channel with "
        "bounded planes",
        ctx));
  w.axis = unit<D>(s.axis, ctx, "axis");
  bounds(s, ctx);
  w.z0 = s.z_lo, w.z1 = s.z_hi;
  if (s.type == WallType::cylinder) {
    positive(s.radius, ctx, "radius");
    w.radius = w.rho0 = w.rho1 = s.radius;
    w.inside = s.inside;
    return w;
  }
  // cone
  for (double r : {s.radius_lo, s.radius_hi})
    if (!std::isfinite(r) || r < 0)
      throw InputError(
          fmt::format("{}: radii must be >= 0 [m], got {{{}, {}}}", ctx, s.radius_lo, s.radius_hi));
  if (!(s.radius_lo > 0 || s.radius_hi > 0))
    throw InputError(fmt::format("{}: radii must not both be 0", ctx));
  w.rho0 = s.radius_lo, w.rho1 = s.radius_hi;
  w.radius = std::max(s.radius_lo, s.radius_hi);
  return w;
}

template Wall<2> make_finite_wall<2>(const WallSpec&, const std::string&);
template Wall<3> make_finite_wall<3>(const WallSpec&, const std::string&);

}  // namespace granule
