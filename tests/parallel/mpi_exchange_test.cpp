// The exchange of particles between MPI ranks (src/parallel/exchange.cpp), run
// under mpirun on 1-4 ranks. Every rank makes the same particles from one seed,
// keeps a scattered share (as if a previous decomposition had placed them), and
// then:
//   - migration leaves every particle on exactly one rank, the owner the
//     decomposition names, with its payload intact, sorted by id;
//   - the ghosts a rank receives are exactly those a brute-force test over
//     every particle and periodic image finds within reach of its box, at the
//     shifted positions, bit for bit, in (id, image) order;
//   - after the particles move a little, forward_ghosts refreshes every ghost
//     to its owner's new state (plus shift), bit for bit, and brings back
//     the maxima over the ranks of the values each rank gave it;
//   - a second migration after the move again keeps each particle once.
// Prints "mpi_exchange ok on N ranks" from rank 0 when every check passed on
// every rank; exits 1 otherwise.
#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "parallel/decomposition.hpp"
#include "parallel/exchange.hpp"

using namespace granule;
using namespace granule::parallel;

namespace {

int failures = 0;
int rank = 0, size = 1;

void expect(bool ok, const std::string& what) {
  if (ok) return;
  ++failures;
  std::fprintf(stderr, "rank %d: FAILED %s\n", rank, what.c_str());
}

template <int D>
std::vector<ParticleRecord<D>> make_particles(std::size_t n, const Box<D>& domain) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<ParticleRecord<D>> all;
  for (std::size_t k = 0; k < n; ++k) {
    ParticleRecord<D> r;
    r.id = static_cast<std::int64_t>(5 * k + 3);
    for (int a = 0; a < D; ++a) {
      r.position[a] = domain.lo[a] + u(rng) * (domain.hi[a] - domain.lo[a]);
      r.velocity[a] = u(rng) - 0.5;
    }
    if constexpr (D == 2)
      r.spin = u(rng);
    else
      r.spin = Vec<3>(u(rng), u(rng), u(rng));
    r.radius = 2e-4 * (1 + u(rng));
    r.mass = 1e-9 * u(rng);
    r.material = static_cast<std::int32_t>(k % 3);
    r.payload = "history of " + std::to_string(r.id) + std::string(k % 5, '\x01');
    all.push_back(r);
  }
  return all;
}

