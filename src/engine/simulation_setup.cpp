// Simulation<D>: set-up, validation, accessors and reports -- everything
// outside the step (simulation.cpp).
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
bool finite3(const Triple& t) {
  return std::isfinite(t[0]) && std::isfinite(t[1]) && std::isfinite(t[2]);
}
}  // namespace

// ----------------------------------------------------------------------------
// Set-up and validation
// ----------------------------------------------------------------------------
template <int D>
typename Simulation<D>::V Simulation<D>::to_vec(const Triple& t) const {
  V v;
  for (int k = 0; k < D; ++k) v[k] = t[k];
  return v;
}
template <int D>
Triple Simulation<D>::to_triple(const V& v) const {
  Triple t{0, 0, 0};
  for (int k = 0; k < D; ++k) t[k] = v[k];
  return t;
}
template <int D>
typename Simulation<D>::S Simulation<D>::to_spin(const Triple& t) const {
  if constexpr (D == 2) {
    return t[2];
  } else {
    return S(t[0], t[1], t[2]);
  }
}
template <int D>
Triple Simulation<D>::spin_triple(const S& s) const {
  if constexpr (D == 2) {
    return Triple{0, 0, s};
  } else {
    return Triple{s[0], s[1], s[2]};
  }
}

template <int D>
int Simulation<D>::checked(std::int64_t id) const {
  int i = p_.index(id);
  if (i < 0) throw InputError(fmt::format("no particle with id {}", id));
  return i;
}

template <int D>
void Simulation<D>::check_particle_input(const ParticleSpec& s, const std::string& context) const {
  if (!(s.radius > 0) || !std::isfinite(s.radius))
    throw InputError(fmt::format("{}: radius must be > 0 [m], got {}", context, s.radius));
  if (s.material < 0 || s.material >= static_cast<int>(materials_.size()))
    throw InputError(fmt::format("{}: unknown material", context));
  if (!(materials_[s.material].density > 0))
    throw InputError(fmt::format("{}: material '{}' needs a density > 0 [kg/m^3] for particles",
                                 context, materials_[s.material].name));
  if (!finite3(s.position) || !finite3(s.velocity) || !finite3(s.spin))
    throw InputError(fmt::format("{}: position, velocity and spin must be finite", context));
}

// A request for more particles than the machine's memory holds is refused at
// once, instead of thrashing or failing deep inside an allocation. Per
// particle: its arrays (positions, velocities, spins, forces, radii, masses,
// ids, the list's reference positions: ~200 bytes in 3D) and its share of
// the neighbour candidates, ~10 per particle in a dense 3D pack at the
// automatic skin, each with indices, ids and a contact history (~100 bytes).
template <int D>
void Simulation<D>::refuse_beyond_memory(std::int64_t particles, const char* what) const {
  const double per_particle =
      static_cast<double>(4 * sizeof(V) + sizeof(S) + sizeof(ForceTorque<D>) + 4 * sizeof(double) +
                          sizeof(std::int64_t) + 2 * sizeof(std::int32_t) + 1) +
      10.0 * 100.0;
  const double needed = per_particle * static_cast<double>(particles);
  const double available = available_memory_bytes();
  if (available > 0 && needed > available)
    throw InputError(fmt::format(
        "{}: {} particles need about {:.3g} GB (about {:.0f} bytes each, with their neighbour "
        "candidates), more than the {:.3g} GB of memory available (MemAvailable, /proc/meminfo)",
        what, particles, needed / 1e9, per_particle, available / 1e9));
}

template <int D>
std::int64_t Simulation<D>::add_particle(const ParticleSpec& s) {
  check_particle_input(s, "particle");
  std::int64_t id = p_.add(to_vec(s.position), to_vec(s.velocity), to_spin(s.spin), s.radius,
                           materials_[s.material].density, s.material, s.fixed);
  position_at_rebuild_.push_back(p_.position.back());
  lists_valid_ = false;
  prepared_ = false;
  return id;
}

