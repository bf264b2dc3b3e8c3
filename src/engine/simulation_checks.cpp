// Checks that stop a run which has gone wrong, naming the step, the particle
// and what it touched, before the state written with the failure is useless.
// A NaN is caught by the integration (integrate/leapfrog.hpp); an escape here.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "engine/simulation.hpp"

namespace granule {

namespace {
// Each touching wall contact of the buckets: f(particle, wall index, overlap /
// the particle's radius), a mesh's overlap as this step found it.
template <int D, typename WallBuckets, typename F>
void each_wall_touch(const WallBuckets& buckets, const std::vector<Wall<D>>& walls,
                     const Particles<D>& p, const std::uint8_t* in_contact, F&& f) {
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    const auto& wb = std::get<I>(buckets);
    for (std::size_t k = 0; k < wb.size(); ++k) {
      if (!in_contact[wb.offset + k]) continue;
      const std::uint32_t i = wb.particle[k];
      const Wall<D>& wall = walls[wb.wall[k]];
      const double overlap = is_surface_wall(wall.type)
                                 ? wb.touch[k].overlap
                                 : -wall.clearance(p.position[i], p.radius[i]);
      f(i, static_cast<std::size_t>(wb.wall[k]), overlap / p.radius[i]);
    }
  });
}
}  // namespace

// A particle whose centre lies more than its radius beyond a wall (an overlap
// above twice its radius) has tunnelled through it: it crossed the wall within
// one step, or was driven through by a contact far stiffer or faster than the
// time step resolves. Walls are half-spaces, so the contact law would now push
// it back with a force far outside its range, creating energy: stop instead.
// (A centre just past the wall is a hard impact, not an escape: the overlapping
// fills of SPEC 2 throw particles at the chamber that hard in their first steps.)
// A post thinner than the particle (an outside cylinder of radius R < 2 r)
// holds no centre a radius past its surface: past the axis its normal turns
// and it pushes the particle on through. A centre within half the post's
// radius of the axis is the stop there (an off-axis pass further out, or one
// step across that band, is not caught).
// Called at every list rebuild, which a fast particle triggers within half a
// skin of travel, and on any step with a wall contact deeper than a radius
// (step()); the cost is one clearance per particle and wall, as much as
// listing the wall contacts.
template <int D>
void Simulation<D>::check_escapes() {
  for (std::size_t w = 0; w < walls_.size(); ++w) {
    const Wall<D>& wall = walls_[w];
    const bool post = wall.type == WallType::cylinder && !wall.inside && !wall.finite();
    for (std::size_t i = 0; i < p_.size(); ++i) {
      if (p_.fixed[i]) continue;
      const double c = wall.clearance(p_.position[i], p_.radius[i]);
      const double beyond = post ? std::min(p_.radius[i], 0.5 * wall.radius) : p_.radius[i];
      if (!(c + p_.radius[i] + beyond < 0)) continue;
      const Triple x = to_triple(p_.position[i]), v = to_triple(p_.velocity[i]);
      // A particle that moves a small part of its radius a step was not carried
      // through by one step: the contact was too soft for its load (a static
      // overlap m g / k beyond the radius) or for the speed it was driven at.
      const double per_step = p_.velocity[i].norm() * dt_;
      const std::string cause =
          per_step < 0.25 * p_.radius[i]
              ? fmt::format(
                    "it moves {:.3g} m a step, so the wall contact was too soft to hold it (its "
                    "load or its speed pressed it deeper than its radius): stiffen the contact "
                    "(k_normal, young) or lighten the load",
                    per_step)
              : std::string(
                    "it moved too far in one step for the wall contact to stop it; "
                    "reduce time_step or raise the skin");
      fail(fmt::format(
          "step {} (t = {:.6g} s): particle {} (radius {:.4g} m) escaped through wall '{}' (its "
          "centre is {:.4g} m beyond its surface; position ({:.6g}), velocity ({:.6g}) m/s): {}",
          step_, time_, p_.id[i], p_.radius[i], wall.name, -(c + p_.radius[i]),
          fmt::join(x.begin(), x.begin() + D, ", "), fmt::join(v.begin(), v.begin() + D, ", "),
          cause));
    }
  }
}

