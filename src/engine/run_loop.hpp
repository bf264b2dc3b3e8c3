// One run of a scene: the steps taken in chunks, with the scene's stop
// criterion, its checkpoint plan and the user's interrupt served between
// chunks. The engine's runner knows nothing of Lua: the binding (sim:run)
// hands it the criterion, the checkpoint writer and the progress line as
// functions, and reports the outcome to the script.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>

#include "engine/simulation_base.hpp"

namespace granule {

// The steps that cover a span of time at step dt: a span a whole number of
// steps long, less its division's round-off (a few ulps of the quotient), is
// that number of steps.
inline double steps_to_cover(double span, double dt) {
  const double quotient = span / dt;
  return std::ceil(quotient -
                   std::max(1e-9, 8 * std::numeric_limits<double>::epsilon() * quotient));
}

// When a running scene writes checkpoints (sim:checkpoint).
struct CheckpointPlan {
  std::string path;              // where periodic checkpoints go ("" = none)
  std::int64_t every_steps = 0;  // 0: not by steps
  double every_seconds = 0;      // wall-clock seconds; 0: not by time
  std::int64_t last_step = -1;   // step of the last checkpoint written
  std::chrono::steady_clock::time_point last_wall = std::chrono::steady_clock::now();
};

struct RunPlan {
  std::int64_t steps = 0;        // the run's length
  std::int64_t done = 0;         // steps already taken (a run continued from a checkpoint)
  std::int64_t check_every = 0;  // steps between stop checks, counted from the run's start;
                                 // 0: the run has no stop criterion
  // A run of a duration: the simulated time it ends at [s]. When the time step
  // changes during the run (a schedule stiffens a law, a callback adds smaller
  // particles), the steps left are counted again from the time left, so the
  // run still reaches it. NaN: a run of a step count, whatever the step.
  double end_time = std::numeric_limits<double>::quiet_NaN();
  // The time step `steps` was counted with (0: the simulation's now). A run
  // continued from a checkpoint taken before a change of the step took effect
  // (a spread run prepares at the step after a law changed) counts again at once.
  double planned_dt = 0;
};

struct RunHooks {
  std::function<bool()> stop_when;  // true ends the run (called only if check_every > 0)
  std::function<void(const std::string& path)> write_checkpoint;
  std::function<bool()> interrupt_pending;  // the user asked to stop (a signal)
  std::function<void(std::int64_t done, double time)> progress;
  std::function<void()> between_chunks;  // after each chunk (the output's rows to disk)
  // A run spread over MPI ranks (engine/spread_run.hpp): the steps, and the
  // decisions every rank must take alike although each takes them from its own
  // clock or signals: "any rank says yes", and rank 0's chunk length. Empty:
  // sim.advance(), and this process's own decisions.
  std::function<void(std::int64_t steps)> advance;
  std::function<bool(bool mine)> any;
  std::function<std::int64_t(std::int64_t mine)> agreed;
  // The run's length counted again (RunPlan::end_time): its new total of steps,
  // and the time step it was counted with.
  std::function<void(std::int64_t steps, double dt)> retarget;
};

struct RunOutcome {
  std::int64_t done = 0;     // steps taken, counting those before a continuation
  std::int64_t steps = 0;    // the run's length as it ended (RunPlan::end_time may change it)
  bool stopped = false;      // the stop criterion ended the run
  bool interrupted = false;  // a signal ended it, after a checkpoint to `interrupt_path`
};

// Takes plan.steps - plan.done steps (a run of a duration: as many more or
// fewer as a change of the time step on the way calls for). Chunks last about 0.1 s of wall time
// (so that the progress line and an interrupt are served promptly at negligible cost) and end at
// every stop check (every check_every steps of the run, also when it was continued from a
// checkpoint) and at every checkpoint step. On an interrupt it writes a checkpoint to
// `interrupt_path` between two steps and returns. Exceptions from the steps or the functions
// propagate.
RunOutcome run_in_chunks(SimulationBase& sim, const RunPlan& plan, CheckpointPlan& checkpoints,
                         const std::string& interrupt_path, const RunHooks& hooks);

}  // namespace granule
