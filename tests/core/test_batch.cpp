// The pair loop's batched path (kernel/pair_batch.hpp with a model's
// force_batch) against its per-contact path (set_batched_contacts(false)) on
// the same 3D scene: a pile of overlapping spheres with friction in a box,
// settling under gravity; all of one material (one law for the whole
// bucket), or with a third of another material under other laws (a batch
// then mixes laws lane by lane).
#include <catch2/catch.hpp>
#include <cstring>
#include <string>

#include "batch_compare.hpp"
#include "box_walls.hpp"
#include "engine/simulation.hpp"

using namespace granule;

namespace {
struct PileRun {
  SimulationBase::FlatState state;
  GlobalStats stats;
  std::vector<ContactRecord> contacts;  // the last step's, from the contact log
};

using test::relative_gap;

void build_pile(Simulation<3>& sim, bool batched, bool mixed) {
  sim.set_warning_handler([](const std::string&) {});
  sim.set_batched_contacts(batched);
  sim.add_material({"p", 2500, 0, 0, 0});
  sim.add_material({"q", 2000, 0, 0, 0});
  sim.add_material({"w", 0, 0, 0, 0});
  ParamValues law{{"k_normal", 1e3}, {"restitution", 0.5}, {"friction", 0.4}};
  ParamValues other{{"k_normal", 2e3}, {"restitution", 0.8}, {"friction", 0.2}};
  ParamValues stiff{
      {"k_normal", 3e3}, {"restitution", 0.3}, {"friction", 0.6}, {"allow_tension", 0}};
  sim.set_contact("p", "p", "linear", law);
  sim.set_contact("p", "q", "linear", other);
  sim.set_contact("q", "q", "linear", stiff);
  sim.set_contact("p", "w", "linear", law);
  sim.set_contact("q", "w", "linear", other);
  const double side = 0.008, r = 0.4e-3;
  test::add_box_walls(sim, side, 0.05, 2);
  FillSpec pile;
  pile.shape = RegionShape::box;
  pile.lo = {0, 0, 0}, pile.hi = {side, side, 0.005};
  pile.count = 500;
  pile.radius_min = 0.8 * r, pile.radius_max = r;
  pile.material = 0;
  pile.seed = 11;
  pile.allow_overlap = true;  // contacts from the first step, some far from rest
  sim.fill(pile);
  if (mixed) {
    pile.count = 250, pile.material = 1, pile.seed = 12;
    sim.fill(pile);
  }
  sim.set_gravity({0, 0, -9.81});
}

PileRun run_pile(bool batched, bool mixed, std::int64_t steps, bool record = false) {
  Simulation<3> sim;
  build_pile(sim, batched, mixed);
  sim.set_record_contacts(record);  // the kernels' logging instantiation
  sim.advance(steps);
  return {sim.flat_state(), sim.stats(), record ? sim.contacts() : std::vector<ContactRecord>{}};
}
}  // namespace

TEST_CASE("pair loop: the batched 3D kernel gives the per-contact path's trajectory", "[batch]") {
  const std::int64_t steps = 300;
  for (const bool mixed : {false, true}) {
    const PileRun batched = run_pile(true, mixed, steps),
                  one_by_one = run_pile(false, mixed, steps);
    INFO((mixed ? "two materials, three laws" : "one law")
         << ": contacts " << batched.stats.contacts_particle << " (batched "
         << batched.stats.contacts_batched << "), per contact "
         << one_by_one.stats.contacts_particle << " (batched " << one_by_one.stats.contacts_batched
         << ")");
    // Each run took the path it was meant to.
    REQUIRE(batched.stats.contacts_particle > 100);
    REQUIRE(batched.stats.contacts_batched == batched.stats.contacts_particle);
    REQUIRE(one_by_one.stats.contacts_batched == 0);
    REQUIRE(batched.stats.contacts_particle == one_by_one.stats.contacts_particle);
    // Positions, velocities and spins agree to round-off, grown over 300
    // steps of a pile pushing itself apart: relative to each one's largest value.
    REQUIRE(batched.state.id == one_by_one.state.id);
    const double position = relative_gap(batched.state.position, one_by_one.state.position);
    const double velocity = relative_gap(batched.state.velocity, one_by_one.state.velocity);
    const double spin = relative_gap(batched.state.spin, one_by_one.state.spin);
    INFO("relative differences: position " << position << ", velocity " << velocity << ", spin "
                                           << spin);
    CHECK(position <= 1e-12);
    CHECK(velocity <= 1e-10);
    CHECK(spin <= 1e-10);
  }
}