template <int D>
void Simulation<D>::remove_particle(std::int64_t id) {
  const std::size_t i = checked(id), last = p_.size() - 1;
  auto erase = [&](auto& v) {
    v[i] = v[last];
    v.pop_back();
  };
  erase(p_.position), erase(p_.velocity), erase(p_.force_torque), erase(p_.spin);
  erase(p_.radius), erase(p_.inv_mass), erase(p_.inv_inertia), erase(p_.mass), erase(p_.id);
  erase(p_.material), erase(p_.fixed), erase(position_at_rebuild_);
  p_.index_of_id[id] = -1;
  if (i != last) p_.index_of_id[p_.id[i]] = static_cast<std::int32_t>(i);
  lists_valid_ = false;
}

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
  Random rng(f.seed);
  const double density = materials_[f.material].density;
  if (!(density > 0))
    throw InputError(
        fmt::format("fill: material '{}' needs a density > 0", materials_[f.material].name));

  // Region as a bounding box plus an inside test for a sphere of radius r.
  V lo, hi;
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
  // Fixed particles must never be overlapped (SPEC 2); other particles may be
  // (SPEC 2 for the Mechanofusion fill), unless the scene asks for no overlaps.
  // Occupied space goes into a hash grid of cells of side 2 r_max (r_max the
  // largest radius this fill draws): each particle is entered in every cell its
  // box, grown by r_max, touches, so a candidate looks in its own cell only.
  double r_new_max = f.radius_max;
  for (double r : f.radii) r_new_max = std::max(r_new_max, r);
  const double cell = 2 * r_new_max;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> occupied;
  auto cell_key = [&](const std::array<long long, 3>& c) {
    std::uint64_t k = 1469598103934665603ull;
    for (long long v : c) k = (k ^ static_cast<std::uint64_t>(v)) * 1099511628211ull;
    return k;
  };
  auto cell_of = [&](double coordinate) {
    return static_cast<long long>(std::floor(coordinate / cell));
  };
  auto occupy = [&](std::size_t q) {
    const V& xq = p_.position[q];
    const double reach = p_.radius[q] + r_new_max;
    std::array<long long, 3> lo_c{0, 0, 0}, hi_c{0, 0, 0};
    for (int k = 0; k < D; ++k) lo_c[k] = cell_of(xq[k] - reach), hi_c[k] = cell_of(xq[k] + reach);
    for (long long a = lo_c[0]; a <= hi_c[0]; ++a)
      for (long long b = lo_c[1]; b <= hi_c[1]; ++b)
        for (long long c = lo_c[2]; c <= hi_c[2]; ++c)
          occupied[cell_key({a, b, c})].push_back(static_cast<std::uint32_t>(q));
  };
  for (std::size_t i = 0; i < p_.size(); ++i)
    if (p_.fixed[i] || !f.allow_overlap) occupy(i);
  auto overlaps_occupied = [&](const V& x, double r) {
    std::array<long long, 3> c{0, 0, 0};
    for (int k = 0; k < D; ++k) c[k] = cell_of(x[k]);
    auto it = occupied.find(cell_key(c));
    if (it == occupied.end()) return false;
    for (std::uint32_t q : it->second)
      if (separation(x, p_.position[q]).norm() < r + p_.radius[q]) return true;
    return false;
  };

  const std::int64_t attempts_allowed =
      f.max_attempts > 0 ? f.max_attempts : 2000 * std::max<std::int64_t>(f.count, 1);
  std::vector<std::int64_t> ids;
  std::int64_t attempts = 0;
  std::vector<V> velocities;
  while (static_cast<std::int64_t>(ids.size()) < f.count) {
    if (++attempts > attempts_allowed)
      throw InputError(fmt::format(
          "fill: placed only {} of {} particles after {} attempts; the region is too full{} or "
          "lies outside the walls",
          ids.size(), f.count, attempts_allowed,
          f.allow_overlap ? "" : " for particles that may not overlap"));
    double r = f.radii.empty()
                   ? rng.uniform(f.radius_min, f.radius_max)
                   : f.radii[std::min(f.radii.size() - 1,
                                      static_cast<std::size_t>(rng.uniform() * f.radii.size()))];
    V x;
    for (int k = 0; k < D; ++k) x[k] = rng.uniform(lo[k], hi[k]);
    if (!inside_region(x, r)) continue;
    bool ok = true;
    for (const auto& w : walls_)
      if (w.clearance(x, r) < 0) {
        ok = false;
        break;
      }
    if (!ok || overlaps_occupied(x, r)) continue;
    // Random direction, speed uniform in [0, max_speed].
    V v = V::Zero();
    if (f.max_speed > 0) {
      V dir;
      do {
        for (int k = 0; k < D; ++k) dir[k] = rng.uniform(-1, 1);
      } while (dir.squaredNorm() > 1 || dir.squaredNorm() < 1e-6);
      v = dir.normalized() * rng.uniform(0, f.max_speed);
    }
    ids.push_back(p_.add(x, v, Dim<D>::zero_spin(), r, density, f.material, false));
    position_at_rebuild_.push_back(x);
    if (!f.allow_overlap) occupy(p_.size() - 1);
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
    for (auto id : ids) p_.velocity[p_.index(id)] -= mean;
  }
  lists_valid_ = false;
  prepared_ = false;
  return ids;
}

