// The simulation's read-only queries: a wall, a particle, the particle ids, global
// statistics, the contact list, time and step, the time-step rule, stage timings,
// contact parameters, materials and wall names.
#include <fmt/format.h>

#include "contact/models.hpp"
#include "contact/pair_table.hpp"
#include "contact/rolling.hpp"
#include "core/errors.hpp"
#include "engine/simulation_base.hpp"
#include "lua/lua_util.hpp"
#include "lua/wrap_simulation.hpp"

namespace granule::lua {

int l_wall(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    int d = dim(L);
    int w = s.sim->wall_id(read_string(L, 2, "wall name"));
    WallSpec spec = s.sim->wall(w);
    lua_newtable(L);
    lua_pushstring(L, spec.name.c_str());
    lua_setfield(L, -2, "name");
    lua_pushstring(L, wall_type_name(spec.type));
    lua_setfield(L, -2, "type");
    lua_pushboolean(L, spec.finite());
    lua_setfield(L, -2, "finite");
    push_vector(L, s.sim->wall_force(w), d);
    lua_setfield(L, -2, "force");
    lua_pushnumber(L, s.sim->wall_axial_torque(w));
    lua_setfield(L, -2, "torque");
    // The geometry as the scene gave it, resolved (directions normalised, a
    // rectangle's default side chosen), so that a script can read it back.
    auto pair = [L](double a, double b, const char* key) {
      lua_createtable(L, 2, 0);
      lua_pushnumber(L, a);
      lua_rawseti(L, -2, 1);
      lua_pushnumber(L, b);
      lua_rawseti(L, -2, 2);
      lua_setfield(L, -2, key);
    };
    if (spec.type == WallType::plane) {
      push_vector(L, spec.point, d);
      lua_setfield(L, -2, "point");
      push_vector(L, spec.normal, d);
      lua_setfield(L, -2, "normal");
      push_vector(L, spec.velocity, d);
      lua_setfield(L, -2, "velocity");
      if (spec.bounded) {  // a rectangle (a segment in 2D)
        if (d == 3) {
          pair(spec.size_a, spec.size_b, "size");
          push_vector(L, spec.side, d);
          lua_setfield(L, -2, "side");
        } else {
          lua_pushnumber(L, spec.size_a);
          lua_setfield(L, -2, "size");
        }
      }
    } else if (is_surface_wall(spec.type)) {  // offset: how far it has moved
      push_vector(L, spec.point, d);
      lua_setfield(L, -2, "offset");
      push_vector(L, spec.velocity, d);
      lua_setfield(L, -2, "velocity");
      push_vector(L, spec.center, d);
      lua_setfield(L, -2, "axis_point");
      if (d == 3) {  // a polyline turns about z
        push_vector(L, spec.axis, d);
        lua_setfield(L, -2, "axis");
      }
      lua_pushnumber(L, spec.angular_velocity);
      lua_setfield(L, -2, "angular_velocity");
      lua_pushnumber(L, spec.angle);
      lua_setfield(L, -2, "angle");
    } else {
      push_vector(L, spec.center, d);
      lua_setfield(L, -2, "center");
      if (spec.type != WallType::cone) {
        lua_pushnumber(L, spec.radius);
        lua_setfield(L, -2, "radius");
      }
      lua_pushnumber(L, spec.angular_velocity);
      lua_setfield(L, -2, "angular_velocity");
      if (spec.type == WallType::cylinder) {
        lua_pushboolean(L, spec.inside);
        lua_setfield(L, -2, "inside");
        if (d == 3) {
          push_vector(L, spec.axis, d);
          lua_setfield(L, -2, "axis");
        }
        if (spec.bounded) pair(spec.z_lo, spec.z_hi, "bounds");
      } else if (spec.type == WallType::disk) {
        push_vector(L, spec.normal, d);
        lua_setfield(L, -2, "normal");
        lua_pushnumber(L, spec.inner_radius);
        lua_setfield(L, -2, "inner_radius");
      } else if (spec.type == WallType::cone) {
        push_vector(L, spec.axis, d);
        lua_setfield(L, -2, "axis");
        pair(spec.z_lo, spec.z_hi, "bounds");
        pair(spec.radius_lo, spec.radius_hi, "radii");
      }
      if (spec.bounded || spec.type != WallType::cylinder) {  // finite walls also translate
        push_vector(L, spec.velocity, d);
        lua_setfield(L, -2, "velocity");
      }
    }
    return 1;
  });
}

