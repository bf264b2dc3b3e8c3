// One scene stepped over MPI ranks by spatial decomposition: each rank owns the
// particles in its box (recursive coordinate bisection, decomposition.hpp) and
// holds ghosts of the others' particles within the interaction reach of it
// (exchange.hpp). Every step the ghosts' positions, velocities and spins come
// from their owners; at a list rebuild (decided from every rank's
// displacements, so the rebuilds fall on the steps one rank would choose)
// particles migrate to the boxes that now hold them with their contacts'
// histories, the ghosts are chosen anew and the lists rebuilt.
//
// The result is bit-identical for any number of ranks: each rank runs in
// canonical order (docs/parallel.md), so an owned particle's contacts, all on
// its rank, are summed in the same order as on one rank; a pair straddling two
// boxes is computed on both from the same bits, each adding it only to the
// particle it owns.
//
// Built so far: pair and wall contacts of the dissertation's and the common
// laws, gravity and central fields, moving walls and meshes (on every rank),
// re-cutting from measured imbalance, the gathered state, hooks (fired on the
// whole scene gathered by the caller's hook wrapper: parallel/scene_over_ranks.hpp),
// periodic scenes (each rank's scene wraps the periodic axis as one process
// does, so a ghost is the owner's particle where it is, sent once per rank
// that needs it: Images::wrapped).
// parallel bonds (every rank keeps every bond and steps those with a particle
// it owns; their states meet at each redistribution and gather).
// Not yet: diagnostics on the shares (their sums cross ranks).
#pragma once

#ifdef GRANULE_HAVE_MPI

#include <mpi.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "engine/simulation.hpp"
#include "parallel/decomposition.hpp"
#include "parallel/exchange.hpp"
#include "parallel/shared_forward.hpp"

namespace granule::parallel {

// A particle's state gathered from its owner, for comparisons and output.
template <int D>
struct GatheredParticle {
  std::int64_t id = 0;
  Vec<D> position = Vec<D>::Zero(), velocity = Vec<D>::Zero();
  Spin<D> spin = Dim<D>::zero_spin();
  Vec<D> force = Vec<D>::Zero();
  Spin<D> torque = Dim<D>::zero_spin();
  double radius = 0;
  std::int32_t material = 0;
  std::uint8_t fixed = 0;  // bit 0: fixed (infinite mass)
};

struct DistributedTimes {
  double compute = 0;   // s: this rank's steps (contacts, integration)
  double exchange = 0;  // s: forwarding the ghosts' states each step
  double rebuild = 0;   // s: at rebuilds, packing histories, migrating, new ghosts and lists
  std::int64_t rebuilds = 0;
  std::int64_t recuts = 0;  // rebuilds at which the boxes were cut afresh
  double waiting = 0;       // s: the collective that decides a rebuild (waits for the slowest rank)
};

template <int D>
class DistributedRun {
 public:
  // Every rank passes the same scene, every particle in it (as a scene script
  // run on every rank builds it); the run keeps this rank's share. Switches the
  // scene to canonical order. The boxes are cut to equal costs (particles
  // weighed by their contacts: particle_cost); `rebalance_threshold`: the
  // costliest rank's share over the mean above which a rebuild re-cuts them.
  DistributedRun(Simulation<D>& sim, MPI_Comm comm, double rebalance_threshold = 1.1);

  void advance(std::int64_t steps);

  // Ends the run: every rank's simulation holds the whole scene again, every
  // particle (in id order) with its last force and torque and its contacts'
  // histories, the walls' reactions and the step's contact tallies summed over
  // the ranks, and (where the scene records them) the last step's contacts in
  // the canonical slot order. A collective; the run takes no more steps after it.
  void dissolve();
  bool dissolved() const { return dissolved_; }
  // What stats() gives on the whole scene, bit for bit (the sums in id order),
  // on every rank; a collective. The engine's own counters (candidates,
  // rebuilds, prunes) are this rank's.
  GlobalStats totals() const;
  // Every particle's flat state and last force and torque, in id order, on
  // every rank (what flat_state() and flat_forces() give on the whole scene);
  // a collective.
  typename Simulation<D>::StateOverride gathered_state() const;

  // Every particle, in id order, on every rank.
  std::vector<GatheredParticle<D>> gather() const;
  std::int64_t global_particles() const;