template <int D>
int Simulation<D>::add_wall(const WallSpec& s) {
  std::string ctx = fmt::format("wall '{}'", s.name);
  if (s.name.empty()) throw InputError("wall: 'name' must not be empty");
  for (const auto& w : walls_)
    if (w.name == s.name) throw InputError(fmt::format("{} is declared twice", ctx));
  if (s.material < 0 || s.material >= static_cast<int>(materials_.size()))
    throw InputError(fmt::format("{}: unknown material", ctx));
  Wall<D> w;
  w.name = s.name;
  w.type = s.type;
  w.material = s.material;
  if (s.type == WallType::plane) {
    if (!finite3(s.point) || !finite3(s.normal) || !finite3(s.velocity))
      throw InputError(fmt::format("{}: point, normal and velocity must be finite", ctx));
    w.point = to_vec(s.point);
    V nn = to_vec(s.normal);
    if (!(nn.norm() > 0)) throw InputError(fmt::format("{}: normal must be non-zero", ctx));
    w.normal = nn.normalized();
    w.velocity = to_vec(s.velocity);
  } else {
    if (!(s.radius > 0) || !std::isfinite(s.radius))
      throw InputError(fmt::format("{}: radius must be > 0 [m], got {}", ctx, s.radius));
    if (!finite3(s.center) || !finite3(s.axis) || !std::isfinite(s.angular_velocity))
      throw InputError(fmt::format("{}: center, axis and angular_velocity must be finite", ctx));
    w.center = to_vec(s.center);
    w.radius = s.radius;
    w.inside = s.inside;
    w.angular_velocity = s.angular_velocity;
    if constexpr (D == 3) {
      V a = to_vec(s.axis);
      if (!(a.norm() > 0)) throw InputError(fmt::format("{}: axis must be non-zero", ctx));
      w.axis = a.normalized();
    }
  }
  walls_.push_back(w);
  lists_valid_ = false;
  prepared_ = false;
  return static_cast<int>(walls_.size() - 1);
}

template <int D>
TimeStepReport Simulation<D>::time_step_rule() {
  TimeStepReport r;
  r.rule = INFINITY;
  r.stability_limit = INFINITY;
  const int nm = static_cast<int>(materials_.size());
  // Smallest free-particle mass and radius per material (the shortest contacts).
  std::vector<double> min_mass(nm, INFINITY), min_radius(nm, INFINITY),
      min_radius_any(nm, INFINITY);
  std::vector<char> used(nm, 0), free_used(nm, 0);
  for (std::size_t i = 0; i < p_.size(); ++i) {
    int m = p_.material[i];
    used[m] = 1;
    min_radius_any[m] = std::min(min_radius_any[m], p_.radius[i]);
    if (!p_.fixed[i]) {
      free_used[m] = 1;
      min_mass[m] = std::min(min_mass[m], p_.mass[i]);
      min_radius[m] = std::min(min_radius[m], p_.radius[i]);
    }
  }
  // Eq. 6.1-6.2: Rayleigh time of the smallest particle of a material.
  auto rayleigh = [&](int m, double radius) -> double {
    const Material& mat = materials_[m];
    if (!(mat.young > 0) || !(mat.density > 0) || std::isinf(radius)) return INFINITY;
    const double shear = mat.young / (2 * (1 + mat.poisson));
    return pi * radius / (0.1631 * mat.poisson + 0.876605) * std::sqrt(mat.density / shear);
  };
  std::vector<char> wall_material(nm, 0);
  for (const auto& w : walls_) wall_material[w.material] = 1;
  auto consider = [&](int a, int b, const PairScale& scale, const char* kind) {
    const PairTable::Entry& e = pairs_.at(a, b);
    if (e.model < 0)
      throw InputError(fmt::format(
          "no contact law for materials '{}' and '{}' ({} contacts can occur): declare "
          "contact {{ '{}', '{}', model = ... }}",
          materials_[a].name, materials_[b].name, kind, materials_[a].name, materials_[b].name));
    for_each_model([&](auto index) {
      constexpr int I = decltype(index)::value;
      if (e.model != I) return;
      using M = ContactModelAt<I>;
      const auto& par = pairs_.params<I>()[e.slot];
      double rule = M::rule_time_step(par, scale, steps_per_contact_);
      // Leap-frog is stable on a spring for omega dt < 2, but an impact is resolved
      // only with more than ~pi steps per contact: nearer 2/omega the overlap a
      // particle jumps into on its first step stores more energy than it brought
      // (restitution 1.1 at 0.8 (2/omega), 3 at 0.99; tests/stress/dt_limit.lua).
      // So the accepted limit is half of it, 1/omega.
      double limit = 0.5 * M::stability_limit(par, scale);
      if (rule < r.rule) {
        r.rule = rule;
        r.governing_pair =
            fmt::format("{}-{} ({}, {})", materials_[a].name, materials_[b].name, M::name, kind);
      }
      if (limit < r.stability_limit) {
        r.stability_limit = limit;
        r.limit_pair =
            fmt::format("{}-{} ({}, {})", materials_[a].name, materials_[b].name, M::name, kind);
      }
    });
  };
  for (int a = 0; a < nm; ++a) {
    if (!free_used[a]) continue;
    for (int b = 0; b < nm; ++b) {
      if (!used[b]) continue;
      PairScale scale;
      double mb = free_used[b] ? min_mass[b] : INFINITY;
      scale.effective_mass = std::isinf(mb) ? min_mass[a] : min_mass[a] * mb / (min_mass[a] + mb);
      double ra = min_radius[a], rb = min_radius_any[b];
      scale.effective_radius = ra * rb / (ra + rb);
      scale.rayleigh_time =
          std::min(rayleigh(a, ra), rayleigh(b, free_used[b] ? min_radius[b] : INFINITY));
      consider(a, b, scale, "particle-particle");
    }
    for (int w = 0; w < nm; ++w)
      if (wall_material[w]) {
        PairScale scale{min_mass[a], min_radius[a], rayleigh(a, min_radius[a])};
        consider(a, w, scale, "particle-wall");
      }
  }
  return r;
}

