// Parallel bonds in the engine (contact/parallel_bond.hpp): making them
// between the pairs a script names, adding their loads each step after the
// contacts', and their state in checkpoints.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "core/bytes.hpp"
#include "core/errors.hpp"
#include "core/state.hpp"
#include "engine/simulation.hpp"
#include "engine/state_checks.hpp"

namespace granule {

namespace {

void require_positive(double v, const char* name, const char* unit) {
  if (!(std::isfinite(v) && v > 0))
    throw InputError(
        fmt::format("bond: '{}' must be positive and finite ({}), got {}", name, unit, v));
}

}  // namespace

// The stiffest particle's bonded mode, omega^2 bounded by the row sums of the
// bonds' stiffness (Gershgorin): the intact bonds and the `fresh` ones about to be made.
template <int D>
typename Simulation<D>::BondMode Simulation<D>::stiffest_bond_mode(
    const std::vector<std::pair<std::int64_t, std::int64_t>>& fresh,
    const std::vector<BondProperties>& made) const {
  std::vector<double> row_sum(p_.size(), 0.0);
  std::vector<int> bonds_of(p_.size(), 0);
  auto load_ends = [&](int i, int j, const BondProperties& bp) {
    for (const int k : {i, j}) {
      const double r = p_.radius[k];
      const double mode =
          std::max({bp.normal_stiffness * bp.area * p_.inv_mass[k],
                    bp.shear_stiffness * bp.area * (p_.inv_mass[k] + r * r * p_.inv_inertia[k]),
                    bp.normal_stiffness * bp.inertia * p_.inv_inertia[k],
                    bp.shear_stiffness * bp.polar * p_.inv_inertia[k]});
      row_sum[static_cast<std::size_t>(k)] += 2 * mode;
      ++bonds_of[static_cast<std::size_t>(k)];
    }
  };
  for (std::size_t k = 0; k < bonds_.size(); ++k) {
    if (bonds_.broken[k]) continue;
    const int i = p_.index(bonds_.id_a[k]), j = p_.index(bonds_.id_b[k]);
    if (i >= 0 && j >= 0) load_ends(i, j, bonds_.properties[k]);
  }
  for (std::size_t k = 0; k < fresh.size(); ++k)
    load_ends(p_.index(fresh[k].first), p_.index(fresh[k].second), made[k]);
  BondMode out;
  for (std::size_t k = 0; k < row_sum.size(); ++k)
    if (row_sum[k] > out.omega_sq) out = {row_sum[k], k, bonds_of[k]};
  return out;
}

template <int D>
void Simulation<D>::settle_moved_bonds() {
  for (const auto& [k, before] : moved_bond_gaps_) {
    if (bonds_.broken[k]) continue;
    const int a = p_.index(bonds_.id_a[k]), b = p_.index(bonds_.id_b[k]);
    if (a < 0 || b < 0) continue;
    const double gap =
        separation(p_.position[a], p_.position[b]).norm() - p_.radius[a] - p_.radius[b];
    if (gap - before > std::min(p_.radius[a], p_.radius[b])) {
      bonds_.break_bond(k);
      warn(fmt::format(
          "set_position: the bond of particles {} and {} broke: the moves widened the gap "
          "between them by {:.3g} m, more than the smaller radius",
          bonds_.id_a[k], bonds_.id_b[k], gap - before));
    }
  }
  moved_bond_gaps_.clear();
}

// A time step set after the bonds were made (sim:set, a changed law) meets their limit too.
template <int D>
void Simulation<D>::check_bond_step() {
  if (bonds_.intact == 0) return;
  if (dt_ == bond_step_checked_ && bonds_.size() == bond_count_checked_ &&
      static_cast<std::size_t>(bonds_.intact) == bonds_intact_checked_)
    return;
  const BondMode mode = stiffest_bond_mode({}, {});
  if (mode.omega_sq > 0 && !(dt_ * std::sqrt(mode.omega_sq) < 1))
    throw InputError(fmt::format(
        "time step {:.4g} s is above the bonds' stability limit 1/omega = {:.4g} s (particle {} "
        "with {} bonds is the stiffest): set a time_step below the limit or soften the bonds",
        dt_, 1 / std::sqrt(mode.omega_sq), p_.id[mode.particle], mode.bonds));
  bond_step_checked_ = dt_;
  bond_count_checked_ = bonds_.size();
  bonds_intact_checked_ = static_cast<std::size_t>(bonds_.intact);
}

template <int D>
std::int64_t Simulation<D>::create_bonds(const BondSpec& spec) {
  require_positive(spec.normal_stiffness, "normal_stiffness", "Pa/m");
  require_positive(spec.shear_stiffness, "shear_stiffness", "Pa/m");
  require_positive(spec.tensile_strength, "tensile_strength", "Pa");
  require_positive(spec.shear_strength, "shear_strength", "Pa");
  require_positive(spec.radius_multiplier, "radius_multiplier", "-");
  if (!(std::isfinite(spec.gap) && spec.gap >= 0))
    throw InputError(fmt::format("bond: 'gap' must be finite and >= 0 (m), got {}", spec.gap));
  const int nm = static_cast<int>(materials_.size());
  for (int m : {spec.material_a, spec.material_b})
    if (m < -1 || m >= nm) throw InputError(fmt::format("bond: unknown material index {}", m));
  if (p_.size() < 2) return 0;
  ensure_prepared();  // the time step, against which the bonds' stiffness is checked

  // The pairs whose surfaces are at most `gap` apart. The cell lists give the
  // pairs strictly closer than r_i + r_j + skin: with a skin a hair beyond
  // `gap`, the test below decides the pairs exactly `gap` apart.
  double r_max = 0;
  for (double r : p_.radius) r_max = std::max(r_max, r);
  if (spec.gap > r_max)
    throw InputError(fmt::format(
        "bond: 'gap' = {:.4g} m exceeds the largest particle radius {:.4g} m: a bond spans a "
        "narrow gap between neighbours, not the space between non-neighbours",
        spec.gap, r_max));
  std::vector<std::pair<std::uint32_t, std::uint32_t>> near;
  CellGrid<D> grid;
  grid.build(p_, spec.gap + 1e-9 * r_max, periodic_, near);
  auto wanted = [&](int ma, int mb) {
    if (spec.material_a < 0) return true;
    return (ma == spec.material_a && mb == spec.material_b) ||
           (ma == spec.material_b && mb == spec.material_a);
  };
  std::vector<std::pair<std::int64_t, std::int64_t>> existing;
  existing.reserve(bonds_.size());
  for (std::size_t k = 0; k < bonds_.size(); ++k)
    existing.emplace_back(bonds_.id_a[k], bonds_.id_b[k]);
  std::sort(existing.begin(), existing.end());
  std::vector<std::pair<std::int64_t, std::int64_t>> fresh;
  for (const auto& [i, j] : near) {
    const V d = separation(p_.position[i], p_.position[j]);
    if (!(d.norm() - p_.radius[i] - p_.radius[j] <= spec.gap)) continue;
    if (!wanted(p_.material[i], p_.material[j])) continue;
    std::pair<std::int64_t, std::int64_t> ids{std::min(p_.id[i], p_.id[j]),
                                              std::max(p_.id[i], p_.id[j])};
    if (std::binary_search(existing.begin(), existing.end(), ids)) continue;
    fresh.push_back(ids);
  }
  // In id order, so that the bonds' sums do not depend on the storage order.
  std::sort(fresh.begin(), fresh.end());
  fresh.erase(std::unique(fresh.begin(), fresh.end()), fresh.end());

  // The bonds are springs that load each particle from every side at once: the
  // fastest mode of a bonded cluster is faster than any one bond's. By
  // Gershgorin's theorem every eigenvalue of the (mass-scaled) stiffness is at
  // most the largest row sum, which for particle i is bounded by
  // 2 sum_bonds k_b / m_i (the diagonal and as much again off it, for equal
  // neighbours); the same for the shear (whose end moves by the particle's
  // translation and its turn: 1/m_i + r_i^2/I_i), bending and twisting modes.
  // The step must resolve that bound as prepare() demands of a contact,
  // dt < 1/omega (half of leap-frog's 2/omega). For one bond between equal
  // free particles it is that bond's own frequency, sqrt(k (1/m_i + 1/m_j)).
  // Counted over the intact bonds already made as well as these: a particle
  // with many bonds needs softer ones (12 bonds: sqrt(12) times less stiff).
  std::vector<BondProperties> made;
  made.reserve(fresh.size());
  for (const auto& [a, b] : fresh) {
    const int i = p_.index(a), j = p_.index(b);
    const BondProperties bp =
        bond_properties(spec.radius_multiplier * std::min(p_.radius[i], p_.radius[j]), spec);
    for (double v : {bp.area, bp.inertia, bp.polar})
      if (!(std::isfinite(v) && v > 0))
        throw InputError(fmt::format(
            "bond: 'radius_multiplier' = {:.4g} gives a bond radius of {:.4g} m, whose section "
            "(area, moments) is not a positive finite number",
            spec.radius_multiplier, bp.radius));
    made.push_back(bp);
  }
  const BondMode mode = stiffest_bond_mode(fresh, made);
  if (mode.omega_sq > 0 && !(dt_ * std::sqrt(mode.omega_sq) < 1))
    throw InputError(fmt::format(
        "bond: normal_stiffness = {:.4g} Pa/m and shear_stiffness = {:.4g} Pa/m make the bonds' "
        "stability limit 1/omega = {:.4g} s shorter than the time step {:.4g} s (particle {} "
        "with {} bonds is the stiffest): soften the bonds or set a time_step below the limit",
        spec.normal_stiffness, spec.shear_stiffness, 1 / std::sqrt(mode.omega_sq), dt_,
        p_.id[mode.particle], mode.bonds));
  for (std::size_t k = 0; k < fresh.size(); ++k)
    bonds_.add(fresh[k].first, fresh[k].second, made[k]);
  return static_cast<std::int64_t>(fresh.size());
}

template <int D>
std::vector<SimulationBase::BondRecord> Simulation<D>::bond_records() const {
  std::vector<BondRecord> out(bonds_.size());
  for (std::size_t k = 0; k < bonds_.size(); ++k)
    out[k] = {bonds_.id_a[k], bonds_.id_b[k], bonds_.broken[k] != 0};
  return out;
}

template <int D>
void Simulation<D>::apply_bonds() {
  ForceTorque<D>* const load = p_.force_torque.data();
  // A rank's share (parallel/distributed_run.hpp) holds its owned particles
  // and ghosts: a bond is stepped where one of its particles is owned (the
  // other is then a ghost: the ghosts' reach covers the bonds), and a particle
  // that is not here is another rank's, not a removed one.
  const bool share = external_rebuilds_;
  for (std::size_t k = 0; k < bonds_.size(); ++k) {
    if (bonds_.broken[k]) continue;
    const int i = p_.index(bonds_.id_a[k]), j = p_.index(bonds_.id_b[k]);
    if (share && (i < 0 || j < 0 || ((p_.fixed[i] & ghost_flag) && (p_.fixed[j] & ghost_flag))))
      continue;
    if (i < 0 || j < 0) {  // a bonded particle was removed: nothing holds the other
      bonds_.break_bond(k);
      continue;
    }
    const V d = separation(p_.position[i], p_.position[j]);
    const double dist = d.norm();
    BondMotion<D> m;
    m.normal = dist > 0 ? V(d / dist) : V(V::UnitX());
    // The bond's centre lies midway in the gap (or overlap), at lever L_i from
    // i's centre and L_j from j's: L_i + L_j = |d|, so a pair moving as a rigid
    // body loads its bond not at all, and the loads exert no net torque
    // (angular momentum is conserved to round-off, as with the contacts).
    const double overlap = p_.radius[i] + p_.radius[j] - dist;
    const double lever_i = p_.radius[i] - 0.5 * overlap, lever_j = p_.radius[j] - 0.5 * overlap;
    // The velocities and spins that moved the pair over the step before (a
    // script's since are in bond_moved_with_), none for a bond made since.
    V vel_i = p_.velocity[i], vel_j = p_.velocity[j];
    S spin_i = p_.spin[i], spin_j = p_.spin[j];
    if (k >= bonds_unmoved_from_) {
      vel_i = vel_j = V::Zero();
      spin_i = spin_j = Dim<D>::zero_spin();
    } else if (!bond_moved_with_.empty()) {
      if (const auto a = bond_moved_with_.find(bonds_.id_a[k]); a != bond_moved_with_.end())
        vel_i = a->second.velocity, spin_i = a->second.spin;
      if (const auto b = bond_moved_with_.find(bonds_.id_b[k]); b != bond_moved_with_.end())
        vel_j = b->second.velocity, spin_j = b->second.spin;
    }
    const V v_centres = vel_j - vel_i;
    const V v_rel =
        v_centres + Dim<D>::spin_cross(S(lever_i * spin_i + lever_j * spin_j), m.normal);
    m.shear_velocity = v_rel - m.normal * v_rel.dot(m.normal);
    // The closing speed along d(t) + d(t - dt), d(t - dt) = d + v_centres dt
    // (parallel_bond.hpp: exact for a pair turning as one body).
    const V mid_chord = d + (0.5 * dt_) * v_centres;
    const double mid_length = mid_chord.norm();
    m.normal_velocity = v_centres.dot(mid_length > 0 ? V(mid_chord / mid_length) : m.normal);
    m.relative_spin = spin_j - spin_i;
    if constexpr (D == 3)
      m.mean_axial_spin = 0.5 * (spin_i + spin_j).dot(m.normal);
    else
      m.mean_axial_spin = 0;
    m.dt = dt_;
    BondLoad<D>& f = bonds_.load[k];
    if (advance_bond<D>(bonds_.properties[k], f, m)) {
      bonds_.break_bond(k);  // from this step on only the pair's contact law acts
      continue;
    }
    const V force = f.normal * m.normal + f.shear;
    const S n_cross_shear = Dim<D>::torque(m.normal, f.shear);
    S moment = f.bending;
    if constexpr (D == 3) moment += f.twist * m.normal;
    load[i].force += force;
    load[j].force -= force;
    load[i].torque += S(moment - lever_i * n_cross_shear);
    load[j].torque -= S(moment + lever_j * n_cross_shear);
  }
}

// ----------------------------------------------------------------------------
// Bonds over MPI ranks: every rank keeps every bond; each steps those with a
// particle it owns, and the owner of a bond's first particle (id_a) hands its
// state to every rank at each redistribution and gather.
// ----------------------------------------------------------------------------
template <int D>
void Simulation<D>::break_orphan_bonds() {
  for (std::size_t k = 0; k < bonds_.size(); ++k)
    if (!bonds_.broken[k] && (p_.index(bonds_.id_a[k]) < 0 || p_.index(bonds_.id_b[k]) < 0))
      bonds_.break_bond(k);
}

template <int D>
std::string Simulation<D>::pack_led_bonds() const {
  std::string out;
  for (std::size_t k = 0; k < bonds_.size(); ++k) {
    const int i = p_.index(bonds_.id_a[k]);
    if (i < 0 || (p_.fixed[i] & ghost_flag)) continue;
    bytes::put(out, static_cast<std::uint64_t>(k));
    bytes::put(out, bonds_.broken[k]);
    bytes::put(out, bonds_.load[k]);
  }
  return out;
}

template <int D>
void Simulation<D>::set_bond_states(const std::string& all) {
  const char* what = "distributed run: a bond's state";
  for (std::size_t at = 0; at < all.size();) {
    const auto k = static_cast<std::size_t>(bytes::take<std::uint64_t>(all, at, what));
    const std::uint8_t broken = bytes::take<std::uint8_t>(all, at, what);
    const BondLoad<D> load = bytes::take<BondLoad<D>>(all, at, what);
    if (k >= bonds_.size())
      throw RunError(fmt::format("{}: bond {} of {}", what, k, bonds_.size()));
    bonds_.load[k] = load;
    if (broken) bonds_.break_bond(k);
  }
}

template <int D>
double Simulation<D>::led_bond_reach() const {
  double reach = 0;
  for (std::size_t k = 0; k < bonds_.size(); ++k) {
    if (bonds_.broken[k]) continue;
    const int i = p_.index(bonds_.id_a[k]), j = p_.index(bonds_.id_b[k]);
    if (i < 0 || j < 0 || (p_.fixed[i] & ghost_flag)) continue;
    reach = std::max(reach, separation(p_.position[i], p_.position[j]).norm());
  }
  return reach;
}

// ----------------------------------------------------------------------------
// Checkpoints: every bond's ids, broken flag, properties and loads, exactly.
// A checkpoint written before bonds existed has none of the entries: no bonds.
// ----------------------------------------------------------------------------
namespace {
const char* const bond_keys[] = {"bonds.ids", "bonds.broken", "bonds.properties", "bonds.load"};
}

template <int D>
void Simulation<D>::save_bonds(StateBlob& s) const {
  const std::size_t n = bonds_.size();
  std::vector<std::int64_t> ids(2 * n), broken(n);
  std::vector<double> props, loads;
  props.reserve(BondProperties::doubles * n);
  loads.reserve(BondLoad<D>::doubles * n);
  for (std::size_t k = 0; k < n; ++k) {
    ids[2 * k] = bonds_.id_a[k], ids[2 * k + 1] = bonds_.id_b[k];
    broken[k] = bonds_.broken[k];
    const BondProperties& b = bonds_.properties[k];
    props.insert(props.end(), {b.radius, b.area, b.inertia, b.polar, b.normal_stiffness,
                               b.shear_stiffness, b.tensile_strength, b.shear_strength});
    const BondLoad<D>& f = bonds_.load[k];
    loads.push_back(f.normal);
    for (int a = 0; a < D; ++a) loads.push_back(f.shear[a]);
    loads.push_back(f.twist);
    if constexpr (D == 3)
      for (int a = 0; a < 3; ++a) loads.push_back(f.bending[a]);
    else
      loads.push_back(f.bending);
  }
  s.integers["bonds.ids"] = std::move(ids);
  s.integers["bonds.broken"] = std::move(broken);
  s.doubles["bonds.properties"] = std::move(props);
  s.doubles["bonds.load"] = std::move(loads);
  if (n == 0) return;
  s.integers["bonds.unmoved_from"] = {static_cast<std::int64_t>(bonds_unmoved_from_)};
  if (bond_moved_with_.empty()) return;
  std::vector<std::int64_t> moved_ids;
  std::vector<double> moved;
  for (const auto& [id, w] : bond_moved_with_) {
    moved_ids.push_back(id);
    for (int a = 0; a < D; ++a) moved.push_back(w.velocity[a]);
    const Triple spin = spin_triple(w.spin);
    moved.insert(moved.end(), spin.begin(), spin.end());
  }
  s.integers["bonds.moved_with.ids"] = std::move(moved_ids);
  s.doubles["bonds.moved_with"] = std::move(moved);
}

template <int D>
typename Simulation<D>::BondMotionState Simulation<D>::read_bond_motion(const StateBlob& s,
                                                                        std::size_t bonds) const {
  BondMotionState out;
  out.unmoved_from = bonds;
  if (s.has("bonds.unmoved_from")) {
    const auto& from = s.i("bonds.unmoved_from");
    if (from.size() != 1 || from[0] < 0 || static_cast<std::size_t>(from[0]) > bonds)
      refuse_entry("bonds.unmoved_from", fmt::format("must be one bond index from 0 to {}", bonds));
    out.unmoved_from = static_cast<std::size_t>(from[0]);
  }
  if (!s.has("bonds.moved_with.ids")) return out;
  const auto& ids = s.i("bonds.moved_with.ids");
  const auto& moved = s.d("bonds.moved_with");
  constexpr std::size_t per = D + 3;
  if (moved.size() != per * ids.size())
    refuse_entry("bonds.moved_with", fmt::format("has {} values, expected {} (from "
                                                 "'bonds.moved_with.ids')",
                                                 moved.size(), per * ids.size()));
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const double* q = &moved[per * k];
    for (std::size_t e = 0; e < per; ++e)
      if (!std::isfinite(q[e]))
        refuse_entry("bonds.moved_with", fmt::format("value {} is not finite", per * k + e));
    MovedWith w;
    for (int a = 0; a < D; ++a) w.velocity[a] = q[a];
    w.spin = to_spin(Triple{q[D], q[D + 1], q[D + 2]});
    out.moved_with[ids[k]] = w;
  }
  return out;
}

