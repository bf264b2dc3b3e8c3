// The contacts the kernels work on, as flat arrays, one bucket per contact
// model: particle pairs, and particles against walls. A bucket holds its
// candidates (who, which law, the history) and the lists of this step's
// contacts the kernel wrote; how the kernel schedules and prunes its work is
// the kernel's own state (pair_kernel.hpp).
#pragma once

#include <cstdint>
#include <tuple>
#include <vector>

#include "core/hot_array.hpp"
#include "core/types.hpp"
#include "hooks/contact_log.hpp"

namespace granule {

// A list filled anew every step: its storage only grows, so filling it costs a
// store per entry and no allocation or initialisation. With more than one
// thread each listed wall contact also leaves its results at its position in
// the list, for the reactions on the walls to be summed afterwards in slot
// order (WallKernel::scatter_reactions).
template <int D>
struct StepList {
  HotArray<std::uint32_t> entries;
  std::size_t count = 0;
  std::vector<std::uint32_t> b;  // wall contacts: the wall
  std::vector<Vec<D>> force;     // on the particle (on the wall: minus it)
  std::vector<double> axial;     // torque on the wall about its axis
  void reserve_outputs(std::size_t most) {
    if (force.size() < most) b.resize(most), force.resize(most), axial.resize(most);
  }
  void start(std::size_t most) {
    if (entries.size() < most) entries.resize(most);
    count = 0;
  }
  void push(std::uint32_t e) { entries[count++] = e; }
  const std::uint32_t* begin() const { return entries.data(); }
  const std::uint32_t* end() const { return entries.data() + count; }
};

// Contacts between particles handled by model M. A pair is oriented so that
// id(i) < id(j): the history (force on i) keeps its meaning when particles are
// re-sorted or lists rebuilt. Entry k is slot `offset + k` of the step's
// per-slot flags and of the contact log.
template <int D, typename M>
struct PairBucket {
  static constexpr bool is_pair = true;
  using History = typename M::template History<D>;
  // Streamed by the contact loop every step: in huge pages (hot_array.hpp).
  HotArray<std::uint32_t> i, j, slot;
  HotArray<History> history;
  std::vector<std::int64_t> id_i, id_j;  // cold: for carrying histories across rebuilds
  // The parameter slot every candidate shares (one law for the whole bucket),
  // -1 when they differ, -2 until the kernel looks (set again when the slots change).
  std::int64_t law = -2;
  std::vector<ContactTrack<D>> track;  // only while an observer tracks contact events
  std::size_t offset = 0;
  // This step's contacts, per thread: entry k << 1 | touching, in increasing k
  // within a list and from list to list (each thread takes a contiguous range).
  std::vector<StepList<D>> touched;
  std::size_t size() const { return i.size(); }
};

// A mesh wall's contact found for this step (kernel/mesh_contacts.hpp): what
// Wall::contact gives for an analytic wall.
template <int D>
struct WallTouch {
  Vec<D> normal = Vec<D>::Zero();
  Vec<D> surface_velocity = Vec<D>::Zero();
  Vec<D> lever = Vec<D>::Zero();
  double overlap = -1e300;      // none: the part is free
  double effective_radius = 0;  // R* (a mesh's flat faces: the particle's radius)
};

// Contacts between particles and walls handled by model M, particle-major
// (each particle's wall contacts lie together, in memory order). A mesh wall
// lists each particle near it several times, its parts 0, 1, ... in a row:
// one per contact the particle can have with the mesh at once.
template <int D, typename M>
struct WallBucket {
  static constexpr bool is_pair = false;
  using History = typename M::template History<D>;
  std::vector<std::uint32_t> particle, wall, slot;
  std::vector<History> history;
  std::vector<std::int64_t> id;     // cold
  std::vector<std::uint8_t> part;   // 0 for analytic walls
  std::vector<Vec<D>> part_normal;  // a mesh part's last normal (zero: free)
  std::vector<WallTouch<D>> touch;  // a mesh part's contact this step
  std::vector<ContactTrack<D>> track;
  std::size_t offset = 0;
  std::vector<StepList<D>> touched;  // as in PairBucket
  std::size_t size() const { return particle.size(); }
};

}  // namespace granule