template <int D>
void Simulation<D>::prepare() {
  // Every position inside the periodic box: the force loops take minimum images
  // of separations between two positions in the box (Periodicity::wrap).
  if (periodic_.on())
    for (auto& x : p_.position) {
      double& c = x[periodic_.axis];
      c -= periodic_.length * std::floor((c - periodic_.origin) / periodic_.length);
    }
  // Particles must start inside every wall (their centres on the allowed side).
  for (std::size_t i = 0; i < p_.size(); ++i) {
    for (const auto& w : walls_) {
      double c = w.clearance(p_.position[i], p_.radius[i]);
      if (c + p_.radius[i] < 0)
        throw InputError(fmt::format("particle {} at ({}) lies outside wall '{}'", p_.id[i],
                                     fmt::join(to_triple(p_.position[i]), ", "), w.name));
      if (c < 0 && !p_.fixed[i] && step_ == 0)
        warn(fmt::format("particle {} starts overlapping wall '{}' by {:.3g} m", p_.id[i], w.name,
                         -c));
    }
  }
  // Skin: automatic = half the median radius.
  if (skin_set_ > 0) {
    skin_ = skin_set_;
    // A skin beyond the scene's extent makes every pair a candidate: it is a
    // slip of units or of a factor, never a setting that helps.
    double extent = periodic_.on() ? periodic_.length : 0;
    if (p_.size()) {
      V lo = p_.position[0], hi = p_.position[0];
      auto include = [&](const V& x, double reach) {
        lo = lo.cwiseMin(x - V::Constant(reach));
        hi = hi.cwiseMax(x + V::Constant(reach));
      };
      for (std::size_t i = 0; i < p_.size(); ++i) include(p_.position[i], p_.radius[i]);
      for (const auto& w : walls_)
        include(w.type == WallType::plane ? w.point : w.center,
                w.type == WallType::plane ? 0.0 : w.radius);
      extent = std::max(extent, (hi - lo).maxCoeff());
    }
    if (p_.size() && skin_ > extent)
      throw InputError(fmt::format(
          "skin {:.4g} m is larger than the scene ({:.4g} m across its particles and walls): "
          "every pair would be a neighbour candidate; give a skin of a fraction of a radius "
          "(0 = automatic, half the median radius)",
          skin_, extent));
  } else if (p_.size()) {
    std::vector<double> r(p_.radius.begin(), p_.radius.end());
    std::nth_element(r.begin(), r.begin() + r.size() / 2, r.end());
    skin_ = 0.5 * r[r.size() / 2];
  }
  // Adhesive contacts persist past zero overlap, to the JKR separation point
  // (-alpha_f, Eq. 6.14): a pair stays in the neighbour list only while its gap
  // is below the skin, so the skin must exceed that reach, taken for the
  // largest effective radius (alpha_f grows as R*^(1/3)).
  contact_reach_ = 0;
  {
    double r_max = 0;
    for (double r : p_.radius) r_max = std::max(r_max, r);
    // Only pairs that can meet: an adhesive law declared for materials no
    // particle has must not widen the skin of the whole scene.
    for (auto [a, b] : pairs_in_use()) {
      const PairTable::Entry& e = pairs_.at(a, b);
      for_each_model([&](auto index) {
        constexpr int I = decltype(index)::value;
        using M = ContactModelAt<I>;
        if constexpr (M::adhesive)
          if (e.model == I)
            contact_reach_ = std::max(contact_reach_, M::reach(pairs_.params<I>()[e.slot], r_max));
      });
    }
  }
  // Spins are integrated only when some pair in use has friction: without it
  // no contact exerts a torque (simulation_effects.cpp).
  rotation_ = effects().rotation;
  if (contact_reach_ > 0 && !(skin_ > 1.5 * contact_reach_)) {
    if (skin_set_ > 0)
      throw InputError(fmt::format(
          "skin {:.4g} m is too small for the adhesive contacts: they last until the surfaces are "
          "{:.4g} m apart (the JKR separation point); give a skin above {:.4g} m",
          skin_, contact_reach_, 1.5 * contact_reach_));
    skin_ = 2 * contact_reach_;
  }
  if (periodic_.on()) {
    double r_max = 0;
    for (double r : p_.radius) r_max = std::max(r_max, r);
    if (periodic_.length < 2 * (2 * r_max + skin_))
      throw InputError(fmt::format(
          "periodic length {} m is too short: it must exceed twice the largest contact reach "
          "(2 (2 r_max + skin) = {} m)",
          periodic_.length, 2 * (2 * r_max + skin_)));
  }
  if (p_.size()) {
    TimeStepReport rule = time_step_rule();
    dt_governing_pair_ = rule.governing_pair;
    if (dt_fixed_ > 0) {
      dt_ = dt_fixed_;
      if (dt_ >= rule.stability_limit)
        throw InputError(fmt::format(
            "time_step {:.4g} s is above the stability limit 1/omega = {:.4g} s of {} (half of "
            "leap-frog's 2/omega: with fewer than pi steps per contact an impact gains energy): "
            "refused",
            dt_, rule.stability_limit, rule.limit_pair));
      if (dt_ > rule.rule * (1 + 1e-9))
        warn(
            fmt::format("time_step {:.4g} s exceeds the Eq. 4.1 rule {:.4g} s (n = {} steps per "
                        "contact) for {}",
                        dt_, rule.rule, steps_per_contact_, rule.governing_pair));
    } else if (dt_ == 0 || std::isinf(dt_)) {
      if (std::isinf(rule.rule))
        throw InputError("cannot choose a time step: no contact can occur; set time_step");
      dt_ = rule.rule;
    } else if (dt_ > rule.rule * (1 + 1e-9)) {
      // An automatic dt chosen earlier is too long for changed parameters (a
      // stiffer law, smaller particles): choose again. A dt that became shorter
      // than needed is kept, so that removing particles does not change it.
      dt_ = rule.rule;
    }
    // The automatic dt is t_c / n (Eq. 4.1): a small n puts it beyond the limit
    // as surely as a time_step does (n = 1 gives restitution 3 with Walton-Braun,
    // 17 with Hertz), so it is refused the same way. The limit is 1/omega, so
    // linear and Walton-Braun laws accept n > pi; Hertz and Thornton, whose rule
    // is 8 T_R / n against a limit of T_R / 2, n > 16.
    if (!(dt_fixed_ > 0) && dt_ >= rule.stability_limit)
      throw InputError(fmt::format(
          "steps_per_contact = {} gives a time step {:.4g} s (Eq. 4.1 for {}), above the "
          "stability limit 1/omega = {:.4g} s of {} (half of leap-frog's 2/omega: with fewer than "
          "pi steps per contact an impact gains energy): refused; raise steps_per_contact",
          steps_per_contact_, dt_, rule.governing_pair, rule.stability_limit, rule.limit_pair));
  } else if (dt_ == 0) {
    dt_ = dt_fixed_;
  }
  if (!(dt_ > 0)) throw InputError("no time step: the scene has no particles and no time_step");
  rebuild_lists();
  scene_overlaps_ = true;
  prepared_ = true;
}