template <int D>
ParallelBonds<D> Simulation<D>::read_bonds(const StateBlob& s) const {
  bool any = false;
  for (const char* key : bond_keys) any = any || s.has(key);
  if (!any) return {};
  const std::int64_t next_id = s.i("meta").at(3);  // checked by check_state
  const auto& ids = s.i("bonds.ids");
  const auto& broken = s.i("bonds.broken");
  const auto& props = s.d("bonds.properties");
  const auto& loads = s.d("bonds.load");
  if (ids.size() % 2)
    refuse_entry("bonds.ids", fmt::format("has {} values, not pairs", ids.size()));
  const std::size_t n = ids.size() / 2;
  auto sized = [&](const char* key, std::size_t size, std::size_t per) {
    if (size != n * per)
      refuse_entry(key,
                   fmt::format("has {} values, expected {} (from 'bonds.ids')", size, n * per));
  };
  sized("bonds.broken", broken.size(), 1);
  sized("bonds.properties", props.size(), BondProperties::doubles);
  sized("bonds.load", loads.size(), BondLoad<D>::doubles);
  for (std::size_t k = 0; k < n; ++k) {
    const std::int64_t a = ids[2 * k], b = ids[2 * k + 1];
    if (a < 0 || b < 0 || a >= next_id || b >= next_id || !(a < b))
      refuse_entry("bonds.ids",
                   fmt::format("bond {} joins ids {} and {}: each must be a particle id below {}, "
                               "the first the smaller",
                               k, a, b, next_id));
    if (broken[k] != 0 && broken[k] != 1)
      refuse_entry("bonds.broken", fmt::format("value {} is {}: must be 0 or 1", k, broken[k]));
  }
  for (std::size_t e = 0; e < props.size(); ++e)
    if (!(std::isfinite(props[e]) && props[e] > 0))
      refuse_entry("bonds.properties",
                   fmt::format("value {} is {}: must be positive and finite", e, props[e]));
  for (std::size_t e = 0; e < loads.size(); ++e)
    if (!std::isfinite(loads[e]))
      refuse_entry("bonds.load", fmt::format("value {} is {}: must be finite", e, loads[e]));
  ParallelBonds<D> out;
  for (std::size_t k = 0; k < n; ++k) {
    const double* q = &props[BondProperties::doubles * k];
    BondProperties b;
    b.radius = q[0], b.area = q[1], b.inertia = q[2], b.polar = q[3];
    b.normal_stiffness = q[4], b.shear_stiffness = q[5];
    b.tensile_strength = q[6], b.shear_strength = q[7];
    out.add(ids[2 * k], ids[2 * k + 1], b);
    const double* f = &loads[BondLoad<D>::doubles * k];
    BondLoad<D>& l = out.load.back();
    l.normal = f[0];
    for (int a = 0; a < D; ++a) l.shear[a] = f[1 + a];
    l.twist = f[1 + D];
    if constexpr (D == 3)
      for (int a = 0; a < 3; ++a) l.bending[a] = f[2 + D + a];
    else
      l.bending = f[2 + D];
    if (broken[k]) out.break_bond(k);
  }
  return out;
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace granule
