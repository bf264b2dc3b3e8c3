// What the contact stage tells observers about one step: one entry per
// candidate contact slot (the engine's flat contact buffers), filled only on
// steps where something asked for it, and contact events (begin, end with the
// peak values reached) on every step while an observer tracks them.
//
// Slots are written by the force kernels in parallel, each its own entry, so
// logging costs a few stores per contact and nothing when nobody asks.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "core/types.hpp"

namespace granule {

// A contact that began or ended this step.
template <int D>
struct ContactEvent {
  std::int64_t id_a = -1;            // persistent ids; the lower id of a particle pair
  std::int64_t id_b = -1;            // -1 for a wall contact
  int wall = -1;                     // wall index for a wall contact
  double begin_time = 0;             // s, first step in contact
  double end_time = 0;               // s, first step out of contact (ended events only)
  double impact_velocity = 0;        // m/s, normal approach speed at the first step in contact
  double peak_normal_force = 0;      // N, largest normal force during the contact (ended only)
  double peak_overlap = 0;           // m, largest overlap during the contact (ended only)
  double effective_radius = 0;       // m, R* of the contact
  Vec<D> position = Vec<D>::Zero();  // contact point at the first step in contact
};

// Per-slot tracking state, carried across neighbour-list rebuilds like a history.
template <int D>
struct ContactTrack {
  // A contact already going on when tracking began (a diagnostic attached to a
  // bed at rest): neither its beginning nor its end is an event, as neither its
  // impact nor its whole peak was seen.
  static constexpr double ongoing = -2;
  double begin_time = -1;  // < 0: not in contact (or `ongoing`)
  double impact_velocity = 0;
  double peak_normal_force = 0;
  double peak_overlap = 0;
  Vec<D> position = Vec<D>::Zero();
};

template <int D>
struct ContactLog {
  using V = Vec<D>;
  // One entry per slot; `active` is 0 for candidate pairs not touching this step.
  std::vector<std::uint8_t> active;
  std::vector<std::int32_t> a;  // particle index (storage order of this step)
  std::vector<std::int32_t> b;  // particle index, or -1 - wall for a wall contact
  std::vector<double> overlap;  // m (negative for adhesive contacts in tension past zero overlap)
  std::vector<double> normal_force;  // N, positive = repulsive
  std::vector<double> overlap_rate;  // m/s, d(overlap)/dt (positive: approaching)
  std::vector<V> normal;             // unit, from b (or the wall) to a
  std::vector<V> tangential;         // N, tangential force on a
  std::vector<V> point;              // contact point, m
  bool filled = false;               // the arrays describe this step
  // Each model's first slot at the step logged (slots before the next list
  // rebuild, which may come before the next log: a failure it reports).
  std::vector<std::pair<std::size_t, const char*>> model_at;
  // The active slots of this step in increasing order: an observer loops over
  // these instead of every candidate slot (~10x more in the Mechanofusion base
  // case), and sums in the same order.
  std::vector<std::uint32_t> slots;

  // Events of this step (only while tracking).
  std::vector<ContactEvent<D>> began, ended;

  std::size_t size() const { return active.size(); }
  // Slot s touches this step (a kernel on a logged step).
  void record(std::size_t s, std::int32_t a_index, std::int32_t b_index, double overlap_m,
              double normal_n, double rate, const V& unit_normal, const V& tangential_n,
              const V& contact_point) {
    active[s] = 1;
    a[s] = a_index;
    b[s] = b_index;
    overlap[s] = overlap_m;
    normal_force[s] = normal_n;
    overlap_rate[s] = rate;
    normal[s] = unit_normal;
    tangential[s] = tangential_n;
    point[s] = contact_point;
  }
  static bool is_wall(std::int32_t b) { return b < 0; }
  static int wall_of(std::int32_t b) { return -1 - b; }

  void resize(std::size_t n) {
    active.assign(n, 0);
    a.resize(n);
    b.resize(n);
    overlap.resize(n);
    normal_force.resize(n);
    overlap_rate.resize(n);
    normal.resize(n);
    tangential.resize(n);
    point.resize(n);
  }
};

}  // namespace granule
