// Read-only views of the engine's arrays for diagnostics written in Lua:
//   local P = sim:arrays();          P.x[i], P.vx[i], P.radius[i], #P  (i = 1..#P)
//   local C = sim:contact_arrays();  C.i[k], C.j[k], C.fn[k], C.nx[k], #C
// A view allocates nothing when indexed: each element read goes straight to the
// engine's storage (particles in storage order, which list rebuilds may change: P.id[i]
// names particle i). A view is valid for the current step and reads whatever step that
// is; a column caches nothing. Writing to a view is an error.
//
// Reads are not journaled (that would cost more than the diagnostic): a restarted
// scene living through its past, whose engine is not at the state the first run's
// callbacks saw, reads NaN from every view (and lengths of the scene being rebuilt).
// What a callback computes from views and writes with sim:append is not written again
// in replay, so a diagnostic that keeps no state of its own across calls continues
// bit-identically; one that accumulates (a running sum) carries NaN on, which
// sim:result and the series refuse, loudly, and the restart warns at the first read.
#include <fmt/format.h>

#include <cstring>
#include <iostream>
#include <limits>
#include <lua.hpp>
#include <stdexcept>

#include "engine/simulation.hpp"
#include "lua/journal.hpp"
#include "lua/lua_util.hpp"
#include "lua/scene.hpp"
#include "lua/wrap_simulation.hpp"

