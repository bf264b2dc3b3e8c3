// Simulation<D>: the time-step rule and prepare(), which checks the scene and
// builds what a run needs before its first step.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

#include "core/errors.hpp"
#include "core/random.hpp"
#include "engine/simulation.hpp"

namespace granule {

namespace {
template <typename Values>
double largest(const Values& radii) {
  double out = 0;
  for (const double r : radii) out = std::max(out, r);
  return out;
}
}  // namespace

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
  std::vector<std::size_t> count(nm, 0);
  for (std::size_t i = 0; i < p_.size(); ++i) {
    int m = p_.material[i];
    used[m] = 1;
    ++count[m];
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
  // E* and G* of a material's contact with itself (Pa; 0 without E): what the
  // Rayleigh limit stands for (softer_partner_limit).
  auto self_contact = [&](int m, PairScale& scale) {
    const Material& mat = materials_[m];
    if (!(mat.young > 0)) return;
    const double shear = mat.young / (2 * (1 + mat.poisson));
    scale.rayleigh_e_star = mat.young / (2 * (1 - mat.poisson * mat.poisson));
    scale.rayleigh_g_star = shear / (2 * (2 - mat.poisson));
  };
  std::vector<char> wall_material(nm, 0);
  for (const auto& w : walls_) wall_material[w.material] = 1;
  auto consider = [&](int a, int b, const PairScale& scale, const char* kind, double smaller,
                      bool can_meet) {
    const PairTable::Entry& e = pairs_.at(a, b);
    if (e.model < 0 && !can_meet) return;
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
        r.per_contact = M::steps_per_contact_counted;
      }
      if (limit < r.stability_limit) {
        r.stability_limit = limit;
        r.limit_pair =
            fmt::format("{}-{} ({}, {})", materials_[a].name, materials_[b].name, M::name, kind);
      }
      if constexpr (has_mode_squared<M>::value)
        r.deep_modes.push_back(
            {fmt::format("{}-{} ({}, {})", materials_[a].name, materials_[b].name, M::name, kind),
             smaller, std::string(kind) == "particle-wall", a, b,
             [par, scale](double overlap) { return M::mode_squared(par, scale, overlap); }});
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
      const double rayleigh_a = rayleigh(a, ra),
                   rayleigh_b = rayleigh(b, free_used[b] ? min_radius[b] : INFINITY);
      scale.rayleigh_time = std::min(rayleigh_a, rayleigh_b);
      self_contact(rayleigh_b < rayleigh_a ? b : a, scale);
      // A material's only particle meets none of its own: a sphere dropped on
      // a wall needs no law with itself (adding a second one prepares anew).
      // A law declared for it still enters the step's rule and limit.
      consider(a, b, scale, "particle-particle", std::min(ra, rb), b != a || count[a] > 1);
    }
    for (int w = 0; w < nm; ++w)
      if (wall_material[w]) {
        PairScale scale{min_mass[a], min_radius[a], rayleigh(a, min_radius[a])};
        self_contact(a, scale);
        consider(a, w, scale, "particle-wall", min_radius[a], true);
      }
  }
  return r;
}

template <int D>
double Simulation<D>::adhesive_reach() const {
  double reach = 0;
  const double r_max = largest(p_.radius);
  // Only pairs that can meet: an adhesive law declared for materials no
  // particle has must not widen the skin of the whole scene.
  for (auto [a, b] : pairs_in_use()) {
    const PairTable::Entry& e = pairs_.at(a, b);
    for_each_model([&](auto index) {
      constexpr int I = decltype(index)::value;
      using M = ContactModelAt<I>;
      if constexpr (M::adhesive)
        if (e.model == I) reach = std::max(reach, M::reach(pairs_.params<I>()[e.slot], r_max));
    });
  }
  return reach;
}