  const Decomposition<D>& decomposition() const { return d_; }
  std::size_t owned() const { return owned_.size(); }
  std::size_t ghosts() const { return ghosts_.size(); }
  std::int64_t migrated() const { return migrated_; }  // particles that left this rank
  std::int64_t recuts() const { return recuts_; }
  const DistributedTimes& times() const { return times_; }
  // "ranks: 4, rcb: 4 boxes, imbalance 1.02; cuts ..." for the run header.
  std::string describe() const;

 private:
  // The boxes, from every particle's position (gathered from the ranks unless
  // this rank holds the whole scene).
  // `cost`: each stored particle's (stored_costs), every particle's when this
  // rank holds the whole scene, else the owned ones'.
  void cut(const std::vector<double>& cost, bool whole_scene_here);
  // owned_'s states from the share, and its payloads: the packed histories
  // (with `only`, those of the particles it marks; the others' left empty).
  void take_states();
  void take_histories(const std::vector<std::uint8_t>* only = nullptr);
  void take_records() { take_states(), take_histories(); }
  // What a particle costs a step, in units of a particle without contacts: its
  // own integration and checks (1), and its share of each of its contacts (a
  // pair's force is computed once per pair on one rank; each contact costs
  // about five times a particle's own work in the 3D lattice box,
  // docs/performance.md, so half of that falls on each of its particles).
  static double particle_cost(std::uint32_t contacts) { return 1.0 + 2.5 * contacts; }
  // The first `count` stored particles' costs (the owned ones come first).
  std::vector<double> stored_costs(std::size_t count) const;
  // This rank's part of the step's tallies (particles, pair and wall
  // contacts, deepest overlap), packed for sum_tallies.
  std::string tallies(const GlobalStats& here) const;
  void redistribute();  // migrate, ghosts, install
  // Every bond's state from the rank owning its first particle, to every
  // rank; the ghosts' reach from the longest bond.
  void sync_bonds();
  // owned_ and ghosts_ as the simulation's share; `keep_own`: the histories of
  // the current lists are carried too (Simulation::install_share)
  void install(bool keep_own = false);
  // The ghosts' state from their owners; with `maxima`, those values' maxima
  // over the ranks in the same exchange (forward_ghosts).
  void forward(double* maxima = nullptr, int count = 0);
  // Up to this many ranks, the step's rebuild flag and fastest speed travel
  // with the ghosts' states (every rank then sends to every other: one
  // collective a step instead of two); beyond it, an MPI_Allreduce of their own.
  static constexpr int fold_ranks = 3;  // (4 ranks in the tests take the other way)
  // The values each step reduces to their maxima over the ranks: the rebuild
  // flag, the fastest speed, the pruned lists' noting flag, the last step's
  // deepest pair overlap (Simulation::end_overlap_grace_with) and its deepest
  // pair with a particle placed mid-run (end_placed_grace_with).
  static constexpr int step_maxima = 5;

  Simulation<D>& sim_;
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  double threshold_ = 1.1;
  double contact_reach_ = 0;  // m: contacts (Simulation::interaction_reach)
  double reach_ = 0;          // m: the ghosts', contacts and bonds
  Decomposition<D> d_;
  GhostPlan plan_;
  // The forward through shared memory where every rank is on this machine.
  std::unique_ptr<SharedForward<D>> shared_;
  std::vector<ParticleRecord<D>> owned_, ghosts_;
  std::int64_t migrated_ = 0, recuts_ = 0;
  DistributedTimes times_;
  bool dissolved_ = false;
  std::int64_t steps_since_install_ = 0;
  std::string whole_contacts_;  // the whole scene's last contacts, at the start (packed)
  // totals()' per-particle buffers, kept from call to call (a callback may
  // call stats() every step): once grown they are not allocated again.
  struct TotalsBuffers {
    std::vector<std::uint32_t> which;
    typename Simulation<D>::StatColumns columns;
    std::string mine, all;
    std::vector<std::int64_t> id;
    std::vector<std::vector<double>> term;
    std::vector<std::int32_t> at_id, order;
  };
  mutable TotalsBuffers totals_buffers_;
};

}  // namespace granule::parallel

#endif  // GRANULE_HAVE_MPI
