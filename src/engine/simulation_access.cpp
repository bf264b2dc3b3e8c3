// Simulation<D>: accessors (walls, particles, flat state, global statistics, the
// contact list), the attached diagnostics, and describe(). The setters, which
// check their input, are in simulation_setup.cpp.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "contact/rolling.hpp"
#include "core/errors.hpp"
#include "core/random.hpp"
#include "engine/simulation.hpp"

namespace granule {

// ----------------------------------------------------------------------------
// Accessors
// ----------------------------------------------------------------------------

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
  s.bounded = x.bounded;
  for (const auto& m : meshes_.meshes)
    if (m.wall == w) s.angle = m.angle;
  if (x.finite()) {
    s.axis = to_triple(x.axis);
    s.side = to_triple(x.side);
    s.size_a = 2 * x.half_a, s.size_b = 2 * x.half_b;
    s.inner_radius = x.type == WallType::disk ? x.rho0 : 0;
    s.z_lo = x.z0, s.z_hi = x.z1;
    s.radius_lo = x.rho0, s.radius_hi = x.rho1;
  }
  return s;
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
void Simulation<D>::flat_forces(std::vector<double>& force, std::vector<double>& torque) const {
  if (state_override_) {
    force = state_override_->force, torque = state_override_->torque;
    return;
  }
  const std::size_t n = p_.size();
  constexpr int sc = Dim<D>::spin_components;
  force.resize(n * D);
  torque.resize(n * sc);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& ft = p_.force_torque[i];
    for (int k = 0; k < D; ++k) force[i * D + k] = ft.force[k];
    if constexpr (D == 2) {
      torque[i] = ft.torque;
    } else {
      for (int k = 0; k < 3; ++k) torque[i * 3 + k] = ft.torque[k];
    }
  }
}

template <int D>
typename SimulationBase::FlatState Simulation<D>::flat_state() const {
  if (state_override_) return state_override_->state;
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
__attribute__((noinline)) void Simulation<D>::stat_columns(const std::uint32_t* which,
                                                           std::size_t count,
                                                           StatColumns& out) const {
  out.resize(count);
  for (std::size_t k = 0; k < count; ++k) {
    const std::uint32_t i = which[k];
    const double m = p_.mass[i];
    const V& x = p_.position[i];
    const V& v = p_.velocity[i];
    const double inertia = sphere_inertia(m, p_.radius[i]);
    out.kinetic_translational[k] = 0.5 * m * v.squaredNorm();
    out.kinetic_rotational[k] = 0.5 * inertia * Dim<D>::spin_sq(p_.spin[i]);
    for (int a = 0; a < D; ++a) out.momentum[static_cast<std::size_t>(a)][k] = m * v[a];
    double spin_z;
    if constexpr (D == 2) {
      spin_z = p_.spin[i];
    } else {
      spin_z = p_.spin[i][2];
    }
    out.angular_momentum_z[k] = m * (x[0] * v[1] - x[1] * v[0]) + inertia * spin_z;
    out.mass[k] = m;
  }
}

template <int D>
std::vector<std::int64_t> Simulation<D>::particle_ids() const {
  std::vector<std::int64_t> ids;
  ids.reserve(p_.size());
  for (const std::uint32_t i : p_.in_id_order()) ids.push_back(p_.id[i]);
  return ids;
}

template <int D>
GlobalStats Simulation<D>::counters() const {
  GlobalStats g;
  g.time = time_;
  g.step = step_;
  g.particles = static_cast<std::int64_t>(p_.size());
  g.contacts_particle = contacts_particle_;
  g.contacts_batched = contacts_batched_;
  g.contacts_wall_batched = contacts_wall_batched_;
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
GlobalStats Simulation<D>::stats() const {
  if (stats_override_) return *stats_override_;
  GlobalStats g = counters();
  // In canonical order the totals are summed in id order: the same bits
  // whatever order the particles are stored in. The terms are formed a chunk
  // at a time, so that a large scene's call allocates no large buffers.
  constexpr std::size_t chunk = 512;
  std::uint32_t which[chunk];
  std::size_t listed = 0;
  StatColumns t;
  V momentum = V::Zero();
  auto sum = [&]() {
    stat_columns(which, listed, t);
    for (std::size_t k = 0; k < listed; ++k) {
      g.kinetic_translational += t.kinetic_translational[k];
      g.kinetic_rotational += t.kinetic_rotational[k];
      for (int a = 0; a < D; ++a) momentum[a] += t.momentum[static_cast<std::size_t>(a)][k];
      g.angular_momentum_z += t.angular_momentum_z[k];
      g.free_mass += t.mass[k];
    }
    listed = 0;
  };
  auto visit = [&](std::uint32_t i) {
    if (p_.fixed[i]) return;
    which[listed++] = i;
    if (listed == chunk) sum();
  };
  if (canonical_order_) {
    for (const std::int32_t i : p_.index_of_id)
      if (i >= 0) visit(static_cast<std::uint32_t>(i));
  } else {
    for (std::size_t i = 0; i < p_.size(); ++i) visit(static_cast<std::uint32_t>(i));
  }
  if (listed) sum();
  g.momentum = to_triple(momentum);
  return g;
}

// Each model's first slot (pairs, then walls), with its name, in slot order.
template <int D>
std::vector<std::pair<std::size_t, const char*>> Simulation<D>::slot_models() const {
  std::vector<std::pair<std::size_t, const char*>> model_at;
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    using M = ContactModelAt<I>;
    const auto& pb = std::get<I>(pair_buckets_);
    if (pb.size()) model_at.emplace_back(pb.offset, M::name);
    const auto& wb = std::get<I>(wall_buckets_);
    if (wb.size()) model_at.emplace_back(wb.offset, M::name);
  });
  std::sort(model_at.begin(), model_at.end());
  return model_at;
}