// ----------------------------------------------------------------------------
// Accessors
// ----------------------------------------------------------------------------
template <int D>
void Simulation<D>::set_gravity(const Triple& g) {
  if (!finite3(g)) throw InputError("gravity must be finite");
  body_.gravity = to_vec(g);
  body_.gravity_on = !body_.gravity.isZero();
}
template <int D>
void Simulation<D>::set_central_field(const Triple& point, double strength) {
  if (!finite3(point)) throw InputError("central_field: point must be finite");
  body_.central_on = true;
  body_.central_point = to_vec(point);
  set_central_strength(strength);
}
template <int D>
void Simulation<D>::set_central_strength(double strength) {
  if (!std::isfinite(strength) || strength < 0)
    throw InputError(fmt::format("central field strength must be >= 0 [m/s^2], got {}", strength));
  body_.central_strength = strength;
}

template <int D>
int Simulation<D>::wall_id(const std::string& name) const {
  std::vector<std::string> names;
  for (std::size_t w = 0; w < walls_.size(); ++w) {
    if (walls_[w].name == name) return static_cast<int>(w);
    names.push_back(walls_[w].name);
  }
  std::string hint = nearest_name(name, names);
  throw InputError(fmt::format("unknown wall '{}'{}", name,
                               hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint)));
}
template <int D>
WallSpec Simulation<D>::wall(int w) const {
  const Wall<D>& x = walls_.at(w);
  WallSpec s;
  s.name = x.name;
  s.type = x.type;
  s.material = x.material;
  s.point = to_triple(x.point);
  s.normal = to_triple(x.normal);
  s.velocity = to_triple(x.velocity);
  s.center = to_triple(x.center);
  if constexpr (D == 3) s.axis = to_triple(x.axis);
  s.radius = x.radius;
  s.inside = x.inside;
  s.angular_velocity = x.angular_velocity;
  return s;
}
template <int D>
void Simulation<D>::set_wall_velocity(int w, const Triple& v) {
  if (!finite3(v)) throw InputError("wall velocity must be finite");
  if (walls_.at(w).type != WallType::plane)
    throw InputError(
        fmt::format("wall '{}' is a cylinder: set its angular velocity", walls_[w].name));
  walls_[w].velocity = to_vec(v);
}
template <int D>
void Simulation<D>::set_wall_angular_velocity(int w, double omega) {
  if (!std::isfinite(omega)) throw InputError("wall angular velocity must be finite");
  if (walls_.at(w).type != WallType::cylinder)
    throw InputError(fmt::format("wall '{}' is a plane: set its velocity", walls_[w].name));
  walls_[w].angular_velocity = omega;
}
template <int D>
Triple Simulation<D>::wall_force(int w) const {
  return to_triple(walls_.at(w).force);
}
template <int D>
double Simulation<D>::wall_axial_torque(int w) const {
  return walls_.at(w).axial_torque;
}

