// Simulation<D>::fill: placing `count` particles in a region (ball, box,
// cylinder) with radii from a rule, three seeded random streams (radii, places,
// velocities) and a placement test.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "core/errors.hpp"
#include "core/random.hpp"
#include "engine/simulation.hpp"

namespace granule {

namespace {
// SplitMix64's finaliser: one word to a well-mixed one, to seed streams that
// share no start.
std::uint64_t mixed_seed(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}
}  // namespace

template <int D>
std::vector<std::int64_t> Simulation<D>::fill(const FillSpec& f) {
  if (f.count < 0) throw InputError(fmt::format("fill: count must be >= 0, got {}", f.count));
  if (f.material < 0 || f.material >= static_cast<int>(materials_.size()))
    throw InputError("fill: unknown material");
  if (f.radii.empty() && !(f.radius_min > 0 && f.radius_max >= f.radius_min))
    throw InputError("fill: give 'radius' > 0, 'radii' or 0 < radius_min <= radius_max [m]");
  for (double r : f.radii)
    if (!(r > 0) || !std::isfinite(r))
      throw InputError(fmt::format("fill: radii must be > 0 [m], got {}", r));
  if (!(f.max_speed >= 0) || !std::isfinite(f.max_speed))
    throw InputError(fmt::format("fill: max_speed must be >= 0 [m/s], got {}", f.max_speed));
  refuse_beyond_memory(static_cast<std::int64_t>(p_.size()) + f.count, "fill");
  // Three streams, so that each draw depends on its own inputs only: the radii on
  // the size rule (a radius is drawn once per particle, whether or not its first
  // places are free, so the radii follow the rule and not the chance to be
  // placed), the velocities on max_speed, the places on the rest. Each starts
  // from the seed and the ids handed out before this fill, so that two fills of
  // one scene never repeat each other's draws, seed given or not, and a restart
  // or a spread run draws the same.
  const std::uint64_t base =
      mixed_seed(f.seed ^ mixed_seed(static_cast<std::uint64_t>(p_.next_id)));
  Random sizes(mixed_seed(base + 1)), places(mixed_seed(base + 2)), speeds(mixed_seed(base + 3));
  const double density = materials_[f.material].density;
  if (!(density > 0))
    throw InputError(
        fmt::format("fill: material '{}' needs a density > 0", materials_[f.material].name));

  // Region as a bounding box plus an inside test for a sphere of radius r.
  V lo = V::Zero(), hi = V::Zero();
  V centre = to_vec(f.center);
  auto inside_region = [&](const V& x, double r) {
    switch (f.shape) {
      case RegionShape::ball:
        return (x - centre).norm() + r <= f.radius;
      case RegionShape::box:
        for (int k = 0; k < D; ++k)
          if (x[k] - r < f.lo[k] || x[k] + r > f.hi[k]) return false;
        return true;
      case RegionShape::cylinder: {
        V d = x - centre;
        if constexpr (D == 3) {
          if (x[2] - r < f.z_min || x[2] + r > f.z_max) return false;
          d[2] = 0;
        }
        return d.norm() + r <= f.radius;
      }
    }
    return false;
  };
  switch (f.shape) {
    case RegionShape::ball:
    case RegionShape::cylinder:
      if (!(f.radius > 0)) throw InputError("fill: region radius must be > 0 [m]");
      lo = centre - V::Constant(f.radius);
      hi = centre + V::Constant(f.radius);
      if constexpr (D == 3) {
        if (f.shape == RegionShape::cylinder) {
          if (!(f.z_max > f.z_min)) throw InputError("fill: cylinder region needs z_max > z_min");
          lo[2] = f.z_min;
          hi[2] = f.z_max;
        }
      }
      break;
    case RegionShape::box:
      lo = to_vec(f.lo);
      hi = to_vec(f.hi);
      for (int k = 0; k < D; ++k)
        if (!(hi[k] > lo[k])) throw InputError("fill: box region needs hi > lo on every axis");
      break;
  }
  for (int k = 0; k < D; ++k)
    if (!std::isfinite(hi[k] - lo[k]))
      throw InputError(
          fmt::format("fill: the region's extent along {} is not a finite length", "xyz"[k]));

  if (f.count == 0) return {};
  // The radii, in the order the ids will follow.
  std::vector<double> radius(static_cast<std::size_t>(f.count));
  for (double& r : radius)
    r = f.radii.empty()
            ? sizes.uniform(f.radius_min, f.radius_max)
            : f.radii[std::min(f.radii.size() - 1,
                               static_cast<std::size_t>(sizes.uniform() * f.radii.size()))];
  const double r_new_max = *std::max_element(radius.begin(), radius.end());
  double room = INFINITY;  // the largest radius the region holds
  if (f.shape == RegionShape::box)
    for (int k = 0; k < D; ++k) room = std::min(room, (hi[k] - lo[k]) / 2);
  else
    room = f.radius;
  if (D == 3 && f.shape == RegionShape::cylinder) room = std::min(room, (f.z_max - f.z_min) / 2);
  if (r_new_max > room)
    throw InputError(fmt::format(
        "fill: a particle of radius {:g} m does not fit in the region (it holds radii up to "
        "{:g} m)",
        r_new_max, room));
  // Particles that may not overlap cannot take more than the region's volume
  // (several of one radius: more than the densest packing, pi / sqrt(18) of it
  // in 3D, pi / sqrt(12) of the area in 2D; a single one may fill a ball more).
  if (!f.allow_overlap) {
    double region = 1;
    if (f.shape == RegionShape::box)
      for (int k = 0; k < D; ++k) region *= hi[k] - lo[k];
    else if (f.shape == RegionShape::cylinder)
      region = M_PI * f.radius * f.radius * (f.z_max - f.z_min);
    else
      region = D == 3 ? 4 * M_PI / 3 * std::pow(f.radius, 3) : M_PI * f.radius * f.radius;
    double taken = 0;
    for (double r : radius) taken += D == 3 ? 4 * M_PI / 3 * r * r * r : M_PI * r * r;
    const bool one_size =
        f.count > 1 && (f.radii.empty() ? f.radius_min == f.radius_max
                                        : std::all_of(f.radii.begin(), f.radii.end(),
                                                      [&](double r) { return r == f.radii[0]; }));
    const double densest =
        one_size ? (D == 3 ? M_PI / std::sqrt(18.0) : M_PI / std::sqrt(12.0)) : 1;
    if (taken > densest * region)
      throw InputError(fmt::format(
          "fill: {} particles that may not overlap would take {:.3g} of the region's {}, more "
          "than {} ({:.3g}); random placement jams near {} of it: give a larger region or "
          "fewer particles, or overlap = true and let them settle",
          f.count, taken / region, D == 3 ? "volume" : "area",
          one_size ? "the densest packing of one size holds" : "there is", densest,
          D == 3 ? "0.38" : "0.55"));
  }

  // Fixed particles must never be overlapped (SPEC 2); other particles may be
  // (SPEC 2 for the Mechanofusion fill), unless the scene asks for no overlaps.
  // Occupied space goes into a hash grid of cells of side 2 r_max (r_max the
  // largest radius this fill draws): each particle is entered in every cell its
  // box, grown by r_max, touches, so a candidate looks in its own cell only.
  // A particle far larger than r_max (a 1 mm sphere among 10 um ones) would
  // cover (R / r_max)^D cells: those go into a second grid whose cells are as
  // large as the largest of them, where each covers at most 2^D cells. Entries
  // from n_before on are this fill's own particles, placed but not yet added.
  const std::size_t n_before = p_.size();
  std::vector<V> placed(radius.size());
  auto position_of = [&](std::size_t q) -> const V& {
    return q < n_before ? p_.position[q] : placed[q - n_before];
  };
  auto radius_of = [&](std::size_t q) {
    return q < n_before ? p_.radius[q] : radius[q - n_before];
  };
  const double large_radius = 4 * r_new_max;
  double largest = 0;
  for (std::size_t i = 0; i < n_before; ++i)
    if ((p_.fixed[i] || !f.allow_overlap) && p_.radius[i] > large_radius)
      largest = std::max(largest, p_.radius[i]);
  struct Grid {
    double cell;
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> occupied;
    static std::uint64_t key(const std::array<long long, 3>& c) {
      std::uint64_t k = 1469598103934665603ull;
      for (long long v : c) k = (k ^ static_cast<std::uint64_t>(v)) * 1099511628211ull;
      return k;
    }
    long long cell_of(double coordinate) const {
      return static_cast<long long>(std::floor(coordinate / cell));
    }
  };
  Grid small{2 * r_new_max, {}}, large{2 * (largest + r_new_max), {}};
  auto occupy = [&](std::size_t q) {
    Grid& g = radius_of(q) > large_radius ? large : small;
    const V& xq = position_of(q);
    const double reach = radius_of(q) + r_new_max;
    std::array<long long, 3> lo_c{0, 0, 0}, hi_c{0, 0, 0};
    for (int k = 0; k < D; ++k)
      lo_c[k] = g.cell_of(xq[k] - reach), hi_c[k] = g.cell_of(xq[k] + reach);
    for (long long a = lo_c[0]; a <= hi_c[0]; ++a)
      for (long long b = lo_c[1]; b <= hi_c[1]; ++b)
        for (long long c = lo_c[2]; c <= hi_c[2]; ++c)
          g.occupied[Grid::key({a, b, c})].push_back(static_cast<std::uint32_t>(q));
  };
  // A particle out of reach of the region (its radius plus the largest new one
  // beyond the box the candidates are drawn from, on an axis that does not wrap)
  // cannot overlap any of them: not entered, so that a small fill beside a large
  // bed costs what it places, not the bed's size.
  auto within_reach = [&](std::size_t i) {
    const double reach = p_.radius[i] + r_new_max;
    for (int k = 0; k < D; ++k) {
      if (periodic_.on() && k == periodic_.axis) continue;
      if (p_.position[i][k] + reach < lo[k] || p_.position[i][k] - reach > hi[k]) return false;
    }
    return true;
  };
  for (std::size_t i = 0; i < n_before; ++i)
    if ((p_.fixed[i] || !f.allow_overlap) && within_reach(i)) occupy(i);
  // Along a periodic axis every particle is in the box (the candidates too, below),
  // and one across the seam is entered at its own side of it: the candidate is
  // looked up at its images a period away too.
  const int images = periodic_.on() ? 3 : 1;
  auto overlaps_occupied = [&](const V& x, double r) {
    for (const Grid* g : {&small, &large}) {
      if (g->occupied.empty()) continue;
      for (int image = 0; image < images; ++image) {
        V y = x;
        if (image > 0) y[periodic_.axis] += image == 1 ? periodic_.length : -periodic_.length;
        std::array<long long, 3> c{0, 0, 0};
        for (int k = 0; k < D; ++k) c[k] = g->cell_of(y[k]);
        auto it = g->occupied.find(Grid::key(c));
        if (it == g->occupied.end()) continue;
        for (std::uint32_t q : it->second)
          if (separation(x, position_of(q)).norm() < r + radius_of(q)) return true;
      }
    }
    return false;
  };

  // Largest first: a large particle finds room more easily among few others,
  // and the small ones then fill the gaps.
  std::vector<std::size_t> order(radius.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return radius[a] > radius[b]; });
  const std::int64_t attempts_allowed =
      f.max_attempts > 0 ? f.max_attempts : 2000 * std::max<std::int64_t>(f.count, 1);
  // A region already full places nothing more however long it is tried (a
  // random packing without overlaps jams near 55 % of the area in 2D, 38 % of
  // the volume in 3D): so many attempts for one particle end the fill. And as
  // the region fills, places get rarer: once the particles left are all of the
  // radius being placed (one size, or the last of a list's), where even the rate
  // of the last window of attempts would not place them within what is left of
  // the budget, the fill ends then rather than when the budget is spent.
  // (Smaller particles still to come would place more easily than the window's.)
  constexpr std::int64_t attempts_in_a_row = 1000000;
  constexpr std::int64_t window = 1 << 20;
  const double smallest = radius[order.back()];
  std::int64_t attempts = 0, since_placed = 0, placed_count = 0;
  std::int64_t window_start = -1, placed_at_window = 0;  // -1: not yet at the last radius
  auto refuse = [&](const std::string& why) {
    throw InputError(fmt::format(
        "fill: placed only {} of {} particles after {} attempts{}; the region is too full{} or "
        "lies outside the walls",
        placed_count, f.count, attempts, why,
        f.allow_overlap ? "" : " for particles that may not overlap"));
  };
  for (const std::size_t k : order) {
    const double r = radius[k];
    for (;;) {
      ++attempts;
      if (attempts > attempts_allowed) refuse("");
      if (++since_placed > attempts_in_a_row)
        refuse(fmt::format(", the last {} without a place", since_placed - 1));
      if (window_start < 0 && r == smallest)
        window_start = attempts, placed_at_window = placed_count;
      if (window_start >= 0 && attempts - window_start == window) {
        const double rate = double(placed_count - placed_at_window) / window;
        const double left = double(f.count - placed_count);
        if (left > rate * double(attempts_allowed - attempts))
          refuse(fmt::format(
              ", the last {} placing {}: at that rate the other {} would need more attempts "
              "than the {} left",
              window, placed_count - placed_at_window, f.count - placed_count,
              attempts_allowed - attempts));
        window_start = attempts, placed_at_window = placed_count;
      }
      if (attempts % 4096 == 0 && f.stop_requested && f.stop_requested()) return {};
      V x;
      for (int c = 0; c < D; ++c) x[c] = places.uniform(lo[c], hi[c]);
      if (!inside_region(x, r)) continue;
      // Into the periodic box, where every other particle is: the look-up below takes
      // images one period away only, and a region may run over several periods.
      if (periodic_.on()) {
        const double along = x[periodic_.axis];
        if (!periodic_.wraps_exactly(along))
          throw InputError(fmt::format(
              "fill: the region reaches {} m along the periodic axis, more than a million "
              "periods ({} m each) from the box: its particles cannot be wrapped into it "
              "without losing their places to round-off",
              along, periodic_.length));
        x[periodic_.axis] = periodic_.into_box(along);
      }
      bool ok = true;
      for (std::size_t w = 0; w < walls_.size() && ok; ++w)
        ok = is_surface_wall(walls_[w].type) ? !meshes_.near(w, x, r) && !meshes_.inside_solid(w, x)
                                             : !(walls_[w].clearance(x, r) < 0);
      if (!ok || overlaps_occupied(x, r)) continue;
      placed[k] = x;
      ++placed_count;
      since_placed = 0;
      if (!f.allow_overlap) occupy(n_before + k);
      break;
    }
  }
  // Every particle has its place: added in the order of their radii's draws, each
  // with a random direction and a speed uniform in [0, max_speed].
  std::vector<std::int64_t> ids;
  ids.reserve(radius.size());
  for (std::size_t k = 0; k < radius.size(); ++k) {
    V v = V::Zero();
    if (f.max_speed > 0) {
      V dir;
      do {
        for (int c = 0; c < D; ++c) dir[c] = speeds.uniform(-1, 1);
      } while (dir.squaredNorm() > 1 || dir.squaredNorm() < 1e-6);
      v = dir.normalized() * speeds.uniform(0, f.max_speed);
    }
    ids.push_back(p_.add(placed[k], v, Dim<D>::zero_spin(), radius[k], density, f.material, false));
    position_at_rebuild_.push_back(placed[k]);
  }
  // Zero net momentum of the filled set (SPEC 2).
  if (!ids.empty() && f.max_speed > 0) {
    V momentum = V::Zero();
    double mass = 0;
    for (auto id : ids) {
      int i = p_.index(id);
      momentum += p_.mass[i] * p_.velocity[i];
      mass += p_.mass[i];
    }
    V mean = momentum / mass;
    double fastest = 0;
    for (auto id : ids) {
      V& v = p_.velocity[p_.index(id)];
      v -= mean;
      fastest = std::max(fastest, v.norm());
    }
    // Taking the mean off can push a speed past max_speed (few particles, unequal
    // masses): all scaled back by one factor, which keeps the momentum zero.
    if (fastest > f.max_speed)
      for (auto id : ids) p_.velocity[p_.index(id)] *= f.max_speed / fastest;
  }
  // A tube or cone is touched on both sides and has no inside, so the region alone
  // bounds the fill around it: one that placed particles on both sides of such a
  // wall (a hopper's bounding cylinder filled) has most likely put some where they
  // were not meant. Said, not refused: a draft tube is filled on both sides on
  // purpose.
  for (const Wall<D>& w : walls_) {
    if (!w.finite() || !(w.type == WallType::cone || w.type == WallType::cylinder)) continue;
    std::int64_t in = 0, out = 0;
    for (auto id : ids) {
      const V d = p_.position[p_.index(id)] - w.point;
      const double z = d.dot(w.axis);
      if (z < w.z0 || z > w.z1) continue;  // beyond its ends: neither side
      const double rho = (d - z * w.axis).norm();
      const double bound = w.rho0 + (w.rho1 - w.rho0) * (z - w.z0) / (w.z1 - w.z0);
      ++(rho < bound ? in : out);
    }
    if (in > 0 && out > 0)
      warn(fmt::format(
          "fill: {} of the {} particles placed lie outside {} '{}' and {} inside it: a finite "
          "wall is touched on both sides and has no inside, so only the region bounds a fill "
          "around it; if one side was meant, give a region on that side (docs/walls.md)",
          out, ids.size(), w.type == WallType::cone ? "cone" : "tube", w.name, in));
  }
  // A closed polyline that is not solid is a thin wall too, its inside no body
  // (the usual 2D container): the same said of it.
  if constexpr (D == 2)
    for (std::size_t w = 0; w < walls_.size(); ++w) {
      const auto* shape = meshes_.of_wall(w);
      if (!shape || shape->solid || !shape->surface->closed()) continue;
      std::int64_t in = 0, out = 0;
      for (auto id : ids)
        ++(shape->surface->encloses(shape->to_mesh(p_.position[p_.index(id)])) ? in : out);
      if (in > 0 && out > 0)
        warn(fmt::format(
            "fill: {} of the {} particles placed lie outside closed polyline '{}' and {} inside "
            "it: a polyline that is not solid is touched on both sides and has no inside, so only "
            "the region bounds a fill around it; if one side was meant, give a region on that "
            "side, or solid = true for a body (docs/walls.md)",
            out, ids.size(), walls_[w].name, in));
    }
  lists_valid_ = false;
  unprepare();
  arm_overlap_grace_for(ids);  // as add_particle: an overlapping fill's overlaps are the scene's
  return ids;
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace granule