// ---- particles ----
int l_particle(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    int d = dim(L);
    std::int64_t id = particle_id(L, 2, *s.sim);
    lua_newtable(L);
    lua_pushinteger(L, id);
    lua_setfield(L, -2, "id");
    push_vector(L, s.sim->position(id), d);
    lua_setfield(L, -2, "position");
    push_vector(L, s.sim->velocity(id), d);
    lua_setfield(L, -2, "velocity");
    if (d == 2)
      lua_pushnumber(L, s.sim->spin(id)[2]);
    else
      push_vector(L, s.sim->spin(id), 3);
    lua_setfield(L, -2, "spin");
    push_vector(L, s.sim->force(id), d);
    lua_setfield(L, -2, "force");
    lua_pushnumber(L, s.sim->radius(id));
    lua_setfield(L, -2, "radius");
    lua_pushnumber(L, s.sim->mass(id));
    lua_setfield(L, -2, "mass");
    lua_pushstring(L, s.sim->materials()[s.sim->material_of(id)].name.c_str());
    lua_setfield(L, -2, "material");
    lua_pushboolean(L, s.sim->is_fixed(id));
    lua_setfield(L, -2, "fixed");
    return 1;
  });
}

int l_particles(lua_State* L) {
  return protect(L, [](lua_State* L) {
    auto ids = self(L).sim->particle_ids();
    lua_createtable(L, static_cast<int>(ids.size()), 0);
    for (std::size_t k = 0; k < ids.size(); ++k) {
      lua_pushinteger(L, ids[k]);
      lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
    }
    return 1;
  });
}

// ---- queries ----
int l_stats(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self_totals(L);
    GlobalStats g = s.sim->stats();
    lua_newtable(L);
    auto set = [&](const char* k, double v) {
      lua_pushnumber(L, v);
      lua_setfield(L, -2, k);
    };
    set("time", g.time);
    lua_pushinteger(L, g.step);
    lua_setfield(L, -2, "step");
    lua_pushinteger(L, g.particles);
    lua_setfield(L, -2, "particles");
    set("kinetic_energy", g.kinetic_translational + g.kinetic_rotational);
    set("kinetic_energy_translational", g.kinetic_translational);
    set("kinetic_energy_rotational", g.kinetic_rotational);
    set("free_mass", g.free_mass);
    push_vector(L, g.momentum, s.sim->dimension());
    lua_setfield(L, -2, "momentum");
    set("angular_momentum_z", g.angular_momentum_z);
    lua_pushinteger(L, g.contacts_particle);
    lua_setfield(L, -2, "contacts_particle");
    lua_pushinteger(L, g.contacts_batched);
    lua_setfield(L, -2, "contacts_batched");
    lua_pushinteger(L, g.contacts_wall_batched);
    lua_setfield(L, -2, "contacts_wall_batched");
    lua_pushinteger(L, g.contacts_wall);
    lua_setfield(L, -2, "contacts_wall");
    set("max_overlap_ratio", g.max_overlap_ratio);
    set("candidate_pairs", static_cast<double>(g.candidate_pairs));
    set("list_rebuilds", static_cast<double>(g.list_rebuilds));
    set("thread_rebalances", static_cast<double>(g.thread_rebalances));
    set("pair_list_prunes", static_cast<double>(g.pair_list_prunes));
    set("pair_candidates_visited", static_cast<double>(g.pair_candidates_visited));
    return 1;
  });
}

int l_contacts(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    int d = s.sim->dimension();
    auto list = s.sim->contacts();
    lua_createtable(L, static_cast<int>(list.size()), 0);
    for (std::size_t k = 0; k < list.size(); ++k) {
      const ContactRecord& c = list[k];
      lua_newtable(L);
      lua_pushinteger(L, c.id_a);
      lua_setfield(L, -2, "a");
      if (c.wall >= 0) {
        lua_pushstring(L, s.sim->wall(c.wall).name.c_str());
        lua_setfield(L, -2, "wall");
      } else {
        lua_pushinteger(L, c.id_b);
        lua_setfield(L, -2, "b");
      }
      lua_pushstring(L, c.model.c_str());
      lua_setfield(L, -2, "model");
      lua_pushnumber(L, c.overlap);
      lua_setfield(L, -2, "overlap");
      lua_pushnumber(L, c.normal_force);
      lua_setfield(L, -2, "normal_force");
      push_vector(L, c.tangential_force, d);
      lua_setfield(L, -2, "tangential_force");
      push_vector(L, c.normal, d);
      lua_setfield(L, -2, "normal");
      lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
    }
    return 1;
  });
}