// The Hertzian laws' step rule and stability limit come from the Rayleigh time,
// the contact as it begins; pressed deeper, its stiffness grows as the contact
// radius a = sqrt(R* overlap), and the no-slip tangential spring, 8 G* a on a mass
// of m* / 3.5, is its stiffest mode (about 1.7 times the normal one). A soft,
// dense, frictional packing pressed a few per cent of a radius deep then has
// modes the step no longer resolves, and vibrates on its own (no error: the
// friction caps it). Warned once per pair when, at the deepest overlap ratio of
// its own contacts (read at the pair's smallest particles), omega dt passes 0.8:
// a single contact is stable to 2, but a particle held by Z of them has modes up
// to about sqrt(Z) times as fast (2 / sqrt(6) = 0.8 for a packing's six).
// The step's deepest ratio (the pairs', or the walls' for a particle-wall law)
// is a bound that costs nothing; only a law it puts past the bound has its own
// contacts' depth looked at, and while that bound holds but theirs does not
// (soft contacts pressed deep beside stiff ones), again every 64 steps.
template <int D>
void Simulation<D>::check_deep_contact_modes(double pair_ratio, double wall_ratio) {
  deep_checked_pair_ = std::max(deep_checked_pair_, 1.02 * pair_ratio);
  deep_checked_wall_ = std::max(deep_checked_wall_, 1.02 * wall_ratio);
  deep_rescan_step_ = -1;
  const int nm = static_cast<int>(materials_.size());
  std::vector<double> by_pair, by_wall;  // filled by the first law the bound puts past it
  for (const DeepContactMode& m : deep_modes_) {
    if (std::find(deep_warned_.begin(), deep_warned_.end(), m.pair) != deep_warned_.end()) continue;
    const double bound_ratio = m.wall ? wall_ratio : pair_ratio;
    if (!(std::sqrt(m.omega_squared(bound_ratio * m.smaller_radius)) * dt_ > deep_mode_bound))
      continue;
    if (by_pair.empty()) deepest_by_materials(by_pair, by_wall);
    const std::size_t at = static_cast<std::size_t>(m.material_a * nm + m.material_b);
    const double overlap_ratio = m.wall ? by_wall[at] : by_pair[at];
    if (overlap_ratio == -INFINITY) {  // no contact of this pair now (an adhesive law's mode
      deep_rescan_step_ = step_ + deep_rescan_every;  // is stiff from zero overlap on)
      continue;
    }
    const double omega_dt =
        std::sqrt(m.omega_squared(std::max(0.0, overlap_ratio) * m.smaller_radius)) * dt_;
    if (!(omega_dt > deep_mode_bound)) {
      deep_rescan_step_ = step_ + deep_rescan_every;
      continue;
    }
    deep_warned_.push_back(m.pair);
    const double shorter = dt_ * 0.9 * deep_mode_bound / omega_dt;
    warn(fmt::format(
        "step {} (t = {:.6g} s): contacts are pressed {:.3g} of a radius deep, where a {} "
        "contact's stiffest mode (its tangential, rolling or twisting spring's) has omega dt = "
        "{:.3g} at this time "
        "step: above {} a dense frictional packing or an adhesive cluster can vibrate on its own "
        "and gain kinetic energy; {} "
        "(docs/contact_models.md, \"Deep contacts\")",
        step_, time_, std::max(0.0, overlap_ratio), m.pair, omega_dt, deep_mode_bound,
        dt_fixed_ > 0
            ? fmt::format("give time_step {:.3g} s or less", shorter)
            : fmt::format("raise steps_per_contact to {:.0f} or more (time step {:.3g} s)",
                          std::ceil(steps_per_contact_ * omega_dt / (0.9 * deep_mode_bound)),
                          shorter)));
  }
}

