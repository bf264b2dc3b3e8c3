// The wall loop's batched path (kernel/wall_batch.hpp with a model's
// force_batch) against its per-contact path (set_batched_contacts(false)):
// particles in a turning cylinder around a fixed inner one (in 3D between a
// floor and a lid), overlapping the walls and one another from the start, so
// that wall contacts load, unload, slide and turn under every batched law. The
// states, the walls' forces and axial torques, and the contact log's wall
// contacts agree to round-off; the batch on two threads (the reactions summed
// afterwards in slot order) and with the contact log on gives the same
// numbers, bit for bit, as on one thread without it.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "batch_compare.hpp"
#include "engine/simulation.hpp"

using namespace granule;

namespace {

struct ChamberRun {
  SimulationBase::FlatState state;
  GlobalStats stats;
  std::vector<double> wall_loads;       // each wall's force (3 components) and axial torque
  std::vector<ContactRecord> contacts;  // the last step's, when logged
  // Wall contacts summed over the steps, and of them those the batch computed.
  std::int64_t wall_contacts = 0, wall_batched = 0;
};

using test::relative_gap;

struct ChamberOptions {
  bool batched = true;
  int threads = 1;
  bool log = false;
};

template <int D>
ChamberRun run_chamber(const std::string& model, std::int64_t steps, const ChamberOptions& o) {
  Simulation<D> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.set_batched_contacts(o.batched);
  sim.set_threads(o.threads);
  sim.set_parallel_thresholds(0, 0);  // the parallel paths on a small scene
  sim.set_record_contacts(o.log);
  sim.add_material({"p", 2500, 5e6, 0.3, 0});
  sim.add_material({"w", 7800, 2e8, 0.3, 0});
  auto law = [&](double k, double e, double mu) {
    ParamValues v{{"friction", mu}};
    if (model != "thornton_elastic") v["restitution"] = e;
    if (model == "linear") v["k_normal"] = k;
    if (model == "walton_braun") v["k_load"] = k;
    return v;
  };
  sim.set_contact("p", "p", model, law(1e3, 0.5, 0.4));
  sim.set_contact("p", "w", model, law(2e3, 0.7, 0.5));
  const double chamber = 5e-3, height = 4e-3, r = 0.4e-3;
  WallSpec outer;
  outer.name = "chamber", outer.type = WallType::cylinder, outer.material = 1;
  outer.radius = chamber, outer.inside = true, outer.angular_velocity = 40;
  sim.add_wall(outer);
  WallSpec inner;
  inner.name = "inner", inner.type = WallType::cylinder, inner.material = 1;
  inner.center = {1.5e-3, 0, 0}, inner.radius = 1.5e-3, inner.inside = false;
  sim.add_wall(inner);
  if constexpr (D == 3) {
    WallSpec floor, lid;
    floor.name = "floor", lid.name = "lid";
    floor.material = lid.material = 1;
    floor.normal = {0, 0, 1};
    lid.normal = {0, 0, -1}, lid.point = {0, 0, height};
    sim.add_wall(floor), sim.add_wall(lid);
  }
  // Rings of particles overlapping the chamber and the inner cylinder by 10-30 %
  // of their radius (in 3D in three layers, the outer ones overlapping floor
  // and lid too), moving and spinning, then a random fill between them.
  const double outer_rho = chamber, inner_x = 1.5e-3, inner_rho = 1.5e-3;
  const std::vector<double> layers =
      D == 3 ? std::vector<double>{0.8 * r, 0.5 * height, height - 0.8 * r}
             : std::vector<double>{0};
  int placed = 0;
  for (const double z : layers)
    for (int ring = 0; ring < 2; ++ring) {
      const int count = ring == 0 ? 34 : 12;
      for (int q = 0; q < count; ++q, ++placed) {
        const double angle = 2 * M_PI * (q + 0.25 * ring) / count;
        const double wobble = std::sin(7.1 * placed);  // a fixed pattern in [-1, 1]
        ParticleSpec spec;
        spec.radius = r * (0.9 + 0.1 * wobble);
        spec.material = 0;
        const double depth = spec.radius * (0.2 + 0.1 * wobble);
        const double rho =
            ring == 0 ? outer_rho - spec.radius + depth : inner_rho + spec.radius - depth;
        const double cx = ring == 0 ? 0 : inner_x;
        spec.position = {cx + rho * std::cos(angle), rho * std::sin(angle), z};
        spec.velocity = {0.05 * wobble, 0.05 * std::cos(3.3 * placed), D == 3 ? 0.02 * wobble : 0};
        spec.spin = {D == 3 ? 20 * wobble : 0, 0, 30 * std::cos(5.7 * placed)};
        sim.add_particle(spec);
      }
    }
  FillSpec fill;
  fill.shape = D == 3 ? RegionShape::cylinder : RegionShape::ball;
  fill.radius = chamber;
  fill.z_min = 0, fill.z_max = height;
  fill.count = D == 3 ? 150 : 50;
  fill.radius_min = 0.8 * r, fill.radius_max = r;
  fill.material = 0;
  fill.seed = 5;
  fill.max_speed = 0.05;
  sim.fill(fill);
  sim.set_gravity(D == 3 ? Triple{0, -9.81, -9.81} : Triple{0, -9.81, 0});
  std::int64_t wall_contacts = 0, wall_batched = 0;
  for (std::int64_t step = 0; step < steps; ++step) {
    sim.advance(1);
    wall_contacts += sim.stats().contacts_wall;
    wall_batched += sim.stats().contacts_wall_batched;
  }
  ChamberRun run{
      sim.flat_state(), sim.stats(), {}, o.log ? sim.contacts() : std::vector<ContactRecord>{},
      wall_contacts,    wall_batched};
  for (int w = 0; w < (D == 3 ? 4 : 2); ++w) {
    const Triple f = sim.wall_force(w);
    run.wall_loads.insert(run.wall_loads.end(), {f[0], f[1], f[2], sim.wall_axial_torque(w)});
  }
  return run;
}

template <int D>
void check_chamber(const std::string& model, std::int64_t steps) {
  const ChamberRun batched = run_chamber<D>(model, steps, {true, 1, false}),
                   one_by_one = run_chamber<D>(model, steps, {false, 1, false});
  INFO(model << " in " << D << "D, " << steps << " steps: wall contacts summed over the steps "
             << batched.wall_contacts << " (batched " << batched.wall_batched << ")");
  // More than a batch's lanes on the first step; their rebounds thin them out later.
  REQUIRE(batched.wall_contacts >= (steps == 1 ? 33 : 5 * steps));
  REQUIRE(batched.wall_batched == batched.wall_contacts);
  REQUIRE(one_by_one.wall_batched == 0);
  REQUIRE(batched.wall_contacts == one_by_one.wall_contacts);
  REQUIRE(batched.state.id == one_by_one.state.id);
  const double position = relative_gap(batched.state.position, one_by_one.state.position);
  const double velocity = relative_gap(batched.state.velocity, one_by_one.state.velocity);
  const double spin = relative_gap(batched.state.spin, one_by_one.state.spin);
  const double loads = relative_gap(batched.wall_loads, one_by_one.wall_loads);
  INFO("relative differences: position " << position << ", velocity " << velocity << ", spin "
                                         << spin << ", wall loads " << loads);
  // As the pair loop's batch (test_batch.cpp): round-off on the first step,
  // grown over a few hundred steps of particles pushing one another apart,
  // most under the Hertz laws.
  const bool hertz = model == "hertz_mindlin" || model == "thornton_elastic";
  const double growth = steps == 1 ? 1.0 : hertz ? 1e4 : 1e2;
  CHECK(position <= 1e-13 * growth);
  CHECK(velocity <= 1e-12 * growth);
  CHECK(spin <= 1e-12 * growth);
  CHECK(loads <= 1e-11 * growth);
}

}  // namespace

