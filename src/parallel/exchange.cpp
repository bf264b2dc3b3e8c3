#include "parallel/exchange.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "core/bytes.hpp"
#ifdef GRANULE_HAVE_MPI
#include "parallel/gathering.hpp"
#endif

namespace granule::parallel {

namespace {

template <typename T>
void put(std::string& bytes, const T& value) {
  granule::bytes::put(bytes, value);
}

template <typename T>
T take(const std::string& bytes, std::size_t& offset) {
  return granule::bytes::take<T>(bytes, offset, "parallel: a particle record");
}

template <int D>
void put_vec(std::string& bytes, const Vec<D>& v) {
  for (int a = 0; a < D; ++a) put(bytes, v[a]);
}

template <int D>
Vec<D> take_vec(const std::string& bytes, std::size_t& offset) {
  Vec<D> v;
  for (int a = 0; a < D; ++a) v[a] = take<double>(bytes, offset);
  return v;
}

template <int D>
void put_spin(std::string& bytes, const Spin<D>& w) {
  if constexpr (D == 2)
    put(bytes, w);
  else
    put_vec<3>(bytes, w);
}

template <int D>
Spin<D> take_spin(const std::string& bytes, std::size_t& offset) {
  if constexpr (D == 2)
    return take<double>(bytes, offset);
  else
    return take_vec<3>(bytes, offset);
}

}  // namespace

template <int D>
void pack(const ParticleRecord<D>& r, std::string& bytes) {
  put(bytes, r.id);
  put_vec<D>(bytes, r.position);
  put_vec<D>(bytes, r.velocity);
  put_spin<D>(bytes, r.spin);
  put(bytes, r.radius);
  put(bytes, r.mass);
  put(bytes, r.inv_mass);
  put(bytes, r.inv_inertia);
  put(bytes, r.material);
  put(bytes, r.fixed);
  put(bytes, r.image);
  put(bytes, static_cast<std::uint64_t>(r.payload.size()));
  bytes += r.payload;
}

template <int D>
ParticleRecord<D> unpack(const std::string& bytes, std::size_t& offset) {
  ParticleRecord<D> r;
  r.id = take<std::int64_t>(bytes, offset);
  r.position = take_vec<D>(bytes, offset);
  r.velocity = take_vec<D>(bytes, offset);
  r.spin = take_spin<D>(bytes, offset);
  r.radius = take<double>(bytes, offset);
  r.mass = take<double>(bytes, offset);
  r.inv_mass = take<double>(bytes, offset);
  r.inv_inertia = take<double>(bytes, offset);
  r.material = take<std::int32_t>(bytes, offset);
  r.fixed = take<std::uint8_t>(bytes, offset);
  r.image = take<std::int32_t>(bytes, offset);
  const auto length = take<std::uint64_t>(bytes, offset);
  if (offset + length > bytes.size())
    throw std::runtime_error("parallel: a particle's payload is cut short");
  r.payload.assign(bytes, offset, length);
  offset += length;
  return r;
}

#ifdef GRANULE_HAVE_MPI

namespace {

int count_of(std::size_t n) {
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::runtime_error(
        fmt::format("parallel: {} bytes to send at once is more than MPI counts in an int", n));
  return static_cast<int>(n);
}

}  // namespace

std::vector<std::string> all_to_all(const std::vector<std::string>& to_rank, MPI_Comm comm) {
  int size = 0;
  MPI_Comm_size(comm, &size);
  if (static_cast<int>(to_rank.size()) != size)
    throw std::invalid_argument("parallel: one buffer per rank expected");
  std::vector<int> send_counts(size), recv_counts(size), send_at(size), recv_at(size);
  std::size_t total = 0;
  for (int k = 0; k < size; ++k) {
    send_counts[k] = count_of(to_rank[k].size());
    send_at[k] = count_of(total);
    total += to_rank[k].size();
  }
  check_mpi(MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, comm),
            "MPI_Alltoall");
  std::string send;
  send.reserve(total);
  for (const auto& b : to_rank) send += b;
  std::size_t incoming = 0;
  for (int k = 0; k < size; ++k) {
    recv_at[k] = count_of(incoming);
    incoming += static_cast<std::size_t>(recv_counts[k]);
  }
  std::string recv(incoming, '\0');
  check_mpi(MPI_Alltoallv(send.data(), send_counts.data(), send_at.data(), MPI_CHAR, recv.data(),
                          recv_counts.data(), recv_at.data(), MPI_CHAR, comm),
            "MPI_Alltoallv");
  std::vector<std::string> out(size);
  for (int k = 0; k < size; ++k) out[k] = recv.substr(recv_at[k], recv_counts[k]);
  return out;
}

