// Parallel bonds (contact/parallel_bond.hpp) from a script: sim:bond makes
// them between the pairs that touch now, sim:bond_counts says how many are
// intact and broken. sim:bonds (wrap_agglomerate.cpp) is another thing: the
// contact graph of an agglomerate, bonded or not.
#include <fmt/format.h>

#include <string>
#include <vector>

#include "core/errors.hpp"
#include "engine/simulation_base.hpp"
#include "lua/lua_util.hpp"
#include "lua/wrap_simulation.hpp"

namespace granule::lua {

// sim:bond { materials = {"a", "b"}, gap = 0, radius_multiplier = 1, normal_stiffness =,
//            shear_stiffness =, tensile_strength =, shear_strength = } -> count
int l_bond(lua_State* L) {
  return protect(L, [](lua_State* L) {
    SimulationBase& sim = *self(L).sim;
    TableReader t(L, 2, "bond");
    BondSpec spec;
    if (t.push_table("materials")) {
      const std::vector<std::string> names = read_string_list(L, -1, "bond.materials");
      lua_pop(L, 1);
      if (names.size() != 1 && names.size() != 2)
        throw InputError(fmt::format(
            "bond: 'materials' names {} materials: give {{\"a\", \"b\"}} (the pairs between a "
            "particle of a and one of b) or {{\"a\"}} (pairs within a)",
            names.size()));
      spec.material_a = sim.material_id(names[0]);
      spec.material_b = sim.material_id(names.back());
    }
    spec.gap = t.number("gap", 0);
    spec.radius_multiplier = t.number("radius_multiplier", 1);
    spec.normal_stiffness = t.number("normal_stiffness");
    spec.shear_stiffness = t.number("shear_stiffness");
    spec.tensile_strength = t.number("tensile_strength");
    spec.shear_strength = t.number("shear_strength");
    t.finish();
    lua_pushinteger(L, static_cast<lua_Integer>(sim.create_bonds(spec)));
    return 1;
  });
}

// sim:bond_counts() -> { intact =, broken = }
int l_bond_counts(lua_State* L) {
  return protect(L, [](lua_State* L) {
    const SimulationBase::BondCounts c = self(L).sim->bond_counts();
    lua_createtable(L, 0, 2);
    lua_pushinteger(L, static_cast<lua_Integer>(c.intact));
    lua_setfield(L, -2, "intact");
    lua_pushinteger(L, static_cast<lua_Integer>(c.broken));
    lua_setfield(L, -2, "broken");
    return 1;
  });
}

}  // namespace granule::lua