TEST_CASE("wall loop: the batched kernels give the per-contact path's trajectory and wall loads",
          "[batch]") {
  for (const std::string model : {"linear", "walton_braun", "hertz_mindlin"})
    for (const std::int64_t steps : {1, 200}) {
      check_chamber<2>(model, steps);
      check_chamber<3>(model, steps);
    }
  // Thornton's law turns round-off into more than round-off within a few
  // steps (test_batch.cpp measures that drift): compared on the first step.
  check_chamber<2>("thornton_elastic", 1);
  check_chamber<3>("thornton_elastic", 1);
}

TEST_CASE("wall loop: the batch on two threads and with the contact log gives the same numbers",
          "[batch]") {
  for (const std::string model : {"linear", "walton_braun"}) {
    const ChamberRun plain = run_chamber<3>(model, 100, {true, 1, false});
    const ChamberRun two = run_chamber<3>(model, 100, {true, 2, false});
    const ChamberRun logged = run_chamber<3>(model, 100, {true, 1, true});
    INFO(model);
    REQUIRE(plain.wall_batched == plain.wall_contacts);
    REQUIRE(plain.wall_contacts >= 10 * 100);
    for (const ChamberRun* other : {&two, &logged}) {
      CHECK(other->state.position == plain.state.position);
      CHECK(other->state.velocity == plain.state.velocity);
      CHECK(other->state.spin == plain.state.spin);
      CHECK(other->wall_loads == plain.wall_loads);
    }
  }
}

TEST_CASE("wall loop: the batch logs the wall contacts the per-contact path logs", "[batch]") {
  const ChamberRun batched = run_chamber<3>("walton_braun", 100, {true, 1, true}),
                   one_by_one = run_chamber<3>("walton_braun", 100, {false, 1, true});
  std::vector<const ContactRecord*> a, b;
  for (const auto& c : batched.contacts)
    if (c.id_b < 0) a.push_back(&c);
  for (const auto& c : one_by_one.contacts)
    if (c.id_b < 0) b.push_back(&c);
  REQUIRE(a.size() == static_cast<std::size_t>(batched.stats.contacts_wall));
  REQUIRE(a.size() == b.size());
  REQUIRE(a.size() >= 10);
  double largest_force = 0;
  for (const auto* c : a) largest_force = std::max(largest_force, std::abs(c->normal_force));
  REQUIRE(largest_force > 0);
  int sliding = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    INFO("wall contact " << k << " of particle " << a[k]->id_a << " on wall " << a[k]->wall);
    REQUIRE(a[k]->id_a == b[k]->id_a);
    REQUIRE(a[k]->wall == b[k]->wall);
    CHECK(std::abs(a[k]->overlap - b[k]->overlap) <= 1e-9 * std::abs(b[k]->overlap) + 1e-18);
    sliding += test::check_record_forces(*a[k], *b[k], largest_force);
  }
  CHECK(sliding > 5);  // the turning chamber drags them: friction is at work
}
