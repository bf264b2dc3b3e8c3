// granule repl [scene.lua]: an interactive Lua prompt with the Granule API.
#pragma once

#include <functional>
#include <string>

#include "lua/scene.hpp"

namespace granule::app {

// Where the prompt's lines come from: `read` shows the prompt and gives the
// next line (false at end of input); `interactive`: a person types them (a
// banner, readline's history and completion, and errors never fail the session).
struct ReplInput {
  std::function<bool(const char* prompt, std::string& line)> read;
  bool interactive = false;
  // Called on the prompt's Lua state once it is made (a rank's file mapping).
  std::function<void(lua_State*)> prepare;
};

// Standard input: readline on a terminal, else plain lines.
ReplInput terminal_input();
// One line from the terminal (or a pipe) as terminal_input().read reads it.
bool read_terminal_line(const char* prompt, std::string& line);

// Runs the scene (if any), binds its last simulation to `sim`, then reads,
// runs and prints until end of input. Returns the exit status: 0, or 1 when
// input came from a pipe or file and some chunk failed (so scripted sessions
// report errors), never ending the session early. Under mpirun every rank
// calls it with the lines rank 0 reads (main.cpp): each chunk runs on every
// rank, so the scene's runs spread over the ranks as `granule run`'s do.
int run_repl(const std::string& scene, lua::SceneContext& context,
             const ReplInput& input = terminal_input());

}  // namespace granule::app