template <int D>
void Simulation<D>::deepest_by_materials(std::vector<double>& pairs,
                                         std::vector<double>& walls) const {
  const std::size_t nm = materials_.size();
  pairs.assign(nm * nm, -INFINITY);
  walls.assign(nm * nm, -INFINITY);
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    const auto& b = std::get<I>(pair_buckets_);
    for (std::size_t k = 0; k < b.size(); ++k) {
      if (!slot_in_contact_[b.offset + k]) continue;
      const std::uint32_t i = b.i[k], j = b.j[k];
      const double dist = separation(p_.position[i], p_.position[j]).norm();
      const double ratio =
          (p_.radius[i] + p_.radius[j] - dist) / std::min(p_.radius[i], p_.radius[j]);
      const std::size_t mi = static_cast<std::size_t>(p_.material[i]),
                        mj = static_cast<std::size_t>(p_.material[j]);
      pairs[mi * nm + mj] = std::max(pairs[mi * nm + mj], ratio);
      pairs[mj * nm + mi] = std::max(pairs[mj * nm + mi], ratio);
    }
  });
  each_wall_touch(wall_buckets_, walls_, p_, slot_in_contact_.data(),
                  [&](std::uint32_t i, std::size_t w, double ratio) {
                    const std::size_t at = static_cast<std::size_t>(p_.material[i]) * nm +
                                           static_cast<std::size_t>(walls_[w].material);
                    walls[at] = std::max(walls[at], ratio);
                  });
}

// A particle pressed into a wall deeper than overlap_warning of its radius:
// its law acts far outside the range its stiffness was chosen for (a piston
// closing on it, a load its contact is too soft for). A half-space holds it
// until its centre is a radius beyond (check_escapes), a thin wall until 0.9 of
// a radius (check_thin_walls); warned once, naming the deepest contact.
template <int D>
void Simulation<D>::warn_deep_wall_contact() {
  double worst = -INFINITY;
  std::size_t wi = 0, ww = 0;
  each_wall_touch(wall_buckets_, walls_, p_, slot_in_contact_.data(),
                  [&](std::uint32_t i, std::size_t w, double ratio) {
                    if (ratio > worst) worst = ratio, wi = i, ww = w;
                  });
  if (!(worst > overlap_warning_)) return;
  wall_overlap_warned_ = true;
  warn(fmt::format(
      "step {} (t = {:.6g} s): particle {} (radius {:.4g} m) is pressed {:.4g} m into wall "
      "'{}', {:.0f} % of its radius (above overlap_warning = {}): its contact law acts far "
      "outside the range its stiffness was set for; stiffen the contact (k_normal, young, "
      "k_load) or lighten its load{} (warned once)",
      step_, time_, p_.id[wi], p_.radius[wi], worst * p_.radius[wi], walls_[ww].name, 100 * worst,
      overlap_warning_,
      scene_launched_ ? "; or, if the scene's overlapping start launched it (particles placed "
                        "into one another, sim:fill with overlap = true), start without overlaps"
                      : ""));
}