int l_time(lua_State* L) {
  return protect(L, [](lua_State* L) {
    lua_pushnumber(L, self_kept(L).sim->time());
    return 1;
  });
}
int l_step_count(lua_State* L) {
  return protect(L, [](lua_State* L) {
    lua_pushinteger(L, self_kept(L).sim->step_count());
    return 1;
  });
}
int l_time_step(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    s.sim->ensure_prepared();
    lua_pushnumber(L, s.sim->time_step());
    return 1;
  });
}
int l_time_step_rule(lua_State* L) {
  return protect(L, [](lua_State* L) {
    TimeStepReport r = self(L).sim->time_step_rule();
    lua_newtable(L);
    lua_pushnumber(L, r.rule);
    lua_setfield(L, -2, "rule");
    lua_pushnumber(L, r.stability_limit);
    lua_setfield(L, -2, "stability_limit");
    lua_pushstring(L, r.governing_pair.c_str());
    lua_setfield(L, -2, "governing_pair");
    return 1;
  });
}
int l_describe(lua_State* L) {
  return protect(L, [](lua_State* L) {
    std::string all;
    for (const auto& line : self(L).sim->describe()) all += line + "\n";
    lua_pushstring(L, all.c_str());
    return 1;
  });
}
// Wall-clock seconds spent per stage of the step since the simulation was made.
int l_timings(lua_State* L) {
  return protect(L, [](lua_State* L) {
    const auto& t = self(L).sim->stage_times();
    lua_newtable(L);
    lua_pushnumber(L, t.neighbor);
    lua_setfield(L, -2, "neighbor");
    lua_pushnumber(L, t.force);
    lua_setfield(L, -2, "force");
    lua_pushnumber(L, t.diagnostics);
    lua_setfield(L, -2, "diagnostics");
    lua_pushnumber(L, t.integrate);
    lua_setfield(L, -2, "integrate");
    lua_pushnumber(L, t.hooks);
    lua_setfield(L, -2, "hooks");
    lua_pushnumber(L, t.scatter);
    lua_setfield(L, -2, "scatter");
    lua_pushnumber(L, t.walls);
    lua_setfield(L, -2, "walls");
    lua_pushnumber(L, t.pair_wait);
    lua_setfield(L, -2, "pair_wait");
    return 1;
  });
}
int l_dimension(lua_State* L) {
  return protect(L, [](lua_State* L) {
    lua_pushinteger(L, dim(L));
    return 1;
  });
}

int l_contact_parameters(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    std::string a = read_string(L, 2, "contact_parameters: first material");
    std::string b = read_string(L, 3, "contact_parameters: second material");
    int ia = s.sim->material_id(a), ib = s.sim->material_id(b);
    const PairTable& table = s.sim->pair_table();
    const PairTable::Entry& e = table.at(ia, ib);
    if (e.model < 0)
      throw std::runtime_error(fmt::format("no contact law between '{}' and '{}'", a, b));
    lua_newtable(L);
    lua_pushstring(L, contact_model_catalogue()[e.model].name.c_str());
    lua_setfield(L, -2, "model");
    for (const auto& [name, value] : table.values_in_effect(ia, ib, s.sim->materials())) {
      if (name == "rolling_model")
        lua_pushstring(L, rolling_model_name(value));
      else
        lua_pushnumber(L, value);
      lua_setfield(L, -2, name.c_str());
    }
    return 1;
  });
}

int l_materials(lua_State* L) {
  return protect(L, [](lua_State* L) {
    const auto& mats = self(L).sim->materials();
    lua_createtable(L, static_cast<int>(mats.size()), 0);
    for (std::size_t k = 0; k < mats.size(); ++k) {
      lua_newtable(L);
      lua_pushstring(L, mats[k].name.c_str());
      lua_setfield(L, -2, "name");
      const std::pair<const char*, double> fields[] = {{"density", mats[k].density},
                                                       {"young", mats[k].young},
                                                       {"poisson", mats[k].poisson},
                                                       {"surface_energy", mats[k].surface_energy}};
      for (const auto& [key, value] : fields) {
        lua_pushnumber(L, value);
        lua_setfield(L, -2, key);
      }
      lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
    }
    return 1;
  });
}

int l_walls(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    lua_createtable(L, s.sim->wall_count(), 0);
    for (int w = 0; w < s.sim->wall_count(); ++w) {
      lua_pushstring(L, s.sim->wall(w).name.c_str());
      lua_rawseti(L, -2, w + 1);
    }
    return 1;
  });
}

}  // namespace granule::lua
