#include "engine/simulation_base.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <thread>

#include "core/errors.hpp"
#include "core/plain_name.hpp"
#include "engine/simulation.hpp"

namespace granule {

int SimulationBase::add_material(const Material& m) {
  check_plain_name(m.name, "material");
  for (const auto& existing : materials_)
    if (existing.name == m.name)
      throw InputError(fmt::format("material '{}' is declared twice", m.name));
  auto positive_or_zero = [&](double v, const char* what, const char* unit) {
    if (!std::isfinite(v) || v < 0)
      throw InputError(
          fmt::format("material '{}': '{}' must be >= 0 [{}], got {}", m.name, what, unit, v));
  };
  positive_or_zero(m.density, "density", "kg/m^3");
  positive_or_zero(m.young, "young", "Pa");
  positive_or_zero(m.surface_energy, "surface_energy", "J/m^2");
  // Elastic stability of an isotropic solid needs -1 < nu <= 1/2: at nu = -1 the shear
  // modulus E / (2 (1 + nu)) of the Rayleigh time (Eq. 6.1) and of G* is infinite.
  if (!(m.poisson > -1 && m.poisson <= 0.5))
    throw InputError(
        fmt::format("material '{}': 'poisson' must be in (-1, 0.5], got {}", m.name, m.poisson));
  materials_.push_back(m);
  pairs_.resize(static_cast<int>(materials_.size()));
  unprepare();
  return static_cast<int>(materials_.size() - 1);
}

void SimulationBase::set_damping(const Damping& d) {
  auto rate = [](double c, const char* name) {
    if (!std::isfinite(c) || c < 0)
      throw InputError(fmt::format("set_damping: '{}' must be a rate >= 0 [1/s], got {}", name, c));
  };
  rate(d.viscous, "viscous");
  rate(d.spin, "spin");
  // At 1 a particle at rest under a load could never start off (its force is
  // taken whole against the motion it would begin).
  if (!std::isfinite(d.local_fraction) || d.local_fraction < 0 || d.local_fraction >= 1)
    throw InputError(
        fmt::format("set_damping: 'local_fraction' must be in [0, 1), got {}", d.local_fraction));
  damping_ = d;
}

int SimulationBase::material_id(const std::string& name) const {
  std::vector<std::string> names;
  for (std::size_t i = 0; i < materials_.size(); ++i) {
    if (materials_[i].name == name) return static_cast<int>(i);
    names.push_back(materials_[i].name);
  }
  std::string hint = nearest_name(name, names);
  throw InputError(fmt::format("unknown material '{}'{}", name,
                               hint.empty()
                                   ? std::string(names.empty() ? " (no material declared yet)" : "")
                                   : fmt::format(" (did you mean '{}'?)", hint)));
}

// Twisting is resisted about the contact normal (rolling.hpp), which a 2D
// scene's spins never have a part along.
static void refuse_twisting_in_2d(int dimension, const ParamValues& values,
                                  const std::string& context) {
  const auto mu_t = values.find("twisting_friction");
  if (dimension == 2 && mu_t != values.end() && mu_t->second > 0)
    throw InputError(fmt::format(
        "{}: twisting_friction = {} acts about the contact normal, and a 2D scene's spins (about "
        "z) have no part along any normal: it would do nothing here (3D only)",
        context, mu_t->second));
}

void SimulationBase::set_contact(const std::string& a, const std::string& b,
                                 const std::string& model, const ParamValues& given) {
  int ia = material_id(a), ib = material_id(b);
  ParamValues chosen = given;
  const int m = choose_contact_model(contact_model_id(model), chosen);  // rolling.hpp
  std::string context = fmt::format("contact '{}'-'{}' ({})", a, b, model);
  // A misspelt rolling parameter leaves the model without its rolling variant,
  // whose names the hint then offers too.
  const auto catalogue = contact_model_catalogue();
  ParamValues resolved = resolve_parameters(catalogue[m].parameters, chosen, context,
                                            catalogue[rolling_contact_model(m)].parameters);
  refuse_twisting_in_2d(dimension(), resolved, context);
  try {  // the law's own checks of its values (M::make), named by the pair
    pairs_.set(ia, ib, m, resolved, {materials_[ia], materials_[ib]});
  } catch (const InputError& error) {
    throw InputError(fmt::format("{}: {}", context, error.what()));
  }
  unprepare();
}

void SimulationBase::declare_contact(const std::string& a, const std::string& b,
                                     const std::string& model, const ParamValues& given,
                                     const std::string& where) {
  const int ia = material_id(a), ib = material_id(b);
  const std::pair<int, int> key{std::min(ia, ib), std::max(ia, ib)};
  const auto first = contact_declared_at_.find(key);
  if (first != contact_declared_at_.end())
    throw InputError(fmt::format(
        "contact '{}'-'{}' is declared twice: first at {}, again at {}; a pair has one law "
        "(declare it once, and change its parameters with sim:set_contact('{}', '{}', {{ ... }}))",
        a, b, first->second, where, a, b));
  set_contact(a, b, model, given);
  contact_declared_at_[key] = where;
}

void SimulationBase::update_contact(const std::string& a, const std::string& b,
                                    const ParamValues& changes) {
  int ia = material_id(a), ib = material_id(b);
  const std::string context = fmt::format("contact '{}'-'{}'", a, b);
  refuse_twisting_in_2d(dimension(), changes, context);
  pairs_.update(ia, ib, changes, context, {materials_[ia], materials_[ib]});
  // The time step, the spins and the adhesive reach are checked again at the
  // next prepare(); the lists hold unless something else changed too.
  const bool lists_hold = prepared_ || lists_kept_;
  unprepare();
  lists_kept_ = lists_hold;
}

void SimulationBase::set_time_step(double dt) {
  if (!std::isfinite(dt) || dt < 0)
    throw InputError(fmt::format("time_step must be > 0 [s] (or 0 for Eq. 4.1), got {}", dt));
  dt_fixed_ = dt;
  // 0: the rule chooses afresh at the next prepare(). An automatic step is
  // otherwise only ever shortened (choose_time_step), so removing the
  // particles that set it keeps it; this is how to have it lengthened.
  dt_ = dt;
  unprepare();
}

void SimulationBase::set_steps_per_contact(double n) {
  if (!std::isfinite(n) || n < 1)
    throw InputError(fmt::format("steps_per_contact must be >= 1, got {}", n));
  steps_per_contact_ = n;
  if (dt_fixed_ == 0) dt_ = 0;
  unprepare();
}

void SimulationBase::set_skin(double skin) {
  if (!std::isfinite(skin) || skin < 0)
    throw InputError(fmt::format("skin must be >= 0 [m] (0 = automatic), got {}", skin));
  skin_set_ = skin;
  unprepare();
}

void SimulationBase::set_overlap_warning(double fraction) {
  // Above 1 a pair is stopped as passing through before any warning could come.
  if (!(fraction > 0 && fraction <= 1))
    throw InputError(fmt::format(
        "overlap_warning must be in (0, 1] (a fraction of the smaller radius), got {}", fraction));
  overlap_warning_ = fraction;
  overlap_warned_ = false;
  wall_overlap_warned_ = false;
}

void SimulationBase::set_periodic(int axis, double origin, double length) {
  if (axis < 0 || axis >= dimension())
    throw InputError(fmt::format("periodic axis {} does not exist in {}D", axis, dimension()));
  if (dimension() != 3) throw InputError("a periodic axis is available in 3D scenes only");
  if (!std::isfinite(length) || length <= 0 || !std::isfinite(origin))
    throw InputError(fmt::format("periodic length must be > 0 [m], got {}", length));
  periodic_ = {axis, origin, length};
  unprepare();
}

void SimulationBase::set_threads(std::int64_t threads) {
  if (threads < 0 || threads > 4096)
    throw InputError(fmt::format(
        "threads must be from 0 to 4096 (0: OMP_NUM_THREADS where set, else 1), got {}", threads));
  // More threads than cores only take turns on them: every pair-loop barrier
  // then waits for a thread that is not running.
  const unsigned cores = std::thread::hardware_concurrency();
  if (cores > 0 && static_cast<unsigned>(threads) > 2 * cores)
    warn(
        fmt::format("threads = {} is far above the {} cores of this machine: the threads will "
                    "wait for one another; give at most {}",
                    threads, cores, cores));
  threads_ = static_cast<int>(threads);
}

int SimulationBase::thread_count() const {
  if (threads_ > 0) return threads_;
  static const int from_environment = [] {
    const char* env = std::getenv("OMP_NUM_THREADS");
    if (!env) return 1;
    char* end = nullptr;
    long n = std::strtol(env, &end, 10);
    return end != env && n >= 1 && n <= 4096 ? static_cast<int>(n) : 1;
  }();
  return from_environment;
}

int SimulationBase::add_hook(Hook hook) {
  if (hook.every_steps <= 0 && !(hook.every_time > 0))
    throw InputError(fmt::format("hook '{}': give every_steps > 0 or every_time > 0", hook.name));
  if (!hook.fire) throw InputError(fmt::format("hook '{}': no function", hook.name));
  hook.id = next_hook_id_++;
  if (hook.every_time > 0) hook.origin_time = time_, hook.periods = 1;
  hooks_.push_back(std::move(hook));
  return hooks_.back().id;
}

void SimulationBase::remove_hook(int id) {
  for (auto it = hooks_.begin(); it != hooks_.end(); ++it)
    if (it->id == id) {
      hooks_.erase(it);
      return;
    }
}

// Hooks are kept in the order they were added, which is the order of their ids.
// After a hook fires, the loop goes on from the first hook added after it, found
// by id: a hook may remove itself or others, or add new ones (which fire in the
// same step when due), and no hook is skipped or fired twice.
static std::size_t next_after(const std::vector<Hook>& hooks, int id) {
  std::size_t k = 0;
  while (k < hooks.size() && hooks[k].id <= id) ++k;
  return k;
}

void SimulationBase::fire_hooks() {
  for (std::size_t k = 0; k < hooks_.size();) {
    Hook& h = hooks_[k];
    bool due = false;
    if (h.every_steps > 0) {
      due = step_ % h.every_steps == 0;
    } else if (const double next = h.next_time();
               time_ >= next - (1e-6 * dt_ + 1e-15 * std::abs(next))) {
      // Due within round-off (both sides are products, so a few units in the last
      // place apart where dt divides the period); a step that only comes within
      // a millionth of dt of a period that dt does not divide fires for it too.
      due = true;
      // The next period strictly after now, robust to dt not dividing every_time.
      h.periods +=
          static_cast<std::int64_t>(std::max(1.0, std::floor((time_ - next) / h.every_time) + 1));
    }
    if (!due) {
      ++k;
      continue;
    }
    const int id = h.id;
    auto fn = h.fire;  // copy: the hook may remove itself
    if (hook_wrapper_)
      hook_wrapper_(h.totals_only && h.totals_only() ? HookReads::totals
                    : h.state_only && h.state_only() ? HookReads::state
                    : h.script                       ? HookReads::script
                                                     : HookReads::scene,
                    fn);
    else
      fn();
    k = next_after(hooks_, id);
  }
}

void SimulationBase::fire_start_hooks() {
  if (step_ != 0) return;  // a continued run has had its start
  for (std::size_t k = 0; k < hooks_.size();) {
    if (!hooks_[k].at_start) {
      ++k;
      continue;
    }
    hooks_[k].at_start = false;  // once
    const int id = hooks_[k].id;
    auto fn = hooks_[k].fire;
    if (hook_wrapper_)
      hook_wrapper_(HookReads::scene, fn);
    else
      fn();
    k = next_after(hooks_, id);
  }
}

void SimulationBase::warn(const std::string& message) const {
  if (warn_)
    warn_(message);
  else
    std::cerr << "warning: " << message << "\n";
}

void SimulationBase::fail(const std::string& what, const char* kept) {
  failed_at_step_ = step_;
  // What the output keeps of it (RunOutput::write_failure): spread over ranks, the
  // reason only.
  const std::string message =
      what + "; the output keeps " +
      (holds_share() ? std::string("the reason only (each rank holds its share of the scene)")
                     : std::string(kept));
  if (on_failure_) {
    try {
      on_failure_(message);
    } catch (const std::exception& e) {
      throw RunError(message +
                     fmt::format(" (and writing the failed state also failed: {})", e.what()));
    }
  }
  throw RunError(message);
}

double available_memory_bytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kib = 0;
  std::string unit;
  while (meminfo >> key >> kib >> unit)
    if (key == "MemAvailable:") return kib * 1024;
  const long pages = sysconf(_SC_AVPHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 0;
}

std::unique_ptr<SimulationBase> make_simulation(int dimension) {
  if (dimension == 2) return std::make_unique<Simulation<2>>();
  if (dimension == 3) return std::make_unique<Simulation<3>>();
  throw InputError(fmt::format("dimension must be 2 or 3, got {}", dimension));
}

}  // namespace granule