namespace granule::lua {

namespace {

constexpr const char* particle_view_mt = "granule.ParticleArrays";
constexpr const char* contact_view_mt = "granule.ContactArrays";
constexpr const char* column_mt = "granule.ArrayColumn";

// The quantities a view offers, in one list per view (the field is its index here).
const char* const particle_fields[] = {"id", "x",  "y",  "z",  "vx", "vy",     "vz",      "wx",
                                       "wy", "wz", "fx", "fy", "fz", "radius", "material"};
const char* const contact_fields[] = {"i",  "j",  "wall", "overlap", "fn", "tx",
                                      "ty", "tz", "nx",   "ny",      "nz"};
constexpr int particle_field_count = sizeof(particle_fields) / sizeof(particle_fields[0]);
constexpr int contact_field_count = sizeof(contact_fields) / sizeof(contact_fields[0]);

struct Column {
  const LuaSim* sim;
  bool contacts;  // a column of the contact view
  int field;
};

template <int D>
const Simulation<D>& engine(const LuaSim& s) {
  return static_cast<const Simulation<D>&>(*s.sim);  // Simulation<D> is the only implementation
}

std::size_t particle_rows(const LuaSim& s) {
  return static_cast<std::size_t>(s.sim->particle_count());
}

// A scene gathered from MPI ranks lists its contacts from the gathered records
// (Simulation::gathered_contacts), in the order one process's log has them.
template <int D>
std::size_t contact_rows_d(const LuaSim& s) {
  if (const auto* gathered = engine<D>(s).gathered_contacts()) return gathered->size();
  const auto& log = engine<D>(s).contact_log();
  return log.filled ? log.slots.size() : 0;
}
std::size_t contact_rows(const LuaSim& s) {
  return s.sim->dimension() == 2 ? contact_rows_d<2>(s) : contact_rows_d<3>(s);
}

// Component k of a vector; a 2D simulation has no z (0), its spin is about z only.
template <int D, typename V>
double component(const V& v, int k) {
  return k < D ? v[k] : 0.0;
}

template <int D>
double particle_value(const LuaSim& s, int field, std::size_t i) {
  const Particles<D>& p = engine<D>(s).particles();
  switch (field) {
    case 0:
      return static_cast<double>(p.id[i]);
    case 1:
    case 2:
    case 3:
      return component<D>(p.position[i], field - 1);
    case 4:
    case 5:
    case 6:
      return component<D>(p.velocity[i], field - 4);
    case 7:
    case 8:
    case 9:
      if constexpr (D == 2)
        return field == 9 ? p.spin[i] : 0.0;
      else
        return p.spin[i][field - 7];
    case 10:
    case 11:
    case 12:
      return component<D>(p.force_torque[i].force, field - 10);
    case 13:
      return p.radius[i];
    default:
      return static_cast<double>(p.material[i]);
  }
}

template <int D>
double gathered_value(const ContactRecord& r, int field) {
  switch (field) {
    case 0:
      return static_cast<double>(r.id_a);
    case 1:
      return r.wall >= 0 ? -1.0 : static_cast<double>(r.id_b);
    case 2:
      return static_cast<double>(r.wall);
    case 3:
      return r.overlap;
    case 4:
      return r.normal_force;
    case 5:
    case 6:
    case 7:
      return component<D>(r.tangential_force, field - 5);
    default:
      return component<D>(r.normal, field - 8);
  }
}

template <int D>
double contact_value(const LuaSim& s, int field, std::size_t k) {
  const Simulation<D>& e = engine<D>(s);
  if (const auto* gathered = e.gathered_contacts()) return gathered_value<D>((*gathered)[k], field);
  const auto& log = e.contact_log();
  const std::size_t slot = log.slots[k];
  const std::int32_t b = log.b[slot];
  switch (field) {
    case 0:
      return static_cast<double>(e.particles().id[log.a[slot]]);
    case 1:
      return b >= 0 ? static_cast<double>(e.particles().id[b]) : -1.0;
    case 2:
      return b >= 0 ? -1.0 : static_cast<double>(-1 - b);
    case 3:
      return log.overlap[slot];
    case 4:
      return log.normal_force[slot];
    case 5:
    case 6:
    case 7:
      return component<D>(log.tangential[slot], field - 5);
    default:
      return component<D>(log.normal[slot], field - 8);
  }
}

// Whether a restart is replaying the scene's past, when views read NaN (and their
// lengths the scene being rebuilt, not the first run's): said once, whatever -q says,
// since what the scene keeps from these reads differs from the first run's (results it
// wrote with sim:append meanwhile are that run's).
bool read_in_replay(lua_State* L, const Column& c) {
  SceneContext* scene = c.sim->context;
  if (!scene || !scene->journal || !scene->journal->replaying()) return false;
  if (!scene->views_read_in_replay && scene->rank == 0) {
    push_script_where(L);
    std::cerr << fmt::format(
        "granule: warning: restart: {}the scene read sim:arrays() or sim:contact_arrays() "
        "while it replayed its past, when views read NaN and their lengths are not the first "
        "run's (a checkpoint does not keep what they showed); a value the scene keeps from "
        "them (a running sum, a printed line) differs from the first run's from here on\n",
        lua_tostring(L, -1));
    lua_pop(L, 1);
  }
  scene->views_read_in_replay = true;
  return true;
}

std::size_t rows(const Column& c) {
  c.sim->sim->ensure_whole();  // a view kept from an earlier callback of a spread scene
  return c.contacts ? contact_rows(*c.sim) : particle_rows(*c.sim);
}

// column[i]: 1-based, integers for ids, indices and counts, floats for quantities.
int column_index(lua_State* L) {
  const auto* c = static_cast<const Column*>(luaL_checkudata(L, 1, column_mt));
  int is_integer = 0;
  const lua_Integer i = lua_tointegerx(L, 2, &is_integer);
  const std::size_t n = rows(*c);
  const char* name = c->contacts ? contact_fields[c->field] : particle_fields[c->field];
  if (!is_integer) return luaL_error(L, "array '%s': index must be an integer 1..#", name);
  if (read_in_replay(L, *c)) {  // see the top of this file
    lua_pushnumber(L, std::numeric_limits<double>::quiet_NaN());
    return 1;
  }
  if (i < 1 || static_cast<std::size_t>(i) > n)
    return luaL_error(L, "array '%s': index %d outside 1..%d", name, static_cast<int>(i),
                      static_cast<int>(n));
  const std::size_t k = static_cast<std::size_t>(i - 1);
  const bool d2 = c->sim->sim->dimension() == 2;
  const double v = c->contacts ? (d2 ? contact_value<2>(*c->sim, c->field, k)
                                     : contact_value<3>(*c->sim, c->field, k))
                               : (d2 ? particle_value<2>(*c->sim, c->field, k)
                                     : particle_value<3>(*c->sim, c->field, k));
  const bool integral = c->contacts ? c->field <= 2 : (c->field == 0 || c->field == 14);
  if (integral)
    lua_pushinteger(L, static_cast<lua_Integer>(v));
  else
    lua_pushnumber(L, v);
  return 1;
}

int column_len(lua_State* L) {
  const auto* c = static_cast<const Column*>(luaL_checkudata(L, 1, column_mt));
  read_in_replay(L, *c);
  lua_pushinteger(L, static_cast<lua_Integer>(rows(*c)));
  return 1;
}

int read_only(lua_State* L) {
  return luaL_error(L,
                    "the arrays of sim:arrays() and sim:contact_arrays() are read-only; "
                    "change particles with sim:set_velocity, sim:set_position, sim:set_spin");
}

// view.name: the column (made at the first use, then kept in the view's user value).
int view_index(lua_State* L, bool contacts) {
  const char* key = lua_tostring(L, 2);
  const char* const* fields = contacts ? contact_fields : particle_fields;
  const int count = contacts ? contact_field_count : particle_field_count;
  int field = -1;
  for (int f = 0; key && f < count; ++f)
    if (std::strcmp(key, fields[f]) == 0) field = f;
  if (field < 0) {
    // Built on the Lua stack: lua_error must not jump over a C++ object's destructor.
    lua_pushfstring(L, "%s has no array '%s' (it has",
                    contacts ? "sim:contact_arrays()" : "sim:arrays()", key ? key : "?");
    for (int f = 0; f < count; ++f) lua_pushfstring(L, "%s %s", f ? "," : "", fields[f]);
    lua_pushliteral(L, ")");
    lua_concat(L, count + 2);
    return lua_error(L);
  }
  lua_getiuservalue(L, 1, 2);  // the cache of columns
  if (lua_rawgeti(L, -1, field + 1) != LUA_TNIL) return 1;
  lua_pop(L, 1);
  auto* view = static_cast<const Column*>(lua_touserdata(L, 1));
  auto* c = static_cast<Column*>(lua_newuserdatauv(L, sizeof(Column), 1));
  *c = Column{view->sim, contacts, field};
  lua_getiuservalue(L, 1, 1);  // the simulation, kept alive by every column
  lua_setiuservalue(L, -2, 1);
  luaL_setmetatable(L, column_mt);
  lua_pushvalue(L, -1);
  lua_rawseti(L, -3, field + 1);
  return 1;
}
int particle_view_index(lua_State* L) {
  return view_index(L, false);
}
int contact_view_index(lua_State* L) {
  return view_index(L, true);
}
int view_len(lua_State* L) {
  const auto* v = static_cast<const Column*>(lua_touserdata(L, 1));
  read_in_replay(L, *v);
  lua_pushinteger(L, static_cast<lua_Integer>(rows(*v)));
  return 1;
}

void ensure_metatables(lua_State* L) {
  if (luaL_newmetatable(L, column_mt)) {
    lua_pushcfunction(L, column_index);
    lua_setfield(L, -2, "__index");
    lua_pushcfunction(L, column_len);
    lua_setfield(L, -2, "__len");
    lua_pushcfunction(L, read_only);
    lua_setfield(L, -2, "__newindex");
  }
  lua_pop(L, 1);
  for (int contacts = 0; contacts < 2; ++contacts) {
    if (luaL_newmetatable(L, contacts ? contact_view_mt : particle_view_mt)) {
      lua_pushcfunction(L, contacts ? contact_view_index : particle_view_index);
      lua_setfield(L, -2, "__index");
      lua_pushcfunction(L, view_len);
      lua_setfield(L, -2, "__len");
      lua_pushcfunction(L, read_only);
      lua_setfield(L, -2, "__newindex");
    }
    lua_pop(L, 1);
  }
}

int push_view(lua_State* L, bool contacts) {
  LuaSim& s = self(L);
  ensure_metatables(L);
  auto* v = static_cast<Column*>(lua_newuserdatauv(L, sizeof(Column), 2));
  *v = Column{&s, contacts, -1};
  lua_pushvalue(L, 1);
  lua_setiuservalue(L, -2, 1);
  lua_createtable(L, contacts ? contact_field_count : particle_field_count, 0);
  lua_setiuservalue(L, -2, 2);
  luaL_setmetatable(L, contacts ? contact_view_mt : particle_view_mt);
  return 1;
}

}  // namespace

int l_arrays(lua_State* L) {
  return protect(L, [](lua_State* L) { return push_view(L, false); });
}

int l_contact_arrays(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    if (!s.sim->record_contacts())
      throw std::runtime_error(
          "contact_arrays: the step's contacts are recorded only with simulation { "
          "record_contacts = true }");
    return push_view(L, true);
  });
}

}  // namespace granule::lua