// Two particles overlapping by more than the smaller radius are passing through
// each other: their contact law acts far outside its range and, once the
// centres cross, pushes them on instead of apart. The pair loop keeps the
// step's largest overlap / smaller radius (one max() per contact, in both the
// per-contact and the batched path), and step() compares it once a step; the
// contacts are scanned only on the rare steps it is above overlap_warning.
//
// Why a step's deepest overlap catches a pass-through: every pair within touch
// is in the lists (a list is rebuilt before any particle has moved half the
// skin), so the overlap of every touching pair is seen at every step. Two
// particles closing head-on at v pass from touching to centres crossed seen
// at no step with an overlap above r_min only if one step carries them across
// the whole depth between r_max and -r_max: v dt > 2 r_max. With dt = t_c / n
// (Eq. 4.1; t_c >= pi / omega for the linear law) that needs v > 2 n r_max
// omega / pi, 25 r omega at n = 40 (about 5 km/s for the 0.2 mm, 2e4 N/m base
// case), while a spring stops the pair short of r_min below v = r_min omega
// (the largest overlap of an impact is v / omega): every pass-through between
// the two is caught, and at the stability limit dt = 1/omega up to 2 r omega.
//
// Overlaps the scene made (coincident centres, an overlapping fill, a particle
// moved by set_position) are warned of, not stopped: until every pair is back
// under overlap_warning after the scene placed them (arm_overlap_grace; ended in
// step(), or on a distributed run by the run, once every rank's pairs are), the
// particles they launched are still flying into one another. A setting changed
// mid-run (a wall, a law, the skin) places nothing: what the steps do after it
// is the run's. (An
// overlapping fill of the Mechanofusion chamber throws particles together at
// 30-150 m/s for hundreds of steps, some pairs over a radius deep: that is the
// start the scene asked for, and the warning names its launch speed.)
template <int D>
double Simulation<D>::placed_pairs_deepest() const {
  std::vector<std::uint8_t> placed(p_.size(), 0);
  for (const std::int64_t id : placed_ids_) {
    const int i = p_.index(id);
    if (i >= 0) placed[static_cast<std::size_t>(i)] = 1;
  }
  double deepest = -INFINITY;
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    const auto& b = std::get<I>(pair_buckets_);
    for (std::size_t k = 0; k < b.size() && !(deepest > overlap_warning_); ++k) {
      const std::uint32_t i = b.i[k], j = b.j[k];
      if (!slot_in_contact_[b.offset + k] || !(placed[i] || placed[j])) continue;
      const double dist = separation(p_.position[i], p_.position[j]).norm();
      deepest = std::max(
          deepest, (p_.radius[i] + p_.radius[j] - dist) / std::min(p_.radius[i], p_.radius[j]));
    }
  });
  return deepest;
}