template <int D>
std::size_t migrate(const Decomposition<D>& d, std::vector<ParticleRecord<D>>& owned,
                    MPI_Comm comm) {
  int rank = 0, size = 0;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  if (size != d.ranks())
    throw std::invalid_argument(
        fmt::format("parallel: a decomposition into {} boxes on {} ranks", d.ranks(), size));
  std::vector<std::string> out(static_cast<std::size_t>(size));
  std::vector<ParticleRecord<D>> kept;
  kept.reserve(owned.size());
  std::size_t left = 0;
  for (auto& r : owned) {
    r.position = wrap(d, r.position);
    const int to = d.owner(r.position);
    if (to == rank) {
      kept.push_back(std::move(r));
    } else {
      pack(r, out[static_cast<std::size_t>(to)]);
      ++left;
    }
  }
  const auto in = all_to_all(out, comm);
  const std::size_t stayed = kept.size();
  for (const auto& bytes : in)
    for (std::size_t at = 0; at < bytes.size();) kept.push_back(unpack<D>(bytes, at));
  // In id order. Those that stayed keep the order they had, which is id order
  // after the first migration: then only the arrivals are sorted and merged in
  // (a record moves a string; most rebuilds bring few arrivals or none).
  const auto by_id = [](const auto& a, const auto& b) { return a.id < b.id; };
  const auto arrivals = kept.begin() + static_cast<std::ptrdiff_t>(stayed);
  if (std::is_sorted(kept.begin(), arrivals, by_id)) {
    std::sort(arrivals, kept.end(), by_id);
    std::inplace_merge(kept.begin(), arrivals, kept.end(), by_id);
  } else {
    std::sort(kept.begin(), kept.end(), by_id);
  }
  owned = std::move(kept);
  return left;
}

template <int D>
std::vector<ParticleRecord<D>> exchange_ghosts(const Decomposition<D>& d, double reach,
                                               const std::vector<ParticleRecord<D>>& owned,
                                               MPI_Comm comm, GhostPlan& plan, Images images) {
  int rank = 0, size = 0;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  check_reach(d, reach);
  const auto shifts = periodic_shifts(d);
  plan.send.assign(static_cast<std::size_t>(size), {});
  std::vector<GhostTarget<D>> targets;
  for (std::size_t i = 0; i < owned.size(); ++i) {
    targets.clear();
    ghost_targets(d, shifts, owned[i].position, reach, rank, targets);
    if (images == Images::wrapped) {
      // Each other rank once, unshifted (targets come by shift, then rank).
      for (const auto& t : targets) {
        auto& to = plan.send[static_cast<std::size_t>(t.rank)];
        if (t.rank != rank && (to.empty() || to.back().index != i)) to.push_back({i, 0});
      }
      continue;
    }
    for (const auto& t : targets) {
      std::int32_t image = 0;
      while (shifts[static_cast<std::size_t>(image)] != t.shift) ++image;
      plan.send[static_cast<std::size_t>(t.rank)].push_back({i, image});
    }
  }
  std::vector<std::string> out(static_cast<std::size_t>(size));
  for (int k = 0; k < size; ++k)
    for (const auto& s : plan.send[static_cast<std::size_t>(k)]) {
      ParticleRecord<D> g = owned[s.index];
      g.position += shifts[static_cast<std::size_t>(s.image)];
      g.image = s.image;
      g.payload.clear();
      pack(g, out[static_cast<std::size_t>(k)]);
    }
  const auto in = all_to_all(out, comm);
  struct Arrival {
    ParticleRecord<D> record;
    int from;
    std::size_t n;
  };
  std::vector<Arrival> arrivals;
  for (int k = 0; k < size; ++k) {
    std::size_t n = 0;
    for (std::size_t at = 0; at < in[static_cast<std::size_t>(k)].size(); ++n)
      arrivals.push_back({unpack<D>(in[static_cast<std::size_t>(k)], at), k, n});
  }
  std::sort(arrivals.begin(), arrivals.end(), [](const Arrival& a, const Arrival& b) {
    if (a.record.id != b.record.id) return a.record.id < b.record.id;
    return a.record.image < b.record.image;
  });
  plan.place.assign(static_cast<std::size_t>(size), {});
  for (int k = 0; k < size; ++k)
    plan.place[static_cast<std::size_t>(k)].resize(std::count_if(
        arrivals.begin(), arrivals.end(), [k](const Arrival& a) { return a.from == k; }));
  std::vector<ParticleRecord<D>> ghosts;
  ghosts.reserve(arrivals.size());
  for (std::size_t g = 0; g < arrivals.size(); ++g) {
    plan.place[static_cast<std::size_t>(arrivals[g].from)][arrivals[g].n] = g;
    ghosts.push_back(std::move(arrivals[g].record));
  }
  return ghosts;
}

