// granule repl [scene.lua]: an interactive Lua prompt with the Granule API.
#pragma once

#include "lua/scene.hpp"

namespace granule::app {

// Runs the scene (if any), binds its last simulation to `sim`, then reads,
// runs and prints until end of input. Returns the exit status: 0, or 1 when
// input came from a pipe or file and some chunk failed (so scripted sessions
// report errors), never ending the session early.
int run_repl(const std::string& scene, lua::SceneContext& context);

}  // namespace granule::app
