#include "parallel/scene_over_ranks.hpp"

#ifdef GRANULE_HAVE_MPI

#include <fmt/format.h>

#include <exception>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "io/rank_files.hpp"
#include "parallel/distributed_run.hpp"
#include "parallel/gathering.hpp"

namespace granule::parallel {

namespace {

std::string message_of(const std::exception_ptr& error) {
  if (!error) return "it failed on another rank";
  try {
    std::rethrow_exception(error);
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
  }
  return "a hook failed with an exception that is not a std::exception";
}

template <int D>
class SceneOverRanks final : public SpreadRun {
 public:
  SceneOverRanks(Simulation<D>& sim, MPI_Comm comm, double threshold)
      : sim_(sim), comm_(comm), threshold_(threshold) {
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size_);
    // Canonical order: each particle's sums do not depend on which rank holds
    // it (docs/parallel.md); a plain run with canonical_order = true gives the
    // same bits.
    sim_.set_canonical_order(true);
    sim_.ensure_prepared();
    sim_.set_hook_wrapper([this](HookReads reads, const std::function<void()>& fire) {
      // A hook that reads only the totals (the output's series row) gets them
      // reduced over the ranks, one that reads only the particles (the
      // output's snapshots) gets them gathered, the shares kept, and a
      // script's function is fired with the shares kept, to be gathered by
      // its first call that needs more than the totals (gather_when_needed).
      // Any other gets the whole scene, and so do snapshots of a scene with
      // bonds (they record the bonds, whose states meet at a gather).
      const bool shared = run_ && !run_->dissolved();
      const bool whole =
          reads == HookReads::scene || (reads == HookReads::state && !sim_.bonds().empty());
      if (shared && reads == HookReads::script) {
        gather_when_needed();
      } else if (shared && !whole) {
        sim_.set_stats_override(run_->totals());
        if (reads == HookReads::state) sim_.set_state_override(run_->gathered_state());
      } else {
        gather();
      }
      // A script's error is raised on every rank alike, from the same scene,
      // and ends the run as on one process (settle).
      std::exception_ptr error;
      try {
        fire();
      } catch (...) {
        error = std::current_exception();
      }
      end_firing();
      hook_failed_ = error != nullptr;
      settle(error);
    });
    // An error while sharing may be one rank's alone, with the others already
    // inside the share's collectives (a window's free waits for every rank):
    // it ends them all rather than leave them waiting.
    try {
      share();
    } catch (const std::exception& e) {
      abandon(e.what());
    }
    sim_.set_spread(size_, run_->describe());
  }

  ~SceneOverRanks() override {
    // Every rank gets here together: from the end of a run, or from an error
    // every rank raised (a script's); an error on one rank ends them all first.
    try {
      gather();
    } catch (const std::exception& e) {
      abandon(e.what());
    }
    sim_.set_hook_wrapper({});
  }

  void advance(std::int64_t steps) override {
    try {
      if (steps > 0 && sim_.step_count() == 0) sim_.fire_start_hooks();
      for (std::int64_t s = 0; s < steps; ++s) {
        if (sim_.whole_step_due()) {
          // A step a diagnostic looks at: taken whole on every rank (the same
          // bits as the share's would give, each rank doing all the work).
          gather();
          sim_.step();
          ++whole_steps_;
          continue;
        }
        if (!run_ || run_->dissolved()) share();
        run_->advance(1);
        // A schedule changed a law: prepared whole before the next step, as one
        // process prepares it at once.
        if (!sim_.prepared()) gather();
      }
    } catch (const std::exception& e) {
      if (hook_failed_) throw;
      abandon(e.what());  // a step's error (NaN, an escape) may be this rank's alone
    }
  }

  void run_script(const std::function<void()>& script) override {
    if (run_ && !run_->dissolved()) gather_when_needed();
    // An error on one rank alone (a criterion reading the wall clock, or this
    // rank's environment) ends them all with its message, as a hook's does.
    std::exception_ptr error;
    try {
      script();
    } catch (...) {
      error = std::current_exception();
    }
    end_firing();
    settle(error);
  }

  void gather() override {
    if (run_ && !run_->dissolved()) {
      run_->dissolve();
      add(total_, run_->times());
    }
  }

