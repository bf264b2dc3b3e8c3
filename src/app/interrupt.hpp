// Ctrl-C while Lua runs, following lua.c: the first SIGINT asks the running
// sim:run to stop at the next chunk boundary and sets a Lua hook that raises
// "interrupted" at the next Lua call, so a script loop stops too; a second
// SIGINT before the first was handled ends the program the default way. A
// second SIGINT within half a second of the first counts as the same request:
// `timeout -s INT` and some launchers signal both the child and its process
// group, and that echo must not turn a clean stop into a kill.
#pragma once

#include <csignal>
#include <ctime>
#include <lua.hpp>

#include "lua/scene.hpp"

namespace granule::app {

inline lua_State* interrupted_state = nullptr;
inline volatile std::sig_atomic_t first_sigint_seconds = 0;
inline volatile std::sig_atomic_t first_sigint_nanoseconds = 0;

inline double monotonic_seconds_now() {  // clock_gettime is async-signal-safe
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

inline void stop_hook(lua_State* L, lua_Debug*) {
  lua_sethook(L, nullptr, 0, 0);
  luaL_error(L, "interrupted (Ctrl-C)");
}

inline void on_sigint(int) {
  if (lua::interrupt_pending()) {  // asked twice: give up waiting
    double first = double(first_sigint_seconds) + 1e-9 * double(first_sigint_nanoseconds);
    if (monotonic_seconds_now() - first < 0.5) return;  // the same Ctrl-C, delivered twice
    std::signal(SIGINT, SIG_DFL);
    std::raise(SIGINT);
    return;
  }
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  first_sigint_seconds = std::sig_atomic_t(t.tv_sec);
  first_sigint_nanoseconds = std::sig_atomic_t(t.tv_nsec);
  lua::request_interrupt();
  // A run stops between two chunks of steps by itself; only script code outside runs
  // needs the Lua hook to stop.
  if (interrupted_state && !lua::run_active())
    lua_sethook(interrupted_state, stop_hook, LUA_MASKCALL | LUA_MASKRET | LUA_MASKCOUNT, 1);
}

// Handles SIGINT while it exists (around running a chunk), then restores the default.
class InterruptScope {
 public:
  explicit InterruptScope(lua_State* L) {
    lua::clear_interrupt();
    interrupted_state = L;
    std::signal(SIGINT, on_sigint);
  }
  ~InterruptScope() {
    std::signal(SIGINT, SIG_DFL);
    lua_sethook(interrupted_state, nullptr, 0, 0);
    interrupted_state = nullptr;
    lua::clear_interrupt();
  }
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;
};

}  // namespace granule::app