template <int D>
void Simulation<D>::check_overlaps(double pair_ratio) {
  const bool from_scene = scene_overlaps_, through = pair_ratio > 1 && !from_scene;
  if (from_scene) scene_launched_ = true;
  if (!through && overlap_warned_) return;
  // The deepest pair, and the speed its springs' energy would give it: E ~ F a / 2
  // (exact for a linear spring), shared as (1/2) m* v^2.
  double worst = -1, force = 0;
  std::size_t wi = 0, wj = 0;
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    using M = ContactModelAt<I>;
    const auto& b = std::get<I>(pair_buckets_);
    for (std::size_t k = 0; k < b.size(); ++k) {
      const std::uint32_t i = b.i[k], j = b.j[k];
      const V d = separation(p_.position[i], p_.position[j]);
      const double dist = d.norm(), r_min = std::min(p_.radius[i], p_.radius[j]);
      const double ratio = (p_.radius[i] + p_.radius[j] - dist) / r_min;
      if (!(ratio > worst)) continue;
      worst = ratio, wi = i, wj = j;
      ContactState<D> c;
      c.dt = dt_;
      c.normal = dist > 0 ? V(d / dist) : V(V::UnitX());
      c.overlap = p_.radius[i] + p_.radius[j] - dist;
      c.normal_velocity = 0;
      c.tangential_velocity = V::Zero();
      c.inv_mass_sum = p_.inv_mass[i] + p_.inv_mass[j];
      c.effective_mass = 1.0 / c.inv_mass_sum;
      c.effective_radius = p_.radius[i] * p_.radius[j] / (p_.radius[i] + p_.radius[j]);
      typename PairBucket<D, M>::History h{};
      force = M::force(pairs_.params<I>()[b.slot[k]], h, c).normal;
    }
  });
  if (worst < 0) return;
  const double r_min = std::min(p_.radius[wi], p_.radius[wj]);
  const double overlap = worst * r_min;
  const double m_star = 1.0 / (p_.inv_mass[wi] + p_.inv_mass[wj]);
  const V dv = p_.velocity[wi] - p_.velocity[wj];
  const V d = separation(p_.position[wi], p_.position[wj]);
  const double closing = d.norm() > 0 ? -dv.dot(d) / d.norm() : dv.norm();
  // Work the law's elastic force could have done up to this depth (about half
  // of force x overlap for a law that stiffens as it is pressed: linear, Hertz)
  // against the closing motion: the pair, still closing, came in over steps that
  // each closed less than half the smaller radius, so the steps followed the
  // approach and the law did not stop it within a radius: it is too soft for
  // this impact, and no time step stops them. (The energy still left at this
  // depth is no test: the law has taken some of it, at 1.3 r omega head-on
  // about 60 %, and what is left can be below what it stores here.) A pair
  // that closed half a radius or more in the last step came in too fast for
  // the step to follow.
  const double stored = 0.5 * std::max(0.0, force) * overlap;
  const double kinetic = closing > 0 ? 0.5 * m_star * closing * closing : 0.0;
  const bool followed = closing * dt_ < 0.5 * r_min;
  const std::string why =
      closing > 0 && (followed || kinetic > stored)
          ? fmt::format(
                "still closing a radius deep, with about {:.3g} J of closing motion left beside "
                "the {:.3g} J their contact law stores at this depth: it is too soft for this "
                "impact, and no time step stops them; a stiffer law (young, k_normal, k_load) "
                "or a slower impact does",
                kinetic, stored)
          : "they moved too far in one step for their contact to stop them; reduce time_step "
            "or raise steps_per_contact";
  if (through)
    fail(fmt::format(
        "step {} (t = {:.6g} s): particles {} and {} pass through each other: they overlap by "
        "{:.4g} m, {:.0f} % of the smaller radius {:.4g} m (centres {:.4g} m apart; speeds "
        "{:.4g} and {:.4g} m/s, closing at {:.4g} m/s): {}",
        step_, time_, p_.id[wi], p_.id[wj], overlap, 100 * worst, r_min, d.norm(),
        p_.velocity[wi].norm(), p_.velocity[wj].norm(), closing, why));
  overlap_warned_ = true;
  const double launch = std::sqrt(std::max(0.0, force * overlap) / m_star);
  warn(fmt::format(
      "step {}: particles {} and {} overlap by {:.3g} m, {:.0f} % of the smaller radius (above "
      "overlap_warning = {}); their contact pushes them apart with {:.3g} N and would launch them "
      "at about {:.3g} m/s{} (warned once)",
      step_, p_.id[wi], p_.id[wj], overlap, 100 * worst, overlap_warning_, force, launch,
      from_scene ? "; if a fill made this overlap, sim:fill { ..., overlap = false } starts "
                   "without overlaps"
                 : ""));
}