template <int D>
std::vector<ContactRecord> Simulation<D>::contacts() const {
  if (!record_contacts_)
    throw InputError(
        "contact forces are not recorded in this scene: set record_contacts = true in "
        "simulation { ... } (it costs a few stores per contact)");
  drop_removed_contacts();
  if (gathered_contacts_) return *gathered_contacts_;
  // A rank's share between gathers: its log names only its part of the scene.
  if (external_rebuilds_)
    throw RunError(
        "the last step's contacts were asked of one MPI rank's share of the scene: they are "
        "listed once the scene is gathered (parallel/distributed_run.hpp)");
  std::vector<ContactRecord> out;
  if (!log_.filled) return out;  // no step taken yet
  // Model names by slot range, as at the step logged.
  const auto& model_at = log_.model_at;
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
  const std::string& label = a.diagnostic->label();
  for (const auto& d : diagnostics_)
    if (d.diagnostic->label() == label)
      throw InputError(fmt::format(
          "diagnostic '{}': label '{}' is taken by diagnostic '{}' (id {}), whose rows under "
          "/diagnostics/{} would mix with these: give each its own `label`",
          name, label, d.name, d.id, label));
  const std::string options = a.diagnostic->options();
  bool known = false;
  for (const auto& [used, with] : labels_used_) {
    known = known || used == label;
    if (used == label && with != options)
      throw InputError(fmt::format(
          "diagnostic '{}': label '{}' was used in this output by a removed diagnostic with other "
          "options ({}), whose rows are under /diagnostics/{}: give this one its own `label` "
          "(these options: {})",
          name, label, with, label, options));
  }
  if (!known && sink_) labels_used_.emplace_back(label, options);
  a.id = next_diagnostic_id_++;
  if (sink_) a.diagnostic->attach_output(sink_);
  diagnostics_.push_back(std::move(a));
  const bool was_tracking = tracking_;
  tracking_ = false;
  for (const auto& d : diagnostics_) tracking_ = tracking_ || d.needs.events;
  // Contacts going on as tracking begins did not begin now: not counted as collisions.
  // Marked at the next step, once its lists are built (mark_ongoing_contacts).
  if (tracking_ && !was_tracking) ongoing_marks_due_ = true;
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
      if (!tracking_) ongoing_marks_due_ = false;
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
  if (sink != sink_) {  // what went to another file (or none) mixes nothing
    labels_used_.clear();
    if (sink)  // but the attached diagnostics write to this one from now on
      for (const auto& d : diagnostics_)
        labels_used_.emplace_back(d.diagnostic->label(), d.diagnostic->options());
  }
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
  std::size_t fixed = 0, moving = 0;
  for (std::size_t i = 0; i < p_.size(); ++i)
    if (p_.fixed[i]) {
      ++fixed;
      moving += p_.velocity[i] != V::Zero() || Dim<D>::spin_sq(p_.spin[i]) > 0;
    }
  lines.push_back(fmt::format("dimension: {}D{}", D,
                              periodic_.on() ? fmt::format(", periodic along {} ({} m)",
                                                           "xyz"[periodic_.axis], periodic_.length)
                                             : std::string()));
  lines.push_back(fmt::format(
      "particles: {} ({} fixed{})", p_.size(), fixed,
      moving ? fmt::format(", {} of them moving as the scene set them", moving) : std::string()));
  auto catalogue = contact_model_catalogue();
  for (int a = 0; a < pairs_.material_count(); ++a)
    for (int b = a; b < pairs_.material_count(); ++b) {
      const auto& e = pairs_.at(a, b);
      if (e.model < 0) continue;
      std::vector<std::string> kv;
      for (const auto& [k, v] : pairs_.values_in_effect(a, b, materials_))
        kv.push_back(k == "rolling_model" ? fmt::format("{}={}", k, rolling_model_name(v))
                                          : fmt::format("{}={}", k, v));
      lines.push_back(fmt::format("contact {}-{}: {} ({})", materials_[a].name, materials_[b].name,
                                  catalogue[e.model].name, fmt::join(kv, ", ")));
    }
  for (const auto& w : walls_) {
    if (w.type == WallType::plane)
      lines.push_back(fmt::format("wall {}: {}plane, material {}", w.name,
                                  w.bounded ? "bounded " : "", materials_[w.material].name));
    else if (w.type == WallType::disk)
      lines.push_back(fmt::format("wall {}: disk r={} m, hole {} m, {} rad/s, material {}", w.name,
                                  w.rho1, w.rho0, w.angular_velocity, materials_[w.material].name));
    else if (w.type == WallType::cone)
      lines.push_back(fmt::format("wall {}: cone r={}-{} m over {} m, {} rad/s, material {}",
                                  w.name, w.rho0, w.rho1, w.z1 - w.z0, w.angular_velocity,
                                  materials_[w.material].name));
    else if (const auto* m = meshes_.of_wall(static_cast<std::size_t>(&w - walls_.data()))) {
      if constexpr (D == 3) {
        lines.push_back(fmt::format("wall {}: mesh of {} triangles from {}, {} rad/s, material {}",
                                    w.name, m->surface->triangle_count(), m->file,
                                    w.angular_velocity, materials_[w.material].name));
      } else {
        std::size_t arcs = 0;
        for (std::size_t k = 0; k < m->surface->segment_count(); ++k)
          arcs += m->surface->arc_radius(k) != 0;
        lines.push_back(fmt::format(
            "wall {}: {} polyline of {} points, {} segments ({} arcs), {} rad/s, material {}",
            w.name,
            m->solid               ? "solid"
            : m->surface->closed() ? "closed"
                                   : "open",
            m->surface->point_count(), m->surface->segment_count(), arcs, w.angular_velocity,
            materials_[w.material].name));
      }
    } else
      lines.push_back(fmt::format("wall {}: {}cylinder r={} m {}, {} rad/s, material {}", w.name,
                                  w.bounded ? "bounded " : "", w.radius,
                                  w.inside ? "inside" : "outside", w.angular_velocity,
                                  materials_[w.material].name));
  }
  const ActiveEffects e = effects();
  lines.push_back(e.adhesion ? fmt::format("adhesion: on ({})", fmt::join(e.adhesive_pairs, ", "))
                             : std::string("adhesion: off (no adhesive pair in use)"));
  std::vector<std::string> turning;
  if (e.friction) turning.emplace_back("friction in use");
  if (e.rolling) turning.emplace_back("rolling or twisting resistance");
  if (e.bonds) turning.emplace_back("parallel bonds");
  if (damping_.spin > 0) turning.emplace_back("spin damping");
  if (e.adhesion && !e.friction)
    turning.emplace_back("adhesion: peeling resists sliding at mu = 0");
  lines.push_back(
      e.rotation ? fmt::format("rotation: spins integrated ({})", fmt::join(turning, ", "))
                 : std::string("rotation: off (no pair in use has friction, rolling or "
                               "twisting resistance or adhesion, so no torque acts; spins stay "
                               "as set)"));
  lines.push_back(e.moving_walls.empty()
                      ? std::string("moving walls: none")
                      : fmt::format("moving walls: {}", fmt::join(e.moving_walls, ", ")));
  if (!bonds_.empty())
    lines.push_back(fmt::format("parallel bonds: {} intact, {} broken", bonds_.intact,
                                static_cast<std::int64_t>(bonds_.size()) - bonds_.intact));
  lines.push_back(fmt::format("gravity: {}", body_.gravity_on ? "on" : "off"));
  lines.push_back(fmt::format("central field: {}", e.central_field    ? "on"
                                                   : body_.central_on ? "declared, strength 0"
                                                                      : "off"));
  lines.push_back(damping_.active()
                      ? fmt::format("damping: viscous {} 1/s, spin {} 1/s, local_fraction {}",
                                    damping_.viscous, damping_.spin, damping_.local_fraction)
                      : std::string("damping: off"));
  lines.push_back(fmt::format("contact forces recorded: {}", record_contacts_ ? "yes" : "no"));
  if (diagnostics_.empty()) {
    lines.push_back("diagnostics: none");
  } else {
    for (const auto& d : diagnostics_)
      lines.push_back(fmt::format("diagnostic {}: {}", d.name, d.diagnostic->describe()));
  }
  std::size_t scripted = 0;
  for (const auto& h : hooks_) scripted += h.script ? 1 : 0;
  lines.push_back(fmt::format("hooks: {} ({} sim:every, {} the output's series and snapshots)",
                              hooks_.size(), scripted, hooks_.size() - scripted));
  if (canonical_order_)
    lines.push_back("canonical order: on (contacts and totals summed in particle-id order)");
  if (spread_ranks_ > 1) lines.push_back(spread_how_);
  lines.push_back(
      fmt::format("threads: {}{}", thread_count(),
                  threads_ > 0 ? "" : " (OMP_NUM_THREADS, else 1; set with --threads N)"));
  if (dt_ > 0)
    lines.push_back(fmt::format("time step: {:.6g} s ({}), skin {:.4g} m", dt_,
                                dt_fixed_ > 0 ? "set by the scene" : automatic_step_rule(), skin_));
  else  // before the first prepare: the rule and the skin are chosen there
    lines.push_back(
        "time step: not chosen yet (automatic, chosen with the skin when the scene first runs or "
        "prepares)");
  return lines;
}

template <int D>
std::string Simulation<D>::automatic_step_rule() const {
  if (dt_per_contact_)
    return fmt::format(
        "automatic: {}, n = {}, t_c the contact time of {}{}", time_step_rule_name(true),
        steps_per_contact_, dt_governing_pair_,
        dt_governing_pair_.find("walton_braun") != std::string::npos
            ? " (of its unloading spring K2 alone, pi sqrt(m*/K2): its force lasts (1 + e)/(2e) "
              "t_c)"
            : "");
  // Thornton's rule (Eqs. 6.1-6.2): a Hertz contact closing at v lasts
  // 2.87 (m*^2 / (R* E*^2 v))^(1/5), so its steps fall as v^(-1/5).
  return fmt::format(
      "automatic: {}, n = {}, T_R the Rayleigh time, for {}; not steps "
      "per contact: a Hertz contact lasts 2.87 (m*^2/(R* E*^2 v))^(1/5), fewer steps the "
      "faster it closes",
      time_step_rule_name(false), steps_per_contact_, dt_governing_pair_);
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace granule