namespace {
// A pile as build_pile's, in D dimensions, under `model` (linear,
// walton_braun, hertz_mindlin or thornton_elastic), spinning and shaken (random velocities) so that
// contacts load, unload, slide and turn; with `mixed`, a third of the particles of another material
// under two other laws of the same model.
// With `nudged`, every particle's velocity moved by up to two ulp before the
// run (a measure of how far round-off alone carries the run).
// `rescale`: Thornton's shrink_rescale on (with `mixed`, on all laws but q-q's, so that
// the lanes of a batch mix both readings).
template <int D>
PileRun run_law_pile(const std::string& model, bool batched, bool mixed, std::int64_t steps,
                     bool nudged = false, bool rescale = false) {
  Simulation<D> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.set_batched_contacts(batched);
  sim.add_material({"p", 2500, 5e6, 0.3, 0});  // Young moduli: only the Hertz laws read them
  sim.add_material({"q", 2000, 2e7, 0.25, 0});
  sim.add_material({"w", 0, 2e8, 0.3, 0});
  auto law = [&](double k, double e, double mu, double exponent) {
    ParamValues v{{"friction", mu}};
    if (model != "thornton_elastic") v["restitution"] = e;  // an elastic law: no restitution
    if (model == "linear") v["k_normal"] = k;
    if (model == "walton_braun") v["k_load"] = k, v["slip_exponent"] = exponent;
    if (rescale) v["shrink_rescale"] = mixed && k == 3e3 ? 0 : 1;
    return v;
  };
  sim.set_contact("p", "p", model, law(1e3, 0.5, 0.4, 1.0));
  sim.set_contact("p", "q", model, law(2e3, 0.8, 0.2, 1.0));
  sim.set_contact("q", "q", model, law(3e3, 0.9, 0.6, 1.5));
  sim.set_contact("p", "w", model, law(1e3, 0.5, 0.4, 1.0));
  sim.set_contact("q", "w", model, law(2e3, 0.8, 0.2, 1.0));
  const double side = 0.008, r = 0.4e-3;
  test::add_box_walls(sim, side, 0.05, 2);
  FillSpec pile;
  pile.shape = RegionShape::box;
  pile.lo = {r, r, r},
  pile.hi = {side - r, D == 3 ? side - r : 0.005, 0.005};  // clear of the walls
  pile.count = D == 3 ? 500 : 60;
  pile.radius_min = 0.8 * r, pile.radius_max = r;
  pile.material = 0;
  pile.seed = 21;
  pile.max_speed = 0.05;
  pile.allow_overlap = true;
  sim.fill(pile);
  if (mixed) {
    pile.count /= 2, pile.material = 1, pile.seed = 22;
    sim.fill(pile);
  }
  sim.set_gravity(D == 3 ? Triple{0, 0, -9.81} : Triple{0, -9.81, 0});
  if (nudged) {
    const auto state = sim.flat_state();
    for (std::size_t k = 0; k < state.id.size(); ++k) {
      const double f = 1 + 2.2e-16 * (static_cast<double>(k * 7919 % 5) - 2);
      const double* v = &state.velocity[D * k];
      Triple moved{v[0] * f, v[1] * f, 0};
      if constexpr (D == 3) moved = Triple{v[0] * f, v[1] * f, v[2] * f};
      sim.set_velocity(state.id[k], moved);
    }
  }
  sim.advance(steps);
  return {sim.flat_state(), sim.stats(), {}};
}

template <int D>
void check_law_pile(const std::string& model, bool mixed, std::int64_t steps,
                    bool rescale = false) {
  // The Hertz laws' deep first overlaps throw the pile apart within ~200 steps:
  // compared before that.
  const bool hertz = model == "hertz_mindlin" || model == "thornton_elastic";
  if (hertz) steps = std::min<std::int64_t>(steps, 100);
  // Thornton's law makes more of round-off than round-off: where only dN acts,
  // a slip of round-off size decides the sense of its increment mu dN (1 -
  // theta), and near full slip its cube root (Eq. 6.7) makes a round-off e
  // into e^(1/3). Its per-contact path, run again with the velocities moved by
  // an ulp, drifts apart by ~1e-7 within 3 steps and ~1e-5 in 30 (3D; Hertz-
  // Mindlin's stays below 1e-13): past the first step the two paths are held
  // to that drift, over 30 steps (later the piles may differ by a contact).
  const bool sensitive = model == "thornton_elastic" && steps > 1;
  if (sensitive) steps = std::min<std::int64_t>(steps, 30);
  const PileRun batched = run_law_pile<D>(model, true, mixed, steps, false, rescale),
                one_by_one = run_law_pile<D>(model, false, mixed, steps, false, rescale);
  INFO(model << (rescale ? " (shrink_rescale)" : "") << " in " << D << "D"
             << (mixed ? ", two materials, three laws" : "") << ", " << steps << " steps: contacts "
             << batched.stats.contacts_particle << " (batched " << batched.stats.contacts_batched
             << ")");
  REQUIRE(batched.stats.contacts_particle > 0);
  REQUIRE(batched.stats.contacts_batched == batched.stats.contacts_particle);
  REQUIRE(one_by_one.stats.contacts_batched == 0);
  REQUIRE(batched.stats.contacts_particle == one_by_one.stats.contacts_particle);
  REQUIRE(batched.state.id == one_by_one.state.id);
  const double position = relative_gap(batched.state.position, one_by_one.state.position);
  const double velocity = relative_gap(batched.state.velocity, one_by_one.state.velocity);
  const double spin = relative_gap(batched.state.spin, one_by_one.state.spin);
  INFO("relative differences: position " << position << ", velocity " << velocity << ", spin "
                                         << spin);
  // One step: the forces of both paths differ by round-off alone. Over 100-300
  // steps of a pile pushing itself apart the round-off grows; most under the
  // Hertz laws, whose stiffness rises with the (here deep) overlap.
  const double growth = steps == 1 ? 1.0 : hertz ? 1e4 : 1e2;
  double drift_position = 0, drift_velocity = 0, drift_spin = 0;
  if (sensitive) {
    const PileRun nudged = run_law_pile<D>(model, false, mixed, steps, true, rescale);
    REQUIRE(nudged.state.id == one_by_one.state.id);
    drift_position = relative_gap(nudged.state.position, one_by_one.state.position);
    drift_velocity = relative_gap(nudged.state.velocity, one_by_one.state.velocity);
    drift_spin = relative_gap(nudged.state.spin, one_by_one.state.spin);
  }
  INFO("the per-contact path's own drift from an ulp: position "
       << drift_position << ", velocity " << drift_velocity << ", spin " << drift_spin);
  CHECK(position <= 1e-13 * growth + 30 * drift_position);
  CHECK(velocity <= 1e-12 * growth + 30 * drift_velocity);
  CHECK(spin <= 1e-12 * growth + 30 * drift_spin);
}
}  // namespace

