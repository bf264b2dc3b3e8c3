// Moving particles between ranks on Open MPI: migration (a particle goes to the
// rank whose box now holds it, with its contact histories as an opaque payload)
// and the ghost exchange (copies of the particles within reach of another
// rank's box, periodic images included). Both are one all-to-all of counts and
// one of bytes, so a rank talks to every rank; what arrives is put in a
// canonical order (by id, then by image) so that the receiving rank's state
// does not depend on the order ranks answered in, nor on how many there are.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "parallel/decomposition.hpp"
#include "parallel/ghosts.hpp"

#ifdef GRANULE_HAVE_MPI
#include <mpi.h>
#endif

namespace granule::parallel {

template <int D>
struct ParticleRecord {
  std::int64_t id = 0;
  Vec<D> position = Vec<D>::Zero();    // m
  Vec<D> velocity = Vec<D>::Zero();    // m/s
  Spin<D> spin = Dim<D>::zero_spin();  // rad/s
  double radius = 0;                   // m
  double mass = 0;                     // kg
  double inv_mass = 0;                 // 1/kg (0: fixed), carried bit for bit
  double inv_inertia = 0;              // 1/(kg m^2)
  std::int32_t material = 0;
  std::uint8_t fixed = 0;  // the particle's `fixed` flags (bit 0: fixed, infinite mass)
  std::int32_t image = 0;  // a ghost's index into periodic_shifts (0: not an image)
  std::string payload;     // the histories that travel with a migrating particle

  bool operator==(const ParticleRecord& o) const {
    return id == o.id && position == o.position && velocity == o.velocity && spin == o.spin &&
           radius == o.radius && mass == o.mass && inv_mass == o.inv_mass &&
           inv_inertia == o.inv_inertia && material == o.material && fixed == o.fixed &&
           image == o.image && payload == o.payload;
  }
};

// Appends a record to / reads one from a byte buffer (bit-exact doubles).
template <int D>
void pack(const ParticleRecord<D>& r, std::string& bytes);
template <int D>
ParticleRecord<D> unpack(const std::string& bytes, std::size_t& offset);

#ifdef GRANULE_HAVE_MPI
// Sends buffer k to rank k; returns what each rank sent here, in rank order.
std::vector<std::string> all_to_all(const std::vector<std::string>& to_rank, MPI_Comm comm);

// Hands every record whose position the decomposition gives to another rank
// over to it and takes the records that arrive; `owned` ends sorted by id.
// Returns the number of records that left this rank.
template <int D>
std::size_t migrate(const Decomposition<D>& d, std::vector<ParticleRecord<D>>& owned,
                    MPI_Comm comm);

// A ghost's state as the step's forward carries it, as doubles (bit for bit
// between ranks of one machine type): position, velocity, spin.
template <int D>
constexpr std::size_t ghost_state_doubles = 2 * D + Dim<D>::spin_components;
// Writes r's state at `out`, its position shifted to the ghost's periodic
// image; returns the place after it.
template <int D>
double* put_ghost_state(double* out, const ParticleRecord<D>& r, const Vec<D>& shift) {
  const Vec<D> x = r.position + shift;
  for (int a = 0; a < D; ++a) *out++ = x[a];
  for (int a = 0; a < D; ++a) *out++ = r.velocity[a];
  if constexpr (D == 2)
    *out++ = r.spin;
  else
    for (int a = 0; a < 3; ++a) *out++ = r.spin[a];
  return out;
}
// Reads a state put_ghost_state wrote into `ghost`; returns the place after it.
template <int D>
const double* take_ghost_state(const double* in, ParticleRecord<D>& ghost) {
  for (int a = 0; a < D; ++a) ghost.position[a] = *in++;
  for (int a = 0; a < D; ++a) ghost.velocity[a] = *in++;
  if constexpr (D == 2)
    ghost.spin = *in++;
  else
    for (int a = 0; a < 3; ++a) ghost.spin[a] = *in++;
  return in;
}

// Who sends which owned particle (and which image of it) to whom, fixed from
// one list rebuild to the next, and where each arriving ghost goes in this
// rank's canonical ghost order.
struct GhostPlan {
  struct Send {
    std::size_t index;   // into the owned records
    std::int32_t image;  // into periodic_shifts
  };
  std::vector<std::vector<Send>> send;  // per destination rank, in a fixed order
  // place[k][n]: where the n-th ghost from rank k lands in the sorted ghosts.
  std::vector<std::vector<std::size_t>> place;
  // The forward's buffers, kept from step to step so that a step allocates nothing.
  struct Buffers {
    std::vector<double> out, in;
    std::vector<int> send_counts, send_at, recv_counts, recv_at;
    std::vector<MPI_Request> requests;
  };
  mutable Buffers buffers;
};

// How periodic images reach a rank. `shifted`: each image is a ghost of its
// own, at its shifted position (its own rank's particles too), for a receiver
// that knows nothing of the period. `wrapped`: the receiver wraps separations
// along the periodic axes itself (a periodic Simulation: minimum images in its
// cell grid and pair loop), so it gets each particle it needs once, at the
// owner's position, and never one of its own.
enum class Images { shifted, wrapped };

// At a list rebuild: the ghosts this rank needs (copies, without payload, of
// every other rank's particles within `reach` of this rank's box, and the
// periodic images as `images` says), sorted by (id, image); and the plan that
// refreshes them each step.
template <int D>
std::vector<ParticleRecord<D>> exchange_ghosts(const Decomposition<D>& d, double reach,
                                               const std::vector<ParticleRecord<D>>& owned,
                                               MPI_Comm comm, GhostPlan& plan,
                                               Images images = Images::shifted);

// Each step between rebuilds: the ghosts' positions, velocities and spins from
// their owners (the same particles, the same places), nothing else. With
// `maxima` (`count` values), each rank's values also go to every rank in the
// same exchange and come back as their maxima over the ranks (as an
// MPI_Allreduce with MPI_MAX would give them, one collective fewer).
template <int D>
void forward_ghosts(const Decomposition<D>& d, const GhostPlan& plan,
                    const std::vector<ParticleRecord<D>>& owned,
                    std::vector<ParticleRecord<D>>& ghosts, MPI_Comm comm, double* maxima = nullptr,
                    int count = 0);
#endif

}  // namespace granule::parallel
