// SimulationBase's schedules (fields/schedule.hpp): values that follow
// simulated time, set before every step to their value at that step's time.
//
// Each schedule sets its target only when its value changes, so a held value
// costs one evaluation per step. A contact parameter that changes re-prepares
// the simulation at once (prepare() re-checks the time step and whether spins
// are integrated, e.g. friction switched on): at a fixed step, not at the
// start of the next run chunk, whose place depends on the wall clock.
//
// step() applies them at the end of every step (its time already advanced
// to the next step's), before the hooks fire, and add_schedule applies the
// value at once, so step n always runs with the values at t_n.
//
// Checkpoint keys: "schedules" (one line per schedule, every number to 17
// digits) and "schedules.applied" (the values last set). The restarted scene
// declares its schedules again; a checkpoint whose list differs is refused.
#include <fmt/format.h>

#include <sstream>

#include "contact/models.hpp"
#include "core/errors.hpp"
#include "core/names.hpp"
#include "core/state.hpp"
#include "engine/simulation_base.hpp"

namespace granule {

namespace {

bool is_wall_target(const std::string& t) {
  return t == "wall_angular_velocity" || t == "wall_velocity";
}

std::string line_of(const ScheduleSpec& s) {
  std::string out = fmt::format("{} '{}' '{}' ({:.17g} {:.17g} {:.17g}) {}", s.target, s.a, s.b,
                                s.direction[0], s.direction[1], s.direction[2], s.schedule.form());
  for (std::size_t k = 0; k < s.schedule.times().size(); ++k)
    out += fmt::format(" {:.17g} {:.17g}", s.schedule.times()[k], s.schedule.values()[k]);
  return out;
}

std::string lines_of(const std::vector<ScheduleSpec>& list) {
  std::string out;
  for (const auto& s : list) out += line_of(s) + "\n";
  return out;
}
}  // namespace

int SimulationBase::add_schedule(ScheduleSpec spec) {
  const std::string what = fmt::format("schedule '{}'", spec.target);
  if (spec.schedule.empty()) throw InputError(fmt::format("{}: no schedule given", what));
  if (spec.target == "central_strength") {
    // The field must exist: a strength without it would act on nothing.
    if (!body_fields().central_on)
      throw InputError(fmt::format(
          "{}: the scene has no central field; declare it first (sim:central_field)", what));
  } else if (is_wall_target(spec.target)) {
    spec.wall = wall_id(spec.a);
    if (spec.target == "wall_velocity") {
      const auto& d = spec.direction;
      const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      if (!(n > 0) || !std::isfinite(n))
        throw InputError(fmt::format("{}: 'direction' must be a non-zero finite vector", what));
      for (double& c : spec.direction) c /= n;
    }
  } else {
    if (spec.a.empty() || spec.b.empty())
      throw InputError(fmt::format(
          "{}: not a known target (central_strength, wall_angular_velocity, wall_velocity) "
          "nor a contact parameter with the pair's materials (from =, to =)",
          what));
    material_id(spec.a);  // throws naming a material not declared
    material_id(spec.b);
    // A switch (0 or 1) may only jump: a ramp's values in between are no setting.
    for (const auto& model : contact_model_catalogue())
      for (const ParamSpec& p : model.parameters)
        if (p.is_switch && spec.target == p.name) {
          const auto &t = spec.schedule.times(), &v = spec.schedule.values();
          for (std::size_t k = 0; k < v.size(); ++k) {
            if (v[k] != 0 && v[k] != 1)
              throw InputError(fmt::format("{}: '{}' is a switch: its values are 0 or 1, not {}",
                                           what, spec.target, v[k]));
            if (k > 0 && v[k] != v[k - 1] && t[k] != t[k - 1])
              throw InputError(fmt::format(
                  "{}: '{}' is a switch (0 or 1): a schedule of it may only jump between them "
                  "(two points at one time, as piecewise = {{ t, 1, t, 0 }}), not ramp",
                  what, spec.target));
          }
        }
  }
  spec.id = next_schedule_id_;
  schedules_.push_back(std::move(spec));
  try {
    apply_schedules();  // the value now; a parameter the pair's model lacks is refused here
  } catch (...) {
    schedules_.pop_back();
    throw;
  }
  return next_schedule_id_++;
}

void SimulationBase::remove_schedule(int id) {
  for (auto s = schedules_.begin(); s != schedules_.end(); ++s)
    if (s->id == id) {
      schedules_.erase(s);
      return;
    }
  throw InputError(
      fmt::format("remove_schedule: no schedule {} (sim:schedule returns the ids; "
                  "one removed is gone)",
                  id));
}

namespace {
// "schedule 3 ('wall_velocity')", for the refusals below.
std::string schedule_named(const ScheduleSpec& s) {
  return fmt::format("schedule {} ('{}')", s.id, s.target);
}
// Past its last point a schedule holds its last value, which it has set: it
// sets nothing again, and a value set by hand stays. Within half a step of
// that point (a run of the ramp's length ends there, give or take the clock's
// round-off) it counts as past it: its last value is taken as set, so that the
// next step does not set it over the hand's.
bool sets_again(ScheduleSpec& s, double now, double dt) {
  if (now < s.schedule.times().back() - 0.5 * dt) return true;
  s.applied = s.schedule.values().back();
  return false;
}
}  // namespace

void SimulationBase::claim_schedule_target(const ScheduleSpec& spec) {
  const std::string what = fmt::format("schedule '{}'", spec.target);
  // Two schedules would each set their own value, the last to change winning.
  for (ScheduleSpec& s : schedules_) {
    const bool same_pair = (s.a == spec.a && s.b == spec.b) || (s.a == spec.b && s.b == spec.a);
    if (s.target == spec.target && same_pair && sets_again(s, time_, dt_))
      throw InputError(fmt::format(
          "{}: schedule {} already sets it{} until t = {} s (now t = {} s); one schedule a target "
          "(sim:remove_schedule({}) ends the other; a piecewise schedule holds several ramps)",
          what, s.id,
          s.a.empty()   ? std::string()
          : s.b.empty() ? fmt::format(" for '{}'", s.a)
                        : fmt::format(" for '{}'-'{}'", s.a, s.b),
          s.schedule.times().back(), time_, s.id));
  }
}

void SimulationBase::claim_scheduled_wall(int w, const std::string& key) {
  const std::string target = "wall_" + key;
  for (auto& s : schedules_)
    if (s.wall == w && s.target == target && sets_again(s, time_, dt_))
      throw InputError(fmt::format(
          "set_wall '{}': its {} is set by {} until t = {} s (now t = {} s), which "
          "would undo this; end the schedule first (sim:remove_schedule({})): the wall then "
          "keeps the value it has and takes what is set by hand",
          s.a, key, schedule_named(s), s.schedule.times().back(), time_, s.id));
}

void SimulationBase::claim_scheduled_contact(const std::string& a, const std::string& b,
                                             const std::string& key) {
  for (auto& s : schedules_)
    if (s.target == key && ((s.a == a && s.b == b) || (s.a == b && s.b == a)) &&
        sets_again(s, time_, dt_))
      throw InputError(fmt::format(
          "set_contact '{}'-'{}': its {} is set by {} until t = {} s (now t = {} s), "
          "which would undo this; end the schedule first (sim:remove_schedule({})): the law then "
          "keeps the value it has and takes what is set by hand",
          a, b, key, schedule_named(s), s.schedule.times().back(), time_, s.id));
}

void SimulationBase::claim_scheduled_field(const char* caller) {
  for (auto& s : schedules_)
    if (s.target == "central_strength" && sets_again(s, time_, dt_))
      throw InputError(fmt::format(
          "{}: the field's strength is set by {} until t = {} s (now t = "
          "{} s), which would undo this; end the schedule first (sim:remove_schedule({}))",
          caller, schedule_named(s), s.schedule.times().back(), time_, s.id));
}

void SimulationBase::apply_schedules() {
  for (auto& s : schedules_) {
    const double v = s.schedule.at(time_);
    if (v == s.applied) continue;
    if (s.target == "central_strength") {
      // A field the scene removed while its schedule runs: nothing to set.
      if (body_fields().central_on) set_central_strength(v);
    } else if (s.target == "wall_angular_velocity") {
      set_wall_angular_velocity(s.wall, v);
    } else if (s.target == "wall_velocity") {
      set_wall_velocity(s.wall, {v * s.direction[0], v * s.direction[1], v * s.direction[2]});
    } else {
      const bool was_prepared = prepared_;
      try {
        update_contact(s.a, s.b, {{s.target, v}});
        // A rank's share is not prepared on its own (its particles alone would set
        // the skin and the time step): the spread run gathers the scene and
        // prepares it whole before its next step (scene_over_ranks.cpp).
        if (was_prepared && !external_rebuilds_) prepare();
      } catch (const InputError& e) {
        // Mid-run the value comes from the schedule, not from a line of the scene: say when.
        if (step_ == 0) throw;
        throw InputError(
            fmt::format("schedule '{}' of {}-{} at t = {:.6g} s (step {}), value {:.6g}: {}",
                        s.target, s.a, s.b, time_, step_, v, e.what()));
      }
    }
    s.applied = v;
  }
}

void SimulationBase::save_schedules(StateBlob& blob) const {
  blob.texts["schedules"] = lines_of(schedules_);
  std::vector<double> applied;
  for (const auto& s : schedules_) applied.push_back(s.applied);
  blob.doubles["schedules.applied"] = applied;
}

void SimulationBase::load_schedules(const StateBlob& blob) {
  const std::string& saved = blob.t("schedules");  // refuses a checkpoint without the entry
  const std::string now = lines_of(schedules_);
  if (saved != now)
    throw InputError(fmt::format(
        "checkpoint's schedules differ from the scene's (checkpoint:\n{}scene:\n{}); declare the "
        "same schedules, in the same order, as the run that wrote it",
        saved.empty() ? "none\n" : saved, now.empty() ? "none\n" : now));
  const auto& applied = blob.d("schedules.applied");
  if (applied.size() != schedules_.size())
    throw InputError(fmt::format("checkpoint: 'schedules.applied' has {} values for {} schedules",
                                 applied.size(), schedules_.size()));
  for (std::size_t k = 0; k < schedules_.size(); ++k) schedules_[k].applied = applied[k];
}

}  // namespace granule
