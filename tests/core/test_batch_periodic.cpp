// The pair loop's batched path against its per-contact path across a periodic
// boundary: the batch wraps each lane's separation itself (the gather in
// PairKernel::run), so a batch that read the unwrapped one would put the contacts
// that straddle the boundary a whole period apart. A lattice of overlapping
// particles fills the period along x, so the first and last of each row touch
// through the boundary from the first step; walls close the other axes.
#include <algorithm>
#include <catch2/catch.hpp>
#include <string>

#include "batch_compare.hpp"
#include "box_walls.hpp"
#include "core/random.hpp"
#include "engine/simulation.hpp"

using namespace granule;

namespace {
struct LatticeRun {
  SimulationBase::FlatState state;
  GlobalStats stats;
};

// A periodic axis is a 3D feature (2D scenes refuse one): the lattice is
// per_row x rows x rows sites, periodic along x.
constexpr int per_row = 8;        // along the periodic axis
constexpr int rows = 4;           // across each walled axis
constexpr double spacing = 1e-3;  // m, between lattice sites
constexpr double period = per_row * spacing;

LatticeRun run_periodic_lattice(const std::string& model, bool batched, std::int64_t steps) {
  Simulation<3> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.set_batched_contacts(batched);
  sim.add_material({"p", 2500, 5e6, 0.3, 0});  // Young's modulus: only the Hertz laws read it
  sim.add_material({"w", 0, 2e8, 0.3, 0});
  ParamValues law{{"friction", 0.4}};
  if (model != "thornton_elastic") law["restitution"] = 0.6;
  if (model == "linear") law["k_normal"] = 2e3;
  if (model == "walton_braun") law["k_load"] = 2e3, law["slip_exponent"] = 1.0;
  sim.set_contact("p", "p", model, law);
  sim.set_contact("p", "w", model, law);
  sim.set_periodic(0, 0, period);
  test::add_walls_across(sim, 1, rows * spacing, 1);
  // Radii of 0.505-0.52 spacings: every lattice neighbour overlaps, through
  // the boundary too; random velocities make the contacts slide and turn.
  Random rng(17);
  for (int a = 0; a < per_row; ++a)
    for (int b = 0; b < rows; ++b)
      for (int c = 0; c < rows; ++c) {
        ParticleSpec s;
        s.position = {(a + 0.5) * spacing, (b + 0.5) * spacing, (c + 0.5) * spacing};
        s.radius = spacing * rng.uniform(0.505, 0.52);
        s.material = 0;
        for (int d = 0; d < 3; ++d) s.velocity[d] = rng.uniform(-0.05, 0.05);
        s.spin[2] = rng.uniform(-20, 20);
        s.spin[0] = rng.uniform(-20, 20), s.spin[1] = rng.uniform(-20, 20);
        sim.add_particle(s);
      }
  sim.advance(steps);
  return {sim.flat_state(), sim.stats()};
}

// How far the particles spread along x, unwrapped: a period less a spacing
// while the rows still straddle the boundary, so the pairs through it are a
// whole period apart in storage.
double spread_along_x(const SimulationBase::FlatState& state) {
  double lo = period, hi = 0;
  for (std::size_t k = 0; k < state.id.size(); ++k) {
    lo = std::min(lo, state.position[3 * k]);
    hi = std::max(hi, state.position[3 * k]);
  }
  return hi - lo;
}

void check_periodic(const std::string& model, std::int64_t steps) {
  const LatticeRun batched = run_periodic_lattice(model, true, steps),
                   one_by_one = run_periodic_lattice(model, false, steps);
  // Lattice neighbours along x (a ring through the boundary) and across each
  // walled axis; diagonal ones are 1.41 spacings apart.
  const std::int64_t lattice_pairs = per_row * rows * rows + 2 * per_row * (rows - 1) * rows;
  INFO(model << ", " << steps << " steps: contacts " << batched.stats.contacts_particle
             << " (batched " << batched.stats.contacts_batched << "), per contact "
             << one_by_one.stats.contacts_particle << "; lattice pairs " << lattice_pairs);
  REQUIRE(batched.stats.contacts_batched == batched.stats.contacts_particle);
  REQUIRE(one_by_one.stats.contacts_batched == 0);
  REQUIRE(batched.stats.contacts_particle == one_by_one.stats.contacts_particle);
  if (steps == 1) {
    // Every lattice neighbour touches, the rows * rows pairs through the
    // boundary among them, and the particles still span the period.
    CHECK(batched.stats.contacts_particle == lattice_pairs);
    CHECK(spread_along_x(batched.state) > period - 2 * spacing);
  }
  REQUIRE(batched.state.id == one_by_one.state.id);
  const double position = test::relative_gap(batched.state.position, one_by_one.state.position);
  const double velocity = test::relative_gap(batched.state.velocity, one_by_one.state.velocity);
  const double spin = test::relative_gap(batched.state.spin, one_by_one.state.spin);
  INFO("relative differences: position " << position << ", velocity " << velocity << ", spin "
                                         << spin);
  // One step: round-off alone; over more, it grows (most under the Hertz laws).
  const bool hertz = model == "hertz_mindlin" || model == "thornton_elastic";
  const double growth = steps == 1 ? 1.0 : hertz ? 1e4 : 1e2;
  CHECK(position <= 1e-13 * growth);
  CHECK(velocity <= 1e-12 * growth);
  CHECK(spin <= 1e-12 * growth);
}
}  // namespace

TEST_CASE(
    "pair loop: the batched kernels give the per-contact path's trajectory across a periodic "
    "boundary",
    "[batch]") {
  for (const char* model : {"linear", "walton_braun", "hertz_mindlin"})
    for (const std::int64_t steps : {1, 100}) check_periodic(model, steps);
  // Thornton's law makes more of round-off than round-off (test_batch.cpp):
  // its first step only.
  check_periodic("thornton_elastic", 1);
}