template <int D>
Triple Simulation<D>::position(std::int64_t id) const {
  return to_triple(p_.position[checked(id)]);
}
template <int D>
Triple Simulation<D>::velocity(std::int64_t id) const {
  return to_triple(p_.velocity[checked(id)]);
}
template <int D>
Triple Simulation<D>::spin(std::int64_t id) const {
  return spin_triple(p_.spin[checked(id)]);
}
template <int D>
Triple Simulation<D>::force(std::int64_t id) const {
  return to_triple(p_.force_torque[checked(id)].force);
}
template <int D>
void Simulation<D>::set_position(std::int64_t id, const Triple& x) {
  if (!finite3(x)) throw InputError("position must be finite");
  p_.position[checked(id)] = to_vec(x);
  lists_valid_ = false;
  scene_overlaps_ = true;  // a deep overlap made here is the scene's, not a pass-through
}
template <int D>
void Simulation<D>::set_velocity(std::int64_t id, const Triple& v) {
  if (!finite3(v)) throw InputError("velocity must be finite");
  int i = checked(id);
  if (p_.fixed[i]) throw InputError(fmt::format("particle {} is fixed: it cannot move", id));
  p_.velocity[i] = to_vec(v);
}
template <int D>
void Simulation<D>::set_spin(std::int64_t id, const Triple& w) {
  if (!finite3(w)) throw InputError("spin must be finite");
  int i = checked(id);
  if (p_.fixed[i]) throw InputError(fmt::format("particle {} is fixed: it cannot spin", id));
  p_.spin[i] = to_spin(w);
}

template <int D>
typename SimulationBase::FlatState Simulation<D>::flat_state() const {
  FlatState s;
  const std::size_t n = p_.size();
  s.id = p_.id;
  s.radius.assign(p_.radius.begin(), p_.radius.end());
  s.material = p_.material;
  s.fixed = p_.fixed;
  s.position.resize(n * D);
  s.velocity.resize(n * D);
  s.spin.resize(n * Dim<D>::spin_components);
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < D; ++k) {
      s.position[i * D + k] = p_.position[i][k];
      s.velocity[i * D + k] = p_.velocity[i][k];
    }
    if constexpr (D == 2) {
      s.spin[i] = p_.spin[i];
    } else {
      for (int k = 0; k < 3; ++k) s.spin[i * 3 + k] = p_.spin[i][k];
    }
  }
  return s;
}

