// sim:schedule { target, <form> = ..., from =, to =, wall =, direction = }:
// a value that follows simulated time, set before every step in C++
// (fields/schedule.hpp, engine/simulation_schedules.cpp). The forms:
//   constant = v
//   linear = { t0, v0, t1, v1 }            v0 until t0, linear to v1 at t1, then v1
//   piecewise = { t1, v1, t2, v2, ... }    linear through the points, held outside them
//   points = { { t1, v1 }, { t2, v2 }, ... }   the same, as a table of {time, value} pairs
#include <fmt/format.h>

#include <limits>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "fields/schedule.hpp"
#include "lua/lua_simulation.hpp"
#include "lua/lua_util.hpp"
#include "lua/scene.hpp"

namespace granule::lua {

namespace {

// points = { {t, v}, ... }: each entry a pair of numbers.
void read_points(lua_State* L, int index, const std::string& what, std::vector<double>& times,
                 std::vector<double>& values) {
  index = lua_absindex(L, index);
  const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, index));
  for (lua_Integer k = 1; k <= n; ++k) {
    lua_rawgeti(L, index, k);
    const bool pair = lua_type(L, -1) == LUA_TTABLE && lua_rawlen(L, -1) == 2;
    double tv[2] = {0, 0};
    if (pair) {
      for (int j = 0; j < 2; ++j) {
        lua_rawgeti(L, -1, j + 1);
        const bool number = lua_type(L, -1) == LUA_TNUMBER;
        tv[j] = lua_tonumber(L, -1);
        lua_pop(L, 1);
        if (!number) {
          lua_pop(L, 1);
          throw InputError(
              fmt::format("{}: 'points[{}]' must be {{time, value}} (numbers)", what, k));
        }
      }
    }
    lua_pop(L, 1);
    if (!pair)
      throw InputError(fmt::format("{}: 'points[{}]' must be a pair {{time, value}}", what, k));
    times.push_back(tv[0]);
    values.push_back(tv[1]);
  }
}

int l_schedule(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    if (!lua_istable(L, 2))
      throw std::runtime_error("schedule: expected { 'target', linear = {...}, ... }");
    lua_rawgeti(L, 2, 1);
    if (lua_type(L, -1) != LUA_TSTRING)
      throw std::runtime_error(
          "schedule: the first entry must be the target's name ('central_strength', "
          "'wall_angular_velocity', 'wall_velocity', 'friction', 'surface_energy', ...)");
    ScheduleSpec spec;
    spec.target = lua_tostring(L, -1);
    lua_pop(L, 1);
    const std::string what = fmt::format("schedule '{}'", spec.target);
    TableReader t(L, 2, what);
    t.mark("1");
    const bool wall = spec.target == "wall_angular_velocity" || spec.target == "wall_velocity";
    const bool field = spec.target == "central_strength";
    if (wall) spec.a = t.string("wall");
    if (spec.target == "wall_velocity") spec.direction = t.vector("direction", s.sim->dimension());
    if (!wall && !field) {
      spec.a = t.string("from");
      spec.b = t.string("to");
    }
    // Documented keys that do not apply to this target: refused by what they are for.
    auto refuse = [&](const char* key, bool applies, const char* targets) {
      if (!t.has(key) || applies) return;
      t.mark(key);
      throw InputError(
          fmt::format("{}: '{}' applies to {} only, not to '{}'", what, key, targets, spec.target));
    };
    refuse("wall", wall, "wall targets (wall_angular_velocity, wall_velocity)");
    refuse("direction", spec.target == "wall_velocity", "wall_velocity");
    refuse("from", !wall && !field, "contact parameters");
    refuse("to", !wall && !field, "contact parameters");
    int forms = 0;
    for (const char* f : {"constant", "linear", "piecewise", "points"}) forms += t.has(f) ? 1 : 0;
    if (forms != 1)
      throw InputError(fmt::format(
          "{}: give exactly one of constant = v, linear = {{t0, v0, t1, v1}}, piecewise = {{t1, "
          "v1, t2, v2, ...}} or points = {{{{t1, v1}}, ...}} (got {})",
          what, forms));
    if (t.has("constant")) {
      spec.schedule = Schedule::constant(t.number("constant"), what + ", constant");
    } else if (t.has("linear")) {
      const auto v = t.numbers("linear");
      if (v.size() != 4)
        throw InputError(
            fmt::format("{}: 'linear' must be {{t0, v0, t1, v1}}, got {} numbers", what, v.size()));
      spec.schedule = Schedule::linear(v[0], v[1], v[2], v[3], what + ", linear");
    } else if (t.has("piecewise")) {
      const auto v = t.numbers("piecewise");
      if (v.empty() || v.size() % 2 != 0)
        throw InputError(
            fmt::format("{}: 'piecewise' must be {{t1, v1, t2, v2, ...}} (pairs), got {} numbers",
                        what, v.size()));
      std::vector<double> times, values;
      for (std::size_t k = 0; k < v.size(); k += 2)
        times.push_back(v[k]), values.push_back(v[k + 1]);
      spec.schedule = Schedule::piecewise(times, values, what + ", piecewise");
    } else {
      if (!t.push_table("points"))
        throw InputError(
            fmt::format("{}: 'points' must be a table of {{time, value}} pairs", what));
      std::vector<double> times, values;
      try {
        read_points(L, -1, what, times, values);
      } catch (...) {
        lua_pop(L, 1);
        throw;
      }
      lua_pop(L, 1);
      spec.schedule = Schedule::piecewise(times, values, what + ", points");
    }
    t.finish();
    // As set_contact's claim: the replay's engine is not at the first run's time.
    if (!replaying(L)) s.sim->claim_schedule_target(spec);
    lua_pushinteger(L, s.sim->add_schedule(std::move(spec)));
    return 1;
  });
}

// sim:remove_schedule(id): the schedule ends; its target keeps its value.
int l_remove_schedule(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    if (s.running)
      throw InputError(
          "remove_schedule: not from inside a run's callback; end a schedule between runs");
    const std::int64_t id = read_integer(L, 2, "remove_schedule: schedule id");
    if (id < 1 || id > std::numeric_limits<int>::max())
      throw InputError(fmt::format("remove_schedule: no schedule {}", id));
    s.sim->remove_schedule(static_cast<int>(id));
    return 0;
  });
}

}  // namespace

const luaL_Reg schedule_methods[] = {
    {"schedule", l_schedule},
    {"remove_schedule", l_remove_schedule},
    {nullptr, nullptr},
};

}  // namespace granule::lua
