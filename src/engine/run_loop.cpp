#include "engine/run_loop.hpp"

#include <algorithm>
#include <cmath>

namespace granule {

RunOutcome run_in_chunks(SimulationBase& sim, const RunPlan& plan, CheckpointPlan& checkpoints,
                         const std::string& interrupt_path, const RunHooks& hooks) {
  RunOutcome out;
  out.done = plan.done;
  std::int64_t chunk = 16;
  std::int64_t steps = plan.steps;
  double planned_dt = plan.planned_dt > 0 ? plan.planned_dt : sim.time_step();
  // A shorter step on the way (a schedule made a law stiffer): the steps left
  // counted again, as the run's start counted them (sim:run), from the step
  // the time step changed at rather than from where the chunk ended, whose
  // clock carries the chunk's round-off: the count is the same wherever the
  // chunks (which follow the wall clock) fall. The automatic step only shrinks
  // during a run, so the steps taken never pass the end time.
  auto count_again = [&] {
    if (!std::isfinite(plan.end_time) || sim.time_step() == planned_dt) return;
    planned_dt = sim.time_step();
    const std::int64_t since = sim.step_count() - sim.time_step_from_step();
    const double left = steps_to_cover(plan.end_time - sim.time_step_from_time(), planned_dt);
    steps = out.done - since + static_cast<std::int64_t>(std::max(0.0, std::min(left, 4.6e18)));
    steps = std::max(steps, out.done);
    if (hooks.retarget) hooks.retarget(steps, planned_dt);
  };
  count_again();
  const std::int64_t check_every = plan.check_every;
  auto checkpoint = [&](const std::string& path) {
    hooks.write_checkpoint(path);
    checkpoints.last_step = sim.step_count();
    checkpoints.last_wall = std::chrono::steady_clock::now();
  };
  auto any = [&](bool mine) { return hooks.any ? hooks.any(mine) : mine; };
  // No checkpoint at a run's last step (a scene continued from there would have no
  // contacts to report until its next step), so one due there is written before the
  // next run's first step, as an interrupt there would be: stages exactly
  // `every_steps` long are saved too.
  if (plan.done == 0 && !checkpoints.path.empty() && checkpoints.every_steps > 0 && steps > 0 &&
      sim.step_count() > 0 && sim.step_count() % checkpoints.every_steps == 0 &&
      checkpoints.last_step != sim.step_count())
    checkpoint(checkpoints.path);
  while (out.done < steps) {
    if (any(hooks.interrupt_pending && hooks.interrupt_pending())) {
      checkpoint(interrupt_path);
      out.interrupted = true;
      out.steps = steps;
      return out;
    }
    std::int64_t n = std::min<std::int64_t>(chunk, steps - out.done);
    if (check_every > 0) n = std::min(n, check_every - out.done % check_every);
    if (checkpoints.every_steps > 0)
      n = std::min(n, checkpoints.every_steps - sim.step_count() % checkpoints.every_steps);
    const auto t0 = std::chrono::steady_clock::now();
    if (hooks.advance)
      hooks.advance(n);
    else
      sim.advance(n);
    out.done += n;
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (wall < 0.05 && chunk < (std::int64_t{1} << 24))
      chunk *= 2;
    else if (wall > 0.2 && chunk > 1)
      chunk /= 2;
    if (hooks.agreed) chunk = hooks.agreed(chunk);
    count_again();
    if (hooks.progress) hooks.progress(out.done - plan.done, sim.time());
    if (hooks.between_chunks) hooks.between_chunks();
    if (check_every > 0 && (out.done % check_every == 0 || out.done == steps) &&
        hooks.stop_when()) {
      out.stopped = true;
      out.steps = steps;
      return out;
    }
    if (!checkpoints.path.empty() && out.done < steps) {
      const bool by_steps =
          checkpoints.every_steps > 0 && sim.step_count() % checkpoints.every_steps == 0;
      const bool by_time = any(
          checkpoints.every_seconds > 0 &&
          std::chrono::duration<double>(std::chrono::steady_clock::now() - checkpoints.last_wall)
                  .count() >= checkpoints.every_seconds);
      if (by_steps || by_time) checkpoint(checkpoints.path);
    }
  }
  out.steps = steps;
  return out;
}

}  // namespace granule
