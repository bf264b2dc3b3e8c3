// Simulation<D>: set-up and validation -- the vector conversions, particle and
// wall input checks, adding and removing particles and walls, and the setters.
// The rest outside the step: simulation_fill.cpp, simulation_prepare.cpp,
// simulation_access.cpp.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "core/errors.hpp"
#include "core/plain_name.hpp"
#include "core/random.hpp"
#include "engine/finite_wall_setup.hpp"
#include "engine/simulation.hpp"
#include "neighbor/contact_lists.hpp"

namespace granule {

namespace {
// A coordinate along the periodic axis wrapped into the box; one so far out that
// the wrap would lose its place to round-off (a million periods) is refused.
double into_periodic_box(const Periodicity& p, double c, const char* what) {
  if (!p.wraps_exactly(c))
    throw InputError(fmt::format(
        "{}: {} m along the periodic axis is more than a million periods ({} m each) from "
        "the box: it cannot be wrapped into it without losing its place to round-off",
        what, c, p.length));
  return p.into_box(c);
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
  // A sphere's mass and moment of inertia (2D particles are spheres too) must
  // be finite and positive numbers, or every later step divides by them.
  const double mass = materials_[s.material].density * (4.0 / 3.0) * pi * std::pow(s.radius, 3);
  const double inertia = 0.4 * mass * s.radius * s.radius;
  if (!(mass > 0 && std::isfinite(mass) && inertia > 0 && std::isfinite(inertia)))
    throw InputError(fmt::format(
        "{}: radius {} m with density {} kg/m^3 gives a mass of {} kg and a moment of inertia of "
        "{} kg m^2, which are not finite positive numbers",
        context, s.radius, materials_[s.material].density, mass, inertia));
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
void Simulation<D>::warn_if_inside_solid(std::size_t w, const V& x, std::int64_t id,
                                         const char* caller, bool starts) const {
  if (!meshes_.inside_solid(w, x)) return;
  const Triple at = to_triple(x);
  warn(fmt::format(
      "{}particle {} at ({}) {} inside solid wall '{}': its contact throws it out through the "
      "nearest side, as fast as that overlap drives it",
      caller, id < 0 ? std::string("added") : std::to_string(id),
      fmt::join(at.begin(), at.begin() + D, ", "), starts ? "starts" : "lies", walls_[w].name));
}

// A particle placed during a scene (added, id < 0, or moved): its centre inside
// every wall, as prepare() holds the scene's starting particles to (and reads a
// centre just past a wall later on as a hard contact going on, which a particle
// just placed cannot be); inside a solid polyline or overlapping a wall, warned of.
template <int D>
void Simulation<D>::check_placed_in_walls(const V& at, double radius, bool fixed, std::int64_t id,
                                          const char* caller) const {
  const std::string who = id < 0 ? std::string("particle") : fmt::format("particle {}", id);
  for (std::size_t wi = 0; wi < walls_.size(); ++wi) {
    const auto& w = walls_[wi];
    const double c = w.clearance(at, radius);
    if (c + radius < 0)
      throw InputError(fmt::format("{}{} at ({}) would lie outside wall '{}'", caller, who,
                                   fmt::join(at.data(), at.data() + D, ", "), w.name));
    if (fixed) continue;
    warn_if_inside_solid(wi, at, id, caller);
    if (c < 0) warn(fmt::format("{}{} overlaps wall '{}' by {:.3g} m", caller, who, w.name, -c));
  }
}

template <int D>
std::int64_t Simulation<D>::add_particle(const ParticleSpec& s) {
  check_particle_input(s, "particle");
  V at = to_vec(s.position);
  // Into the periodic box now, as set_position (and prepare(), for a box declared later).
  if (periodic_.on())
    at[periodic_.axis] = into_periodic_box(periodic_, at[periodic_.axis], "particle position");
  if (step_ > 0) check_placed_in_walls(at, s.radius, s.fixed, -1, "");
  std::int64_t id = p_.add(at, to_vec(s.velocity), to_spin(s.spin), s.radius,
                           materials_[s.material].density, s.material, s.fixed);
  position_at_rebuild_.push_back(p_.position.back());
  lists_valid_ = false;
  unprepare();
  arm_overlap_grace_for(
      std::array<std::int64_t, 1>{id});  // a deep overlap made here is the scene's
  return id;
}

template <int D>
void Simulation<D>::remove_particle(std::int64_t id) {
  const std::size_t i = checked(id), last = p_.size() - 1;
  // Its parallel bonds break now (bond_counts says so at once, not at the next
  // step's apply_bonds, which would find it gone).
  bonds_.for_each_of(id, [&](std::size_t k) { bonds_.break_bond(k); });
  keep_contacts_by_id();
  if (gathered_contacts_) removed_from_gathered_.insert(id);
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
  list_indices_stale_ = true;
}

// The contact log names particles by storage index (hooks/contact_log.hpp),
// and so do the lists: the log's contacts become records by id, which queries
// read before the log (contacts(), the Lua views), and the log stops
// describing the particles. The lists carry their histories by id at their
// next rebuild.
template <int D>
void Simulation<D>::keep_contacts_by_id() {
  if (record_contacts_ && log_.filled && !gathered_contacts_ && !external_rebuilds_)
    gathered_contacts_ = contacts();
  log_.filled = false;
}

template <int D>
void Simulation<D>::reorder_storage(const std::vector<std::int64_t>& ids) {
  if (ids.size() != p_.size())
    throw InputError(fmt::format("reorder_storage: 'ids' names {} particles, the scene has {}",
                                 ids.size(), p_.size()));
  std::vector<std::uint32_t> order(ids.size());
  std::vector<std::uint8_t> named(p_.size(), 0);
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const int i = p_.index(ids[k]);
    if (i < 0) throw InputError(fmt::format("reorder_storage: 'ids' names no particle {}", ids[k]));
    if (named[i]++)
      throw InputError(fmt::format("reorder_storage: 'ids' names particle {} twice", ids[k]));
    order[k] = static_cast<std::uint32_t>(i);
  }
  keep_contacts_by_id();
  reorder_particles(p_, order);  // neighbor/contact_lists.hpp
  if (position_at_rebuild_.size() == order.size()) gather(position_at_rebuild_, order);
  // The lists name storage indices: rebuilt now, histories carried by id.
  if (lists_valid_)
    rebuild_lists();
  else
    list_indices_stale_ = true;
}

template <int D>
int Simulation<D>::add_wall(const WallSpec& s) {
  std::string ctx = fmt::format("wall '{}'", s.name);
  check_plain_name(s.name, "wall");
  for (const auto& w : walls_)
    if (w.name == s.name) throw InputError(fmt::format("{} is declared twice", ctx));
  if (s.material < 0 || s.material >= static_cast<int>(materials_.size()))
    throw InputError(fmt::format("{}: unknown material", ctx));
  if (s.finite()) {
    walls_.push_back(make_finite_wall<D>(s, ctx));
    lists_valid_ = false;
    unprepare();
    return static_cast<int>(walls_.size() - 1);
  }
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
  // Added during a scene, it must leave every centre inside (prepare() holds the
  // scene's start to that, and reads a centre just past a wall later on as a
  // hard contact going on, which a wall just added cannot be). A finite wall
  // is touched on both sides: no centre is outside it.
  if (step_ > 0)
    for (std::size_t i = 0; i < p_.size(); ++i)
      if (w.clearance(p_.position[i], p_.radius[i]) + p_.radius[i] < 0)
        throw InputError(fmt::format("{}: particle {} at ({}) would lie outside it", ctx, p_.id[i],
                                     fmt::join(to_triple(p_.position[i]), ", ")));
  walls_.push_back(w);
  lists_valid_ = false;
  unprepare();
  return static_cast<int>(walls_.size() - 1);
}

// ----------------------------------------------------------------------------
// Setters: body fields, walls and particles, their input checked
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
  body_.periodic_axis = periodic_.on() ? periodic_.axis : -1;  // prepare() sets it too
  set_central_strength(strength);
}
template <int D>
void Simulation<D>::set_central_strength(double strength) {
  // Without a field there is nothing to set: the call would change nothing, silently.
  if (!body_.central_on)
    throw InputError(
        "set_central_strength: the scene has no central field (sim:central_field declares one)");
  if (!std::isfinite(strength) || strength < 0)
    throw InputError(fmt::format("central field strength must be >= 0 [m/s^2], got {}", strength));
  body_.central_strength = strength;
}
template <int D>
void Simulation<D>::set_wall_velocity(int w, const Triple& v) {
  if (!finite3(v)) throw InputError("wall velocity must be finite");
  if (walls_.at(w).type == WallType::cylinder && !walls_[w].finite())
    throw InputError(
        fmt::format("wall '{}' is a cylinder: set its angular velocity", walls_[w].name));
  walls_[w].velocity = to_vec(v);
}
template <int D>
void Simulation<D>::set_wall_angular_velocity(int w, double omega) {
  if (!std::isfinite(omega)) throw InputError("wall angular velocity must be finite");
  const Wall<D>& x = walls_.at(w);
  if (x.type == WallType::plane)
    throw InputError(fmt::format("wall '{}' is a plane: set its velocity", x.name));
  if (D == 2 && x.finite() && omega != 0)
    throw InputError(fmt::format(
        "wall '{}' is a finite wall in 2D (its axis lies in the plane): it cannot turn", x.name));
  walls_[w].angular_velocity = omega;
}
template <int D>
void Simulation<D>::set_position(std::int64_t id, const Triple& x) {
  if (!finite3(x)) throw InputError("position must be finite");
  const int i = checked(id);
  V at = to_vec(x);
  // Into the periodic box, as prepare() puts every particle: the force loops'
  // minimum images shift by one period only.
  if (periodic_.on())
    at[periodic_.axis] = into_periodic_box(periodic_, at[periodic_.axis], "set_position");
  check_placed_in_walls(at, p_.radius[i], p_.fixed[i], id, "set_position: ");
  // A bond's load follows the particles' motion (parallel_bond.hpp), which a move
  // skips: its gap before the move is kept for settle_moved_bonds().
  bonds_.for_each_of(id, [&](std::size_t k) {
    if (bonds_.broken[k] || moved_bond_gaps_.count(k)) return;
    const int a = p_.index(bonds_.id_a[k]), b = p_.index(bonds_.id_b[k]);
    if (a >= 0 && b >= 0)
      moved_bond_gaps_[k] =
          separation(p_.position[a], p_.position[b]).norm() - p_.radius[a] - p_.radius[b];
  });
  p_.position[i] = at;
  lists_valid_ = false;
  arm_overlap_grace_for(std::array<std::int64_t, 1>{id});  // the scene's, not a pass-through
}
template <int D>
void Simulation<D>::set_velocity(std::int64_t id, const Triple& v) {
  if (!finite3(v)) throw InputError("velocity must be finite");
  int i = checked(id);
  note_bonded_motion(i);
  p_.velocity[i] = to_vec(v);  // a fixed particle's: its prescribed motion (leapfrog.hpp)
}
template <int D>
void Simulation<D>::set_spin(std::int64_t id, const Triple& w) {
  if (!finite3(w)) throw InputError("spin must be finite");
  int i = checked(id);
  note_bonded_motion(i);
  p_.spin[i] = to_spin(w);
}

template <int D>
void Simulation<D>::set_fixed(std::int64_t id, bool fixed) {
  const int i = checked(id);
  if (p_.fixed[i] && fixed) {  // fixed already: stopped where it is, if it moved
    note_bonded_motion(i);
    p_.velocity[i] = V::Zero();
    p_.spin[i] = Dim<D>::zero_spin();
    return;
  }
  if (!p_.fixed[i] && !fixed) return;
  // What it overlaps while fixed (another fixed particle, a wall) went
  // unchecked: freed, it is placed there as an added particle is, refused
  // outside a wall (before anything changes) and its overlaps the scene's, not
  // a pass-through.
  if (!fixed) check_placed_in_walls(p_.position[i], p_.radius[i], false, id, "set_fixed: ");
  note_bonded_motion(i);
  // Fixed where it is, it stops (a velocity set after moves it: prescribed
  // motion); freed, it goes on as it moved, from rest unless set moving.
  if (fixed) {
    p_.velocity[i] = V::Zero();
    p_.spin[i] = Dim<D>::zero_spin();
  }
  p_.fixed[i] = fixed ? Particles<D>::fixed_flag : 0;
  p_.inv_mass[i] = fixed ? 0.0 : 1.0 / p_.mass[i];
  p_.inv_inertia[i] = fixed ? 0.0 : 1.0 / sphere_inertia(p_.mass[i], p_.radius[i]);
  // The lists leave out pairs of fixed particles and fixed particles' wall
  // contacts, and the time-step rule reads the free particles: all made anew.
  // The bonds' stability limit reads the masses too.
  lists_valid_ = false;
  bond_step_checked_ = 0;
  unprepare();
  if (!fixed) arm_overlap_grace_for(std::array<std::int64_t, 1>{id});
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace granule