template <int D>
void forward_ghosts(const Decomposition<D>& d, const GhostPlan& plan,
                    const std::vector<ParticleRecord<D>>& owned,
                    std::vector<ParticleRecord<D>>& ghosts, MPI_Comm comm, double* maxima,
                    int count) {
  int size = 0;
  MPI_Comm_size(comm, &size);
  const std::size_t extra = maxima ? static_cast<std::size_t>(count) : 0;  // first, to each rank
  const auto shifts = periodic_shifts(d);
  // The plan fixes who sends how many to whom until the next rebuild, so one
  // MPI_Alltoallv of doubles moves the states (doubles travel bit for bit
  // between ranks of one machine type): position, velocity, spin per ghost.
  constexpr std::size_t per = ghost_state_doubles<D>;
  GhostPlan::Buffers& b = plan.buffers;
  for (auto* v : {&b.send_counts, &b.send_at, &b.recv_counts, &b.recv_at})
    v->resize(static_cast<std::size_t>(size));
  std::vector<int>&send_counts = b.send_counts, &send_at = b.send_at;
  std::vector<int>&recv_counts = b.recv_counts, &recv_at = b.recv_at;
  std::size_t sending = 0, receiving = 0;
  for (int k = 0; k < size; ++k) {
    const std::size_t u = static_cast<std::size_t>(k);
    send_at[u] = count_of(sending), recv_at[u] = count_of(receiving);
    send_counts[u] = count_of(extra + plan.send[u].size() * per);
    recv_counts[u] = count_of(extra + plan.place[u].size() * per);
    sending += extra + plan.send[u].size() * per, receiving += extra + plan.place[u].size() * per;
  }
  b.out.resize(sending), b.in.resize(receiving);
  std::vector<double>&out = b.out, &in = b.in;
  double* o = out.data();
  for (int k = 0; k < size; ++k) {
    for (std::size_t e = 0; e < extra; ++e) *o++ = maxima[e];
    for (const auto& s : plan.send[static_cast<std::size_t>(k)])
      o = put_ghost_state(o, owned[s.index], shifts[static_cast<std::size_t>(s.image)]);
  }
  // Point to point, only with the ranks there is something for (every rank
  // when the maxima travel too), and this rank's own part (periodic images)
  // copied: an MPI_Alltoallv also sends to itself and to every rank, and
  // costs a sizeable part of a small scene's step.
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  constexpr int tag = 0x6f72;  // used by nothing else on this communicator
  std::vector<MPI_Request>& requests = b.requests;
  requests.clear();
  // The receives posted first, then the sends.
  for (const bool sending : {false, true})
    for (int k = 0; k < size; ++k) {
      const std::size_t u = static_cast<std::size_t>(k);
      const int values = sending ? send_counts[u] : recv_counts[u];
      if (k == rank || values == 0) continue;
      requests.emplace_back();
      if (sending)
        check_mpi(
            MPI_Isend(out.data() + send_at[u], values, MPI_DOUBLE, k, tag, comm, &requests.back()),
            "MPI_Isend");
      else
        check_mpi(
            MPI_Irecv(in.data() + recv_at[u], values, MPI_DOUBLE, k, tag, comm, &requests.back()),
            "MPI_Irecv");
    }
  const std::size_t self = static_cast<std::size_t>(rank);
  if (send_counts[self] != recv_counts[self])
    throw std::runtime_error(
        fmt::format("parallel: ghost forward: rank {} sends itself {} values and expects {}", rank,
                    send_counts[self], recv_counts[self]));
  std::copy_n(out.data() + send_at[self], send_counts[self], in.data() + recv_at[self]);
  check_mpi(MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE),
            "MPI_Waitall");
  const double* q = in.data();
  for (int k = 0; k < size; ++k) {
    for (std::size_t e = 0; e < extra; ++e, ++q)  // rank k's values (this rank's own among them)
      maxima[e] = std::max(maxima[e], *q);
    for (const std::size_t g : plan.place[static_cast<std::size_t>(k)])
      q = take_ghost_state(q, ghosts[g]);
  }
}

template std::size_t migrate<2>(const Decomposition<2>&, std::vector<ParticleRecord<2>>&, MPI_Comm);
template std::size_t migrate<3>(const Decomposition<3>&, std::vector<ParticleRecord<3>>&, MPI_Comm);
template std::vector<ParticleRecord<2>> exchange_ghosts<2>(const Decomposition<2>&, double,
                                                           const std::vector<ParticleRecord<2>>&,
                                                           MPI_Comm, GhostPlan&, Images);
template std::vector<ParticleRecord<3>> exchange_ghosts<3>(const Decomposition<3>&, double,
                                                           const std::vector<ParticleRecord<3>>&,
                                                           MPI_Comm, GhostPlan&, Images);
template void forward_ghosts<2>(const Decomposition<2>&, const GhostPlan&,
                                const std::vector<ParticleRecord<2>>&,
                                std::vector<ParticleRecord<2>>&, MPI_Comm, double*, int);
template void forward_ghosts<3>(const Decomposition<3>&, const GhostPlan&,
                                const std::vector<ParticleRecord<3>>&,
                                std::vector<ParticleRecord<3>>&, MPI_Comm, double*, int);

#endif  // GRANULE_HAVE_MPI

template void pack<2>(const ParticleRecord<2>&, std::string&);
template void pack<3>(const ParticleRecord<3>&, std::string&);
template ParticleRecord<2> unpack<2>(const std::string&, std::size_t&);
template ParticleRecord<3> unpack<3>(const std::string&, std::size_t&);

}  // namespace granule::parallel