// Two tests on the contacts with thin walls (a finite one: a plate, a disk, a
// tube, a cone; a mesh or a polyline), which act from both of their sides, in one
// pass. (A half-space holds a particle past its surface: check_escapes stops one
// whose centre is a radius beyond. A solid polyline is a body, and pushes a
// centre that got inside it back out by design: kernel/mesh_contacts.hpp.)
//
// Pressed through (`pressed`, on steps with a wall contact deeper than
// wall_through_ratio): a contact deeper than nine tenths of the particle's
// radius, the particle still moving into the wall: its centre is at the wall's
// surface and going on, and the wall will push it on through and out of the
// other side. Slow pressing does this as well as fast impacts: a piston
// squeezing a particle through a floor at 0.02 % of its radius a step. A
// particle on its way out (the scene placed it that deep, and the contact
// pushes it back) is let be.
//
// Crossed within a step (`crossed`, on steps with a contact deeper than
// thin_watch_ratio and the step after each, a flag the checkpoint keeps): the
// depth test sees a crossing only if a step lands within a tenth of a radius of
// the surface. A contact whose particle moved out along its normal, relative to
// the wall, by more than its centre now stands off the surface had its centre
// behind the surface's tangent plane a step ago: it came through. A crossing at
// under a radius a step (faster ones check_displacements stops) comes within
// half a radius of the surface on one side or the other. The margin of a
// hundredth of a radius leaves the tangent plane's departure from a curved
// surface out; a centre that crossed from within a hundredth of a radius had a
// contact 0.99 r deep going in a step before, which the first test stopped.
//
// Both read only this step's state, so they are the same on every rank and
// after a restart.
template <int D>
void Simulation<D>::check_thin_walls(bool pressed, bool crossed) {
  double deepest = -1, approach = 0, behind_most = 0;
  std::size_t pressed_particle = 0, pressed_wall = 0, crossed_particle = 0, crossed_wall = 0;
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    const auto& b = std::get<I>(wall_buckets_);
    for (std::size_t k = 0; k < b.size(); ++k) {
      const std::uint32_t i = b.particle[k], w = b.wall[k];
      if (!walls_[w].finite() && !is_surface_wall(walls_[w].type)) continue;
      if constexpr (D == 2)
        if (const auto* shape = meshes_.of_wall(w); shape && shape->solid) continue;
      double overlap = -1;
      V n = V::Zero(), surface_velocity = V::Zero(), lever;
      if (is_surface_wall(walls_[w].type)) {
        if (b.touch.size() != b.size()) continue;
        overlap = b.touch[k].overlap;
        n = b.touch[k].normal, surface_velocity = b.touch[k].surface_velocity;
      } else {
        overlap = walls_[w].contact(p_.position[i], p_.radius[i], n, surface_velocity, lever);
      }
      if (!(overlap > 0)) continue;
      const double r = p_.radius[i];
      const double out = (p_.velocity[i] - surface_velocity).dot(n);  // < 0: going in
      const double ratio = overlap / r;
      if (pressed && ratio > wall_through_ratio && out < 0 && ratio > deepest)
        deepest = ratio, pressed_particle = i, pressed_wall = w, approach = -out;
      const double behind = out * dt_ - (r - overlap);  // how far behind the plane it was
      if (crossed && behind > 0.01 * r && behind > behind_most)
        behind_most = behind, crossed_particle = i, crossed_wall = w;
    }
  });
  if (deepest >= 0) {
    const std::size_t i = pressed_particle;
    const double per_step = approach * dt_;
    fail(fmt::format(
        "step {} (t = {:.6g} s): particle {} (radius {:.4g} m) is pressed through wall '{}': its "
        "contact is {:.0f} % of its radius deep, its centre all but at the wall's surface, and it "
        "goes on into the wall at {:.3g} m/s ({:.3g} m a step); {}",
        step_, time_, p_.id[i], p_.radius[i], walls_[pressed_wall].name, 100 * deepest, approach,
        per_step,
        per_step < 0.25 * p_.radius[i]
            ? "the contact is too soft for what presses it (a load, a moving wall): stiffen it "
              "(k_normal, young) or lighten the load"
            : "it came in too fast for the contact to stop it: reduce time_step or the speed"));
  }
  if (behind_most > 0) {
    const std::size_t i = crossed_particle;
    fail(fmt::format(
        "step {} (t = {:.6g} s): particle {} (radius {:.4g} m, speed {:.3g} m/s) went through "
        "wall '{}': within the last step its centre crossed the wall's surface (a step ago it "
        "stood {:.2g} of its radius on the other side), and the wall now pushes it out of the "
        "far side; the contact was too soft or the step too long to stop it: stiffen the contact "
        "(k_normal, young), reduce time_step or the speed",
        step_, time_, p_.id[i], p_.radius[i], p_.velocity[i].norm(), walls_[crossed_wall].name,
        behind_most / p_.radius[i]));
  }
}

