// Ctrl-C (SIGINT), SIGTERM and SIGHUP while Lua runs, following lua.c: the
// first signal asks the running sim:run to write a checkpoint and stop at the
// next chunk boundary, and sets a Lua hook that raises "interrupted" at the
// next Lua call, so a script loop stops too; a second signal before the first
// was handled ends the program the default way (killed by that signal). A
// second signal within half a second of the first counts as the same request:
// `timeout`, batch schedulers and some launchers signal both the child and its
// process group (and `granule sweep` passes its own signal on), and that echo
// must not turn a clean stop into a kill. SIGTERM and SIGHUP are what a
// scheduler sends at the end of a job's time and a closed terminal sends: a
// run they stop keeps its checkpoint, as one stopped by Ctrl-C does.
//
// Under mpirun a rank's standard output is a pipe or terminal the launcher reads; once
// mpirun itself is signalled it stops reading, and a scene that prints fills
// the pipe and blocks in a write until mpirun kills it: no checkpoint. So on
// the first signal such a rank's standard output stops blocking, and what the
// scene prints after it may be lost instead.
#pragma once

#include <fcntl.h>
#include <sys/stat.h>

#include <csignal>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <lua.hpp>
#include <string>

#include "lua/scene.hpp"

namespace granule::app {

inline constexpr int interrupt_signals[] = {SIGINT, SIGTERM, SIGHUP};

inline lua_State* interrupted_state = nullptr;
inline volatile std::sig_atomic_t stdout_to_launcher = 0;
inline volatile std::sig_atomic_t stdout_flags_before = -1;  // -1: left as they were

// Started by a launcher (its variables set) with standard output a pipe, a socket or a
// terminal (Open MPI gives rank 0 a pseudo-terminal it reads), not a file.
inline bool stdout_read_by_launcher() {
  bool launched = false;
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"})
    launched = launched || std::getenv(variable) != nullptr;
  struct stat out {};
  return launched && fstat(1, &out) == 0 &&
         (S_ISFIFO(out.st_mode) || S_ISSOCK(out.st_mode) || S_ISCHR(out.st_mode));
}
inline volatile std::sig_atomic_t first_signal_seconds = 0;
inline volatile std::sig_atomic_t first_signal_nanoseconds = 0;

inline double monotonic_seconds_now() {  // clock_gettime is async-signal-safe
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

inline void stop_hook(lua_State* L, lua_Debug*) {
  lua_sethook(L, nullptr, 0, 0);
  {
    // Stopped by the signal, as a run is: the program exits with 128 + the signal,
    // and the scene, between runs, is kept in a checkpoint as a run's would be (the
    // hook fires at a Lua call or instruction, never inside an engine call).
    std::string message = std::string("interrupted (") + lua::interrupt_cause() + ")";
    if (lua::SceneContext* ctx = lua::context(L)) {
      ctx->interrupted = true;
      try {
        message += lua::checkpoint_between_runs(*ctx);
      } catch (const std::exception& e) {
        message += std::string("; no checkpoint written: ") + e.what();
      }
      ctx->interrupt_message = message;
    }
    luaL_where(L, 1);
    lua_pushstring(L, message.c_str());
    lua_concat(L, 2);
  }  // (lua_error does not return: nothing with a destructor may be alive there)
  lua_error(L);
}

inline void on_interrupt_signal(int signal_number) {
  if (lua::interrupt_pending()) {  // asked twice: give up waiting
    double first = double(first_signal_seconds) + 1e-9 * double(first_signal_nanoseconds);
    if (monotonic_seconds_now() - first < 0.5) return;  // the same request, delivered twice
    std::signal(signal_number, SIG_DFL);
    std::raise(signal_number);
    return;
  }
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  first_signal_seconds = std::sig_atomic_t(t.tv_sec);
  first_signal_nanoseconds = std::sig_atomic_t(t.tv_nsec);
  lua::request_interrupt(signal_number);
  if (stdout_to_launcher) {  // (fcntl is async-signal-safe)
    const int flags = fcntl(1, F_GETFL);
    if (flags >= 0 && fcntl(1, F_SETFL, flags | O_NONBLOCK) == 0) stdout_flags_before = flags;
  }
  // A run stops between two chunks of steps by itself; only script code outside runs
  // needs the Lua hook to stop.
  if (interrupted_state && !lua::run_active())
    lua_sethook(interrupted_state, stop_hook, LUA_MASKCALL | LUA_MASKRET | LUA_MASKCOUNT, 1);
}

// Handles the signals while it exists (around running a chunk), then restores the defaults.
class InterruptScope {
 public:
  explicit InterruptScope(lua_State* L) {
    lua::clear_interrupt();
    interrupted_state = L;
    stdout_to_launcher = stdout_read_by_launcher() ? 1 : 0;
    for (int s : interrupt_signals) std::signal(s, on_interrupt_signal);
  }
  ~InterruptScope() {
    for (int s : interrupt_signals) std::signal(s, SIG_DFL);
    if (stdout_flags_before >= 0) fcntl(1, F_SETFL, int(stdout_flags_before));  // blocking again
    stdout_flags_before = -1;
    lua_sethook(interrupted_state, nullptr, 0, 0);
    interrupted_state = nullptr;
    lua::clear_interrupt();
  }
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;
};

}  // namespace granule::app