TEST_CASE(
    "pair loop: the batched kernels of Walton-Braun, Hertz-Mindlin and the 2D laws give "
    "the per-contact path's trajectory",
    "[batch]") {
  for (const bool mixed : {false, true})
    for (const std::int64_t steps : {1, 300}) {
      check_law_pile<2>("linear", mixed, steps);
      check_law_pile<2>("walton_braun", mixed, steps);
      check_law_pile<3>("walton_braun", mixed, steps);
      check_law_pile<2>("hertz_mindlin", mixed, steps);
      check_law_pile<3>("hertz_mindlin", mixed, steps);
    }
}

TEST_CASE(
    "pair loop: the batched kernels of Thornton's elastic law give the per-contact path's "
    "trajectory",
    "[batch][thornton]") {
  for (const bool mixed : {false, true})
    for (const std::int64_t steps : {1, 30}) {
      check_law_pile<2>("thornton_elastic", mixed, steps);
      check_law_pile<3>("thornton_elastic", mixed, steps);
      check_law_pile<2>("thornton_elastic", mixed, steps, true);
      check_law_pile<3>("thornton_elastic", mixed, steps, true);
    }
}

TEST_CASE("pair loop: the batched 3D kernel logs the contacts the per-contact path logs",
          "[batch]") {
  const std::int64_t steps = 200;
  const PileRun batched = run_pile(true, true, steps, true),
                one_by_one = run_pile(false, true, steps, true);
  REQUIRE(batched.stats.contacts_batched == batched.stats.contacts_particle);
  REQUIRE(one_by_one.stats.contacts_batched == 0);
  // Pair contacts only (walls take the per-contact path in both), in log order.
  std::vector<const ContactRecord*> a, b;
  for (const auto& c : batched.contacts)
    if (c.id_b >= 0) a.push_back(&c);
  for (const auto& c : one_by_one.contacts)
    if (c.id_b >= 0) b.push_back(&c);
  REQUIRE(a.size() == static_cast<std::size_t>(batched.stats.contacts_particle));
  REQUIRE(a.size() == b.size());
  double largest_force = 0, largest_overlap = 0;
  for (const auto* c : a) {
    largest_force = std::max(largest_force, std::abs(c->normal_force));
    largest_overlap = std::max(largest_overlap, c->overlap);
  }
  REQUIRE(largest_force > 0);
  int sliding_or_turning = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    INFO("contact " << k << " between " << a[k]->id_a << " and " << a[k]->id_b);
    REQUIRE(a[k]->id_a == b[k]->id_a);
    REQUIRE(a[k]->id_b == b[k]->id_b);
    CHECK(std::abs(a[k]->overlap - b[k]->overlap) <= 1e-9 * largest_overlap);
    sliding_or_turning += test::check_record_forces(*a[k], *b[k], largest_force);
  }
  CHECK(sliding_or_turning > 10);  // friction is at work, not only normal springs
}

