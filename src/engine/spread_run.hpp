// A run whose steps are spread over MPI ranks, as the scene's run loop sees it
// (the Lua layer knows nothing of MPI: parallel/scene_over_ranks.hpp makes
// one). Between runs, and whenever a hook fires or the loop serves a stop
// check or a checkpoint, every rank holds the whole scene, the same bits on
// each, so that whatever a script asks or sets is the same everywhere; during
// the steps each rank holds its share.
#pragma once

#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <string>

#include "engine/simulation_base.hpp"

namespace granule {

class SpreadRun {
 public:
  virtual ~SpreadRun() = default;
  // `steps` steps, hooks fired on the gathered scene. An error in a step ends
  // every rank (it may have happened on one only).
  virtual void advance(std::int64_t steps) = 0;
  // Every rank holds the whole scene again.
  virtual void gather() = 0;
  // Runs a script's function (a run's stop_when) with the shares kept: its
  // first call that reads or changes the scene gathers it, one that reads
  // only the totals has them reduced (SimulationBase::set_pending_gather).
  virtual void run_script(const std::function<void()>& script) = 0;
  // True on every rank when it is true on any (a signal, a clock).
  virtual bool any(bool mine) = 0;
  // Rank 0's value, on every rank (a chunk length chosen from a clock).
  virtual std::int64_t agreed(std::int64_t mine) = 0;
  // The largest of the ranks' values, on every rank (the signal that stops a run).
  virtual std::int64_t largest(std::int64_t mine) = 0;
  // Ends every rank after an error that may have reached only this one.
  [[noreturn]] virtual void abandon(const std::string& message) = 0;
  // After what every rank did alike (a hook, a checkpoint), with what it
  // raised here (null: nothing): raised on every rank, it is rethrown (an
  // ordinary error, the same everywhere); on some only (a file rank 0 could
  // not write), every rank ends, lest the others wait; nowhere, returns.
  virtual void settle(const std::exception_ptr& error) = 0;
  // Each rank's time split into compute, exchange, waiting and rebuilds, a
  // line per rank, for the log (an imbalance shows as one rank computing
  // longer). Collective: every rank calls it; rank 0 gets every line.
  virtual std::string timing() const = 0;
};

// Makes the spread run of a scene (prepared, whole on every rank).
using SpreadRunMaker = std::function<std::unique_ptr<SpreadRun>(SimulationBase&)>;

}  // namespace granule