template <int D>
void Simulation<D>::choose_time_step() {
  const double dt_before = dt_;
  struct NoteChange {  // however this returns: when the step changed, for run_loop's count
    Simulation& sim;
    double before;
    ~NoteChange() {
      if (sim.dt_ != before) sim.dt_from_step_ = sim.step_, sim.dt_from_time_ = sim.time_;
    }
  } note{*this, dt_before};
  if (p_.size()) {
    TimeStepReport rule = time_step_rule();
    dt_governing_pair_ = rule.governing_pair;
    dt_per_contact_ = rule.per_contact;
    deep_modes_ = std::move(rule.deep_modes);
    deep_checked_pair_ = deep_checked_wall_ = 0;
    deep_rescan_step_ = -1;
    // A rolling pair's limit may be its epsd springs' modes (rolling.hpp), which the
    // step count does not move but mu_r and mu_t do.
    const std::string rolling_hint =
        rule.limit_pair.find("+rolling") != std::string::npos
            ? "; its limit includes the epsd rolling and twisting springs' modes (omega_r up to "
              "2.37 mu_r omega_n, omega_t up to 2.37 mu_t omega_n), which a lower "
              "rolling_friction or twisting_friction lifts"
            : "";
    const char* const rule_name = time_step_rule_name(rule.per_contact);
    if (dt_fixed_ > 0) {
      dt_ = dt_fixed_;
      if (dt_ >= rule.stability_limit)
        throw InputError(fmt::format(
            "time_step {:.4g} s is above the stability limit {:.4g} s of {} (half of leap-frog's "
            "2/omega for its stiffest mode, less where a dashpot would more than stop the pair in "
            "one step: beyond it an impact gains energy): refused{}",
            dt_, rule.stability_limit, rule.limit_pair, rolling_hint));
      if (dt_ > rule.rule * (1 + 1e-9)) {
        // Said once per rule: a ramp re-checks it every step it changes a law.
        std::string message = fmt::format(
            "time_step {:.4g} s exceeds the rule {} = {:.4g} s (n = {} steps_per_contact) for {}",
            dt_, rule_name, rule.rule, steps_per_contact_, rule.governing_pair);
        if (message != dt_warned_) warn(message);
        dt_warned_ = std::move(message);
      }
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
    // undamped linear and Walton-Braun laws accept n > pi; Hertz and Thornton, whose
    // rule is 8 T_R / n against a limit of T_R / 2, n > 16. A linear law's dashpots
    // lower the limit near e = 0 (linear_spring_dashpot.hpp).
    if (!(dt_fixed_ > 0) && dt_ >= rule.stability_limit)
      throw InputError(fmt::format(
          "steps_per_contact = {} gives a time step {:.4g} s ({} for {}), above the "
          "stability limit {:.4g} s of {} (half of leap-frog's 2/omega for its stiffest mode, "
          "less where a dashpot would more than stop the pair in one step: beyond it an impact "
          "gains energy): refused; raise steps_per_contact{}",
          steps_per_contact_, dt_, rule_name, rule.governing_pair, rule.stability_limit,
          rule.limit_pair, rolling_hint));
  } else if (dt_ == 0) {
    dt_ = dt_fixed_;
  }
  if (!(dt_ > 0)) throw InputError("no time step: the scene has no particles and no time_step");
  check_bond_step();
}

// Only a law's parameters changed since the last prepare() (lists_kept_): the
// lists hold (they depend on positions, the skin and which law each pair has,
// none of which changed), so a ramp that sets a law every step does not
// rebuild them every step. What the parameters decide is chosen again. An
// adhesive reach grown past what the skin allows needs the whole prepare().
template <int D>
bool Simulation<D>::prepare_parameters() {
  const double reach = adhesive_reach();
  if (reach > 0 && !(skin_ > 1.5 * reach)) return false;
  contact_reach_ = reach;
  rotation_ = effects().rotation;
  choose_time_step();
  prepared_ = true;
  lists_kept_ = false;
  return true;
}

// A periodic axis repeats the scene, its walls included, but a wall contact
// takes no periodic image: a wall must be the same all along the axis, or a
// particle that wraps lands on its other side (and is thrown out of it).
// Planes must contain the axis, cylinders lie along it; a mesh or a rectangle
// must span the period and a particle's radius beyond both of its ends.
template <int D>
void Simulation<D>::check_walls_repeat(bool moving_only) const {
  const int a = periodic_.axis;
  const double r_max = largest(p_.radius);
  double r_min = INFINITY;
  for (const double r : p_.radius) r_min = std::min(r_min, r);
  const double from = periodic_.origin - r_max, to = periodic_.origin + periodic_.length + r_max;
  auto refuse = [&](const Wall<D>& w, const std::string& why) {
    throw InputError(fmt::format(
        "wall '{}' {}, but the scene is periodic along {} ({} to {} m): a wall must repeat with "
        "the scene (a plane containing that axis, a cylinder along it, a mesh or rectangle "
        "spanning the period and a radius beyond it), since contacts with walls take no "
        "periodic image",
        w.name, why, "xyz"[a], periodic_.origin, periodic_.origin + periodic_.length));
  };
  auto spans = [&](const Wall<D>& w, double lo, double hi) {
    if (lo > from || hi < to)
      refuse(w, fmt::format("{}reaches only from {:.6g} to {:.6g} m along the axis",
                            moving_only ? "has moved along the axis and now " : "", lo, hi));
  };
  for (std::size_t k = 0; k < walls_.size(); ++k) {
    const Wall<D>& w = walls_[k];
    if (moving_only && !w.moves_along(a)) continue;
    if constexpr (D == 3) {
      switch (w.type) {
        case WallType::plane:
          if (std::abs(w.normal[a]) > 1e-9) refuse(w, "is a plane crossing the periodic axis");
          if (w.bounded) {
            const V other = w.normal.cross(w.side);
            const double half = std::abs(w.side[a]) * w.half_a + std::abs(other[a]) * w.half_b;
            spans(w, w.point[a] - half, w.point[a] + half);
          }
          break;
        case WallType::cylinder:
          if (w.bounded || std::abs(std::abs(w.axis[a]) - 1) > 1e-9)
            refuse(w, w.bounded ? "is a tube of finite length" : "is a cylinder across the axis");
          break;
        case WallType::mesh: {
          const auto* m = meshes_.of_wall(k);
          double lo = INFINITY, hi = -INFINITY;
          for (const auto& x : m->surface->vertices()) {
            const double c = m->to_scene(x)[a];
            lo = std::min(lo, c), hi = std::max(hi, c);
          }
          spans(w, lo, hi);
          // Spanning is not repeating: a face within reach of the box must run
          // straight along the axis (an extruded profile), or the mesh differs at
          // the box's two ends and a particle that wraps falls through it there.
          if (!moving_only) {
            const auto& vertex = m->surface->vertices();
            const auto& triangles = m->surface->triangles();
            for (std::size_t t = 0; t < triangles.size(); ++t) {
              const V p0 = m->to_scene(vertex[triangles[t][0]]);
              const V p1 = m->to_scene(vertex[triangles[t][1]]);
              const V p2 = m->to_scene(vertex[triangles[t][2]]);
              if (std::max({p0[a], p1[a], p2[a]}) < from || std::min({p0[a], p1[a], p2[a]}) > to)
                continue;
              const V normal = (p1 - p0).cross(p2 - p0);
              // Refused where the slope moves the surface over one period by more
              // than 1 % of the smallest radius (the step a wrapping particle meets
              // at the seam); a straight mesh written as float32 (binary STL) tilts
              // its faces by about 1e-6, far less.
              if (std::abs(normal[a]) * periodic_.length > 0.01 * r_min * normal.norm())
                refuse(w, fmt::format("has a face that slopes along the axis within the box "
                                      "(its triangle {}, normal ({:.3g}, {:.3g}, {:.3g})): "
                                      "a mesh there must run straight along the axis, the same "
                                      "at both ends of the period",
                                      t + 1, normal[0] / normal.norm(), normal[1] / normal.norm(),
                                      normal[2] / normal.norm()));
            }
          }
          break;
        }
        default:
          refuse(w, "is a disk or a cone");
      }
    }
  }
}

// A run's wall moved along the periodic axis (integrate() notes it): where it no
// longer spans the period, the run stops as for any failure, the state kept.
template <int D>
void Simulation<D>::report_walls_leave_period() {
  try {
    check_walls_repeat(true);
  } catch (const InputError& e) {
    fail(fmt::format("step {} (t = {:.6g} s): {}", step_, time_, e.what()));
  }
}

// The step-over checks' scales (simulation_checks.cpp): the smallest radius, and
// the smallest free one (a wall may pass a fixed particle, which it never touches).
template <int D>
void Simulation<D>::note_smallest_radii() {
  smallest_radius_ = smallest_free_radius_ = INFINITY;
  for (std::size_t i = 0; i < p_.size(); ++i) {
    smallest_radius_ = std::min(smallest_radius_, p_.radius[i]);
    if (!p_.fixed[i]) smallest_free_radius_ = std::min(smallest_free_radius_, p_.radius[i]);
  }
}

template <int D>
void Simulation<D>::prepare() {
  if (lists_kept_ && lists_valid_ && p_.size() && prepare_parameters()) return;
  // Every position inside the periodic box: the force loops take minimum images
  // of separations between two positions in the box (Periodicity::wrap).
  if (periodic_.on())
    for (auto& x : p_.position) x[periodic_.axis] = periodic_.into_box(x[periodic_.axis]);
  // Particles must start inside every wall (their centres on the allowed side).
  // A moving one placed inside a solid polyline is warned of.
  for (std::size_t i = 0; i < p_.size(); ++i) {
    // Once the scene has stepped, a fixed particle may lie where a moving wall
    // has passed: it touches no wall (set_fixed refuses to free it there).
    if (step_ > 0 && p_.fixed[i]) continue;
    for (std::size_t wi = 0; wi < walls_.size(); ++wi) {
      const auto& w = walls_[wi];
      double c = w.clearance(p_.position[i], p_.radius[i]);
      // Placed, a centre must lie on the allowed side. At a later run's start a
      // centre just past the wall is a hard contact going on, as check_escapes()
      // reads it; more than a radius past, the particle went through.
      if (step_ == 0 ? c + p_.radius[i] < 0 : c + 2 * p_.radius[i] < 0)
        throw InputError(fmt::format(
            "particle {} at ({}) lies outside wall '{}'{}", p_.id[i],
            fmt::join(to_triple(p_.position[i]), ", "), w.name,
            step_ == 0 ? ""
                       : fmt::format(" at step {} (t = {:.6g} s), its centre more than its "
                                     "radius past it: it went through the wall during an "
                                     "earlier run, through a contact too soft for its load or "
                                     "speed (a stiffer law keeps it in)",
                                     step_, time_)));
      if (!p_.fixed[i] && step_ == 0) warn_if_inside_solid(wi, p_.position[i], p_.id[i], "", true);
      if (c < 0 && !p_.fixed[i] && step_ == 0)
        warn(fmt::format("particle {} starts overlapping wall '{}' by {:.3g} m", p_.id[i], w.name,
                         -c));
    }
  }
  if (periodic_.on()) check_walls_repeat();
  body_.periodic_axis = periodic_.on() ? periodic_.axis : -1;
  note_smallest_radii();
  // Positions are doubles, rounded to eps |x|: far from the origin that is a
  // visible part of a radius, and of the overlaps the laws are computed from
  // (1e-7 of a radius at 4.5e8 radii out).
  if (!far_warned_ && p_.size()) {
    double farthest = 0;
    for (const V& x : p_.position) farthest = std::max(farthest, x.cwiseAbs().maxCoeff());
    const double spacing = farthest * std::numeric_limits<double>::epsilon();
    if (spacing > 1e-7 * smallest_radius_) {
      far_warned_ = true;
      warn(fmt::format(
          "particles lie up to {:.3g} m from the origin, {:.3g} times the smallest radius: "
          "positions there are rounded to {:.2g} of that radius, which disturbs the contacts' "
          "overlaps; place the scene near the origin",
          farthest, farthest / smallest_radius_, spacing / smallest_radius_));
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
  contact_reach_ = adhesive_reach();
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
    const double r_max = largest(p_.radius);
    if (!(periodic_.length > 2 * (2 * r_max + skin_)))
      throw InputError(fmt::format(
          "periodic length {} m is too short: it must exceed twice the largest contact reach "
          "(2 (2 r_max + skin) = {} m)",
          periodic_.length, 2 * (2 * r_max + skin_)));
  }
  choose_time_step();
  rebuild_lists();
  // The starting configuration's overlaps are the scene's (simulation_checks.cpp); later
  // the calls that place particles mark theirs (add_particle, fill, set_position). A
  // prepare() for a changed wall or law marks nothing: overlaps the steps made are the
  // run's, and one past a radius (a particle pressed through another by a wall moving
  // into the bed) fails as a pass-through.
  if (step_ == 0) arm_overlap_grace();
  prepared_ = true;
  lists_kept_ = false;
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace granule