template <int D>
void run(const char* name, std::array<bool, D> periodic) {
  Box<D> domain;
  domain.lo.setConstant(0);
  domain.hi.setConstant(0.02);
  const auto all = make_particles<D>(1500, domain);
  std::vector<Vec<D>> x;
  std::vector<std::int64_t> ids;
  for (const auto& r : all) x.push_back(r.position), ids.push_back(r.id);
  const auto d = bisect<D>(domain, periodic, size, x, {}, ids);
  const double reach = 1.5e-3;

  // A scattered start: particle k on rank k % size, whatever its position.
  std::vector<ParticleRecord<D>> owned;
  for (std::size_t k = 0; k < all.size(); ++k)
    if (static_cast<int>(k % static_cast<std::size_t>(size)) == rank) owned.push_back(all[k]);
  // Out of id order: the first migration must sort whatever it is given (the
  // next one below merges its arrivals into the order kept from this one).
  std::reverse(owned.begin(), owned.end());
  migrate(d, owned, MPI_COMM_WORLD);

  // Each particle once, where the decomposition says, payload intact, sorted.
  long long mine = static_cast<long long>(owned.size()), total = 0;
  MPI_Allreduce(&mine, &total, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  expect(total == static_cast<long long>(all.size()),
         std::string(name) + ": particle count after migration");
  std::map<std::int64_t, const ParticleRecord<D>*> by_id;
  for (const auto& r : all) by_id[r.id] = &r;
  for (std::size_t k = 0; k < owned.size(); ++k) {
    expect(d.owner(owned[k].position) == rank,
           std::string(name) + ": a particle on the wrong rank");
    expect(*by_id[owned[k].id] == owned[k], std::string(name) + ": a particle changed on its way");
    if (k) expect(owned[k - 1].id < owned[k].id, std::string(name) + ": owned not sorted by id");
  }

  // Ghosts against brute force over every particle and image.
  GhostPlan plan;
  auto ghosts = exchange_ghosts(d, reach, owned, MPI_COMM_WORLD, plan);
  const auto shifts = periodic_shifts(d);
  const Box<D>& box = d.boxes[static_cast<std::size_t>(rank)];
  std::vector<std::tuple<std::int64_t, int, ParticleRecord<D>>> want;
  for (const auto& r : all) {
    const int owner = d.owner(r.position);
    for (std::size_t s = 0; s < shifts.size(); ++s) {
      if (owner == rank && s == 0) continue;
      if (box.distance(r.position + shifts[s]) < reach) {
        ParticleRecord<D> g = r;
        g.position += shifts[s];
        g.image = static_cast<std::int32_t>(s);
        g.payload.clear();
        want.emplace_back(r.id, static_cast<int>(s), g);
      }
    }
  }
  std::sort(want.begin(), want.end(), [](const auto& a, const auto& b) {
    return std::tie(std::get<0>(a), std::get<1>(a)) < std::tie(std::get<0>(b), std::get<1>(b));
  });
  expect(ghosts.size() == want.size(), std::string(name) + ": ghost count " +
                                           std::to_string(ghosts.size()) + " against " +
                                           std::to_string(want.size()));
  for (std::size_t k = 0; k < std::min(ghosts.size(), want.size()); ++k)
    expect(ghosts[k] == std::get<2>(want[k]),
           std::string(name) + ": ghost " + std::to_string(k) + " differs");

  // Move everything a little (less than the skin would allow) and forward.
  for (auto& r : owned) {
    r.position += r.velocity * 1e-4;
    r.velocity *= 0.5;
    r.spin *= -1.0;
  }
  // With two values whose maxima over the ranks come back from the same
  // exchange: the highest rank, and the largest of -rank (0, rank 0's).
  int ranks = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  double maxima[2] = {static_cast<double>(rank), -static_cast<double>(rank)};
  forward_ghosts(d, plan, owned, ghosts, MPI_COMM_WORLD, maxima, 2);
  expect(maxima[0] == ranks - 1 && maxima[1] == 0,
         std::string(name) + ": the values' maxima over the ranks, from the forward");
  for (std::size_t k = 0; k < std::min(ghosts.size(), want.size()); ++k) {
    const auto& was = *by_id[ghosts[k].id];
    const Vec<D> expected =
        was.position + was.velocity * 1e-4 + shifts[static_cast<std::size_t>(ghosts[k].image)];
    expect(ghosts[k].position == expected, std::string(name) + ": a forwarded ghost's position");
    expect(ghosts[k].velocity == was.velocity * 0.5,
           std::string(name) + ": a forwarded ghost's velocity");
  }

  // Drift across boxes and periodic faces, then migrate again.
  for (auto& r : owned) r.position += r.velocity * 2e-3;
  migrate(d, owned, MPI_COMM_WORLD);
  mine = static_cast<long long>(owned.size());
  MPI_Allreduce(&mine, &total, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  expect(total == static_cast<long long>(all.size()),
         std::string(name) + ": particle count after the drift");
  for (const auto& r : owned) {
    expect(d.owner(r.position) == rank,
           std::string(name) + ": after the drift, a particle on the wrong rank");
    expect(r.payload == by_id[r.id]->payload, std::string(name) + ": a payload lost in the drift");
  }
  for (std::size_t k = 1; k < owned.size(); ++k)
    expect(owned[k - 1].id < owned[k].id,
           std::string(name) + ": after the drift, owned not sorted by id");
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  try {
    run<2>("2D open", {false, false});
    run<2>("2D periodic x", {true, false});
    run<3>("3D open", {false, false, false});
    run<3>("3D periodic x, y", {true, true, false});
  } catch (const std::exception& e) {
    ++failures;
    std::fprintf(stderr, "rank %d: %s\n", rank, e.what());
  }
  int all_failures = 0;
  MPI_Allreduce(&failures, &all_failures, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  if (rank == 0 && all_failures == 0) std::printf("mpi_exchange ok on %d ranks\n", size);
  MPI_Finalize();
  return all_failures == 0 ? 0 : 1;
}