  bool any(bool mine) override {
    int in = mine ? 1 : 0, out = 0;
    MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_MAX, comm_);
    return out != 0;
  }

  std::int64_t agreed(std::int64_t mine) override {
    MPI_Bcast(&mine, 1, MPI_INT64_T, 0, comm_);
    return mine;
  }

  std::int64_t largest(std::int64_t mine) override {
    std::int64_t out = mine;
    MPI_Allreduce(&mine, &out, 1, MPI_INT64_T, MPI_MAX, comm_);
    return out;
  }

  [[noreturn]] void abandon(const std::string& message) override {
    std::cerr << fmt::format("granule: rank {} of {}: error: {}\n", rank_, size_, message);
    std::cerr.flush();
    io::remove_scratch();  // MPI_Abort ends the process without its exit's clean-up
    MPI_Abort(comm_, 1);
    std::abort();  // MPI_Abort does not return
  }

  void settle(const std::exception_ptr& error) override {
    const int failed = error ? 1 : 0;
    int somewhere = 0, everywhere = 0;
    MPI_Allreduce(&failed, &somewhere, 1, MPI_INT, MPI_MAX, comm_);
    MPI_Allreduce(&failed, &everywhere, 1, MPI_INT, MPI_MIN, comm_);
    if (somewhere && !everywhere) abandon(message_of(error));
    if (error) std::rethrow_exception(error);
  }

  std::string timing() const override {
    DistributedTimes t = total_;
    if (run_ && !run_->dissolved()) add(t, run_->times());
    const std::string mine = fmt::format(
        "granule: rank {}: compute {:.3g} s, ghost exchange {:.3g} s, waiting {:.3g} s, "
        "rebuilds {} ({:.3g} s; boxes cut afresh at {}), steps taken whole for the diagnostics "
        "{}\n",
        rank_, t.compute, t.exchange, t.waiting, t.rebuilds, t.rebuild, t.recuts, whole_steps_);
    // Every rank's line, in rank order (once, at the end of a run).
    const std::string all = all_gather(mine, comm_);
    return rank_ == 0 ? all : mine;
  }

 private:
  // After a hook or a script: nothing pending, no overrides.
  void end_firing() {
    sim_.set_pending_gather({}, {});
    sim_.set_stats_override(std::nullopt);
    sim_.set_state_override(std::nullopt);
  }
  // The scene gathered by the first script call that needs it (a script's
  // function, a run's stop_when: one that monitors the totals then costs one
  // reduction, not a gather and a re-share); the totals reduced for one that
  // needs only them (SimulationBase::set_pending_gather).
  void gather_when_needed() {
    sim_.set_pending_gather(
        [this] {
          sim_.set_stats_override(std::nullopt);
          gather();
        },
        [this] { sim_.set_stats_override(run_->totals()); });
  }
  void share() { run_ = std::make_unique<DistributedRun<D>>(sim_, comm_, threshold_); }
  static void add(DistributedTimes& to, const DistributedTimes& t) {
    to.compute += t.compute, to.exchange += t.exchange, to.waiting += t.waiting;
    to.rebuild += t.rebuild, to.rebuilds += t.rebuilds, to.recuts += t.recuts;
  }

  Simulation<D>& sim_;
  MPI_Comm comm_;
  double threshold_;
  int rank_ = 0, size_ = 1;
  std::unique_ptr<DistributedRun<D>> run_;
  DistributedTimes total_;
  bool hook_failed_ = false;
  std::int64_t whole_steps_ = 0;
};

}  // namespace

SpreadRunMaker spread_over(MPI_Comm comm, double rebalance_threshold) {
  return [comm, rebalance_threshold](SimulationBase& sim) -> std::unique_ptr<SpreadRun> {
    if (auto* s2 = dynamic_cast<Simulation<2>*>(&sim))
      return std::make_unique<SceneOverRanks<2>>(*s2, comm, rebalance_threshold);
    if (auto* s3 = dynamic_cast<Simulation<3>*>(&sim))
      return std::make_unique<SceneOverRanks<3>>(*s3, comm, rebalance_threshold);
    throw InputError("a scene of neither 2 nor 3 dimensions cannot be spread over ranks");
  };
}

}  // namespace granule::parallel

#endif  // GRANULE_HAVE_MPI