template <int D>
GlobalStats Simulation<D>::stats() const {
  GlobalStats g;
  g.time = time_;
  g.step = step_;
  g.particles = static_cast<std::int64_t>(p_.size());
  V momentum = V::Zero();
  for (std::size_t i = 0; i < p_.size(); ++i) {
    if (p_.fixed[i]) continue;
    const double m = p_.mass[i];
    g.kinetic_translational += 0.5 * m * p_.velocity[i].squaredNorm();
    g.kinetic_rotational += 0.5 * sphere_inertia(m, p_.radius[i]) * Dim<D>::spin_sq(p_.spin[i]);
    momentum += m * p_.velocity[i];
    const V& x = p_.position[i];
    const V& v = p_.velocity[i];
    double spin_z;
    if constexpr (D == 2) {
      spin_z = p_.spin[i];
    } else {
      spin_z = p_.spin[i][2];
    }
    g.angular_momentum_z +=
        m * (x[0] * v[1] - x[1] * v[0]) + sphere_inertia(m, p_.radius[i]) * spin_z;
  }
  g.momentum = to_triple(momentum);
  g.contacts_particle = contacts_particle_;
  g.contacts_batched = contacts_batched_;
  g.contacts_wall = contacts_wall_;
  g.max_overlap_ratio = max_overlap_ratio_;
  g.candidate_pairs = static_cast<std::int64_t>(slot_count_);
  g.list_rebuilds = static_cast<std::int64_t>(rebuilds_);
  g.thread_rebalances = rebalances_;
  g.pair_list_prunes = prunes_;
  g.pair_candidates_visited = candidates_visited_;
  return g;
}

template <int D>
std::vector<ContactRecord> Simulation<D>::contacts() const {
  if (!record_contacts_)
    throw InputError(
        "contact forces are not recorded in this scene: set record_contacts = true in "
        "simulation { ... } (it costs a few stores per contact)");
  std::vector<ContactRecord> out;
  if (!log_.filled) return out;  // no step taken yet
  // Model names by slot range.
  std::vector<std::pair<std::size_t, const char*>> model_at;  // (first slot, name)
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    using M = ContactModelAt<I>;
    const auto& pb = std::get<I>(pair_buckets_);
    if (pb.size()) model_at.emplace_back(pb.offset, M::name);
    const auto& wb = std::get<I>(wall_buckets_);
    if (wb.size()) model_at.emplace_back(wb.offset, M::name);
  });
  std::sort(model_at.begin(), model_at.end());
  std::size_t m = 0;
  for (std::size_t s = 0; s < log_.size(); ++s) {
    while (m + 1 < model_at.size() && model_at[m + 1].first <= s) ++m;
    if (!log_.active[s]) continue;
    ContactRecord r;
    r.id_a = p_.id[log_.a[s]];
    if (ContactLog<D>::is_wall(log_.b[s])) {
      r.wall = ContactLog<D>::wall_of(log_.b[s]);
    } else {
      r.id_b = p_.id[log_.b[s]];
    }
    r.model = model_at.empty() ? "" : model_at[m].second;
    r.overlap = log_.overlap[s];
    r.normal_force = log_.normal_force[s];
    r.tangential_force = to_triple(log_.tangential[s]);
    r.normal = to_triple(log_.normal[s]);
    out.push_back(r);
  }
  return out;
}

// ----------------------------------------------------------------------------
// Diagnostics
// ----------------------------------------------------------------------------
template <int D>
int Simulation<D>::attach_diagnostic(const std::string& name, DiagnosticOptions& options) {
  options.set_context(fmt::format("diagnostic '{}'", name));
  auto made = make_diagnostic<D>(name, options);
  options.finish();
  return attach(std::move(made), name);
}

template <int D>
int Simulation<D>::attach(std::unique_ptr<Diagnostic<D>> diagnostic, const std::string& name) {
  if (!diagnostic) throw InputError("attach: no diagnostic");
  AttachedDiagnostic a;
  a.name = name;
  a.diagnostic = std::move(diagnostic);
  a.needs = a.diagnostic->needs();
  a.every = a.diagnostic->every();
  if (a.every < 1) throw InputError(fmt::format("diagnostic '{}': every must be >= 1", name));
  a.id = next_diagnostic_id_++;
  if (sink_) a.diagnostic->attach_output(sink_);
  diagnostics_.push_back(std::move(a));
  tracking_ = false;
  for (const auto& d : diagnostics_) tracking_ = tracking_ || d.needs.events;
  return diagnostics_.back().id;
}

template <int D>
Diagnostic<D>& Simulation<D>::diagnostic(int id) const {
  for (const auto& d : diagnostics_)
    if (d.id == id) return *d.diagnostic;
  throw InputError(fmt::format("no diagnostic with id {} (detached?)", id));
}