// The batch adds a force and a torque to a particle as four doubles each
// (pair_batch.hpp): the fourth of each must stay 0, or the record would carry
// garbage into whatever reads it whole.
TEST_CASE("pair loop: the batch leaves the zeros after a particle's force and torque", "[batch]") {
  static_assert(sizeof(ForceTorque<3>) == 64);
  ForceTorque<3> record;
  REQUIRE(reinterpret_cast<char*>(record.torque.data()) - reinterpret_cast<char*>(&record) == 32);
  Simulation<3> sim;
  build_pile(sim, true, true);
  sim.advance(50);
  REQUIRE(sim.stats().contacts_batched > 100);
  const auto& ft = sim.particles().force_torque;
  double largest = 0;
  for (const auto& p : ft) {
    REQUIRE(p.force_pad == 0.0);
    REQUIRE(p.torque_pad == 0.0);
    largest = std::max(largest, p.force.norm());
  }
  CHECK(largest > 0);  // the records were written
}

// The batch reads a particle's 3-vector as four doubles, so the hot arrays
// must be readable past their last element (hot_array.hpp). Under
// AddressSanitizer (GRANULE_SANITIZE) this read fails without that margin.
TEST_CASE("hot arrays: readable four doubles from the last 3-vector", "[batch]") {
  for (std::size_t n : {1, 7, 1000, 50000}) {  // ordinary and huge-page allocations
    HotArray<Vec<3>> v(n, Vec<3>(1, 2, 3));
    double four[4];
    std::memcpy(four, v.back().data(), sizeof four);
    CHECK(four[0] == 1);
    CHECK(four[2] == 3);
  }
}