// A particle that moves farther in one step than the smallest radius can step
// over a contact: two such particles closing head-on cross the depth at which
// check_overlaps() sees them pass through (about three radii) within one
// step, and a finite wall's edge as much. One comparison a step (integrate()
// keeps the fastest speed); the particle is found only when it fails.
template <int D>
void Simulation<D>::report_step_over() {
  std::size_t fastest = 0;
  for (std::size_t i = 1; i < p_.size(); ++i)
    if (p_.velocity[i].squaredNorm() > p_.velocity[fastest].squaredNorm()) fastest = i;
  const double speed = p_.size() ? p_.velocity[fastest].norm() : 0;
  fail(fmt::format(
      "step {} (t = {:.6g} s): particle {} moves {:.4g} m in one step ({:.4g} m/s, time step "
      "{:.4g} s), more than the smallest radius {:.4g} m: it can step over a contact, or two such "
      "particles pass through each other unseen; reduce time_step (or raise steps_per_contact) "
      "below {:.4g} s",
      step_, time_, p_.size() ? p_.id[fastest] : -1, speed * dt_, speed, dt_, smallest_radius_,
      smallest_radius_ / std::max(speed, 1e-300)));
}

// A wall that moves farther in one step than the smallest radius can step over a
// particle (a finite wall is thin, and two-sided) or press one past its centre, which
// no contact law resolves; as for particles, one comparison a step, and only then a
// look at the particles: a particle is at risk where the wall, as it stood before
// the step, advanced towards it (along the normal from its nearest point to the
// particle) by more than the smallest radius and by more than the gap between them.
// A gate pulled away, a plate sliding along itself or a wall far off steps over
// nothing. A mesh or polyline is looked at through its contacts as it stood
// before the step, within its travel bound of the particle's surface, each
// point advancing as the mesh's motion moved it (a turn's too).
template <int D>
void Simulation<D>::report_wall_step_over() {
  for (std::size_t w = 0; w < walls_.size(); ++w) {
    const Wall<D>& wall = walls_[w];
    if (!(wall_travel_[w] > smallest_free_radius_)) continue;
    // The wall before the step, seen from a particle at x, is the wall now seen from
    // x + step (a translation); a mesh or polyline is turned and moved back.
    const V step = wall.velocity * dt_;
    const auto mesh_before = meshes_.before_step(w, wall, dt_);
    // A surface wall's reach, capped: past any finite bound every particle is in it.
    const double reach = std::min(wall_travel_[w], 1e6);
    for (std::size_t i = 0; i < p_.size(); ++i) {
      if (p_.fixed[i]) continue;  // it touches no wall: nothing steps over it
      double overlap = 0, advance = 0;
      if (mesh_before) {
        if (!MeshSet<D>::approach(*mesh_before, wall, p_.position[i], p_.radius[i],
                                  p_.radius[i] + reach, dt_, overlap, advance))
          continue;
      } else {
        V normal, surface_velocity, lever;
        overlap =
            wall.contact(V(p_.position[i] + step), p_.radius[i], normal, surface_velocity, lever);
        advance = step.dot(normal);
      }
      if (!(advance > smallest_free_radius_) || !(-overlap < advance)) continue;
      fail(fmt::format(
          "step {} (t = {:.6g} s): wall '{}' moves {:.4g} m in one step (time step {:.4g} s) "
          "towards particle {}, more than the smallest free particle's radius {:.4g} m and the gap "
          "{:.4g} m "
          "between them: it can step over the particle or press it through; slow the wall (its "
          "velocity, its turning or its schedule){}",
          step_, time_, wall.name, advance, dt_, p_.id[i], smallest_free_radius_, -overlap,
          std::isfinite(advance) ? fmt::format(" or reduce time_step below {:.4g} s",
                                               dt_ * smallest_free_radius_ / advance)
                                 : std::string()));
    }
  }
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace granule