template <int D>
void Simulation<D>::detach_diagnostic(int id) {
  for (auto it = diagnostics_.begin(); it != diagnostics_.end(); ++it)
    if (it->id == id) {
      it->diagnostic->flush();
      diagnostics_.erase(it);
      tracking_ = false;
      for (const auto& d : diagnostics_) tracking_ = tracking_ || d.needs.events;
      if (!tracking_) {  // nobody tracks events any more: drop the per-contact state
        for_each_model([&](auto index) {
          constexpr int I = decltype(index)::value;
          std::get<I>(pair_buckets_).track.clear();
          std::get<I>(wall_buckets_).track.clear();
        });
      }
      return;
    }
  throw InputError(fmt::format("no diagnostic with id {} (detached already?)", id));
}

template <int D>
std::map<std::string, double> Simulation<D>::diagnostic_results(int id) const {
  return diagnostic(id).results();
}

template <int D>
std::map<std::string, std::vector<double>> Simulation<D>::diagnostic_arrays(int id) const {
  return diagnostic(id).arrays();
}

template <int D>
void Simulation<D>::set_output_sink(OutputSink* sink) {
  sink_ = sink;
  for (auto& d : diagnostics_) d.diagnostic->attach_output(sink);
}

template <int D>
void Simulation<D>::flush_diagnostics() {
  for (auto& d : diagnostics_) d.diagnostic->flush();
}

template <int D>
std::vector<std::string> Simulation<D>::describe() const {
  std::vector<std::string> lines;
  std::size_t fixed = 0;
  for (auto f : p_.fixed) fixed += f;
  lines.push_back(fmt::format("dimension: {}D{}", D,
                              periodic_.on() ? fmt::format(", periodic along axis {} ({} m)",
                                                           periodic_.axis, periodic_.length)
                                             : std::string()));
  lines.push_back(fmt::format("particles: {} ({} fixed)", p_.size(), fixed));
  auto catalogue = contact_model_catalogue();
  for (int a = 0; a < pairs_.material_count(); ++a)
    for (int b = a; b < pairs_.material_count(); ++b) {
      const auto& e = pairs_.at(a, b);
      if (e.model < 0) continue;
      std::vector<std::string> kv;
      for (const auto& [k, v] : pairs_.values(a, b)) kv.push_back(fmt::format("{}={}", k, v));
      lines.push_back(fmt::format("contact {}-{}: {} ({})", materials_[a].name, materials_[b].name,
                                  catalogue[e.model].name, fmt::join(kv, ", ")));
    }
  for (const auto& w : walls_) {
    if (w.type == WallType::plane)
      lines.push_back(
          fmt::format("wall {}: plane, material {}", w.name, materials_[w.material].name));
    else
      lines.push_back(fmt::format("wall {}: cylinder r={} m {}, {} rad/s, material {}", w.name,
                                  w.radius, w.inside ? "inside" : "outside", w.angular_velocity,
                                  materials_[w.material].name));
  }
  const ActiveEffects e = effects();
  lines.push_back(e.adhesion ? fmt::format("adhesion: on ({})", fmt::join(e.adhesive_pairs, ", "))
                             : std::string("adhesion: off (no adhesive pair in use)"));
  lines.push_back(e.rotation ? std::string("rotation: spins integrated (friction in use)")
                             : std::string("rotation: off (no pair in use has friction, so no "
                                           "torque acts; spins stay as set)"));
  lines.push_back(e.moving_walls.empty()
                      ? std::string("moving walls: none")
                      : fmt::format("moving walls: {}", fmt::join(e.moving_walls, ", ")));
  lines.push_back(fmt::format("gravity: {}", body_.gravity_on ? "on" : "off"));
  lines.push_back(fmt::format("central field: {}", body_.central_on ? "on" : "off"));
  lines.push_back(fmt::format("contact forces recorded: {}", record_contacts_ ? "yes" : "no"));
  if (diagnostics_.empty()) {
    lines.push_back("diagnostics: none");
  } else {
    for (const auto& d : diagnostics_)
      lines.push_back(fmt::format("diagnostic {}: {}", d.name, d.diagnostic->describe()));
  }
  lines.push_back(fmt::format("hooks: {}", hooks_.size()));
  lines.push_back(
      fmt::format("threads: {}{}", thread_count(),
                  threads_ > 0 ? "" : " (OMP_NUM_THREADS, else 1; set with --threads N)"));
  lines.push_back(fmt::format("time step: {:.6g} s ({}), skin {:.4g} m", dt_,
                              dt_fixed_ > 0
                                  ? "set by the scene"
                                  : fmt::format("automatic: n = {} steps per contact of {}",
                                                steps_per_contact_, dt_governing_pair_),
                              skin_));
  return lines;
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace granule
