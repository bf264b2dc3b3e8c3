// The diagnostics framework (src/hooks) and the parallel force stage: contact
// events carry the right peak values, the wall-force diagnostic balances the
// weight of a settled bed, and results do not depend on the thread count.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>

#include "core/random.hpp"
#include "engine/simulation.hpp"
#include "hooks/diagnostic.hpp"

using namespace granule;

namespace {
// A diagnostic that keeps every contact event it is shown, for the tests.
template <int D>
struct EventRecorder final : Diagnostic<D> {
  std::vector<ContactEvent<D>> began, ended;
  double max_logged_normal = 0;
  EventRecorder() : Diagnostic<D>("test recorder") {}
  typename Diagnostic<D>::Needs needs() const override { return {true, true}; }
  void sample(const StepView<D>& v) override {
    for (std::size_t s = 0; s < v.contacts.size(); ++s)
      if (v.contacts.active[s])
        max_logged_normal = std::max(max_logged_normal, v.contacts.normal_force[s]);
  }
  void on_events(const StepView<D>& v) override {
    began.insert(began.end(), v.contacts.began.begin(), v.contacts.began.end());
    ended.insert(ended.end(), v.contacts.ended.begin(), v.contacts.ended.end());
  }
  std::string describe() const override { return "test recorder"; }
  const std::string& label() const override { return label_; }
  std::string label_ = "test_recorder";
  void close_window(double) override {}
  std::string fingerprint() const override { return "test recorder"; }
  // Never checkpointed by these tests; refuse rather than save nothing.
  void save_own(DiagnosticStateWriter&) const override {
    throw InputError("test recorder: no checkpoint");
  }
  void load_own(const DiagnosticStateReader&) override {
    throw InputError("test recorder: no checkpoint");
  }
};

// A settled bed of `count` disks on a floor under gravity (2D), Walton-Braun.
void bed(Simulation<2>& sim, int count, std::uint64_t seed, bool overlap = false) {
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"p", 2500, 0, 0, 0});
  sim.add_material({"w", 0, 0, 0, 0});
  ParamValues law{{"k_load", 1e3}, {"restitution", 0.3}, {"friction", 0.3}};
  sim.set_contact("p", "p", "walton_braun", law);
  sim.set_contact("p", "w", "walton_braun", law);
  WallSpec floor, left, right;
  floor.name = "floor", floor.material = 1, floor.normal = {0, 1, 0};
  left.name = "left", left.material = 1, left.normal = {1, 0, 0};
  right.name = "right", right.material = 1, right.normal = {-1, 0, 0}, right.point = {0.02, 0, 0};
  sim.add_wall(floor), sim.add_wall(left), sim.add_wall(right);
  FillSpec f;
  f.shape = RegionShape::box;
  f.lo = {0, 0, 0}, f.hi = {0.02, 0.04, 0};
  f.count = count;
  f.radius_min = 0.4e-3, f.radius_max = 0.5e-3;
  f.material = 0;
  f.seed = seed;
  f.allow_overlap = overlap;  // false: a gentle start, no particle shot out of the bed
  sim.fill(f);
  sim.set_gravity({0, -9.81, 0});
}
}  // namespace

TEST_CASE("diagnostics: a binary impact gives one begin and one end event with its peaks",
          "[diagnostics]") {
  Simulation<2> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"p", 1200, 0, 0, 0});
  sim.set_contact("p", "p", "walton_braun", {{"k_load", 2e4}, {"restitution", 0.85}});
  const double r = 0.2e-3, v = 0.8;
  ParticleSpec a, b;
  a.radius = b.radius = r, a.material = b.material = 0;
  a.position = {-r - 1e-6, 0, 0}, a.velocity = {v / 2, 0, 0};
  b.position = {r + 1e-6, 0, 0}, b.velocity = {-v / 2, 0, 0};
  sim.add_particle(a), sim.add_particle(b);
  auto recorder = std::make_unique<EventRecorder<2>>();
  EventRecorder<2>* rec = recorder.get();
  sim.prepare();
  sim.set_record_contacts(true);
  double max_normal = 0;
  // A C++ diagnostic attached directly (the registry is for named ones).
  sim.attach(std::move(recorder), "recorder");
  for (int k = 0; k < 20000; ++k) {
    sim.advance(1);
    for (const auto& c : sim.contacts()) max_normal = std::max(max_normal, c.normal_force);
  }
  REQUIRE(rec->began.size() == 1);
  REQUIRE(rec->ended.size() == 1);
  const auto& e = rec->ended[0];
  CHECK(e.id_a == 0);
  CHECK(e.id_b == 1);
  CHECK(e.wall == -1);
  CHECK(e.peak_normal_force == max_normal);
  CHECK(e.peak_normal_force == rec->max_logged_normal);
  // The approach speed at first touch is the impact speed (no force before contact).
  CHECK(e.impact_velocity == Approx(v).epsilon(1e-9));
  // Walton-Braun loading branch: peak force = K1 * peak overlap, and the closed form
  // of the peak overlap v sqrt(m*/K1) (energy balance on the loading spring).
  const double m_eff = 0.5 * sphere_mass(r, 1200);
  CHECK(e.peak_normal_force == Approx(2e4 * e.peak_overlap).epsilon(1e-12));
  CHECK(e.peak_overlap == Approx(v * std::sqrt(m_eff / 2e4)).epsilon(0.02));
  CHECK(e.effective_radius == Approx(r / 2));
  // The event spans the geometric contact: the force acts for
  // (pi/2)(sqrt(m*/K1) + sqrt(m*/K2)), then the spheres leave the permanent set
  // a0 = a_max (1 - e^2) at the rebound speed e v. Within two steps.
  const double e_r = 0.85, k2 = 2e4 / (e_r * e_r);
  const double geometric = 0.5 * pi * (std::sqrt(m_eff / 2e4) + std::sqrt(m_eff / k2)) +
                           e.peak_overlap * (1 - e_r * e_r) / (e_r * v);
  CHECK(std::abs(e.end_time - e.begin_time - geometric) < 2 * sim.time_step());
}

TEST_CASE("diagnostics: the wall_force diagnostic carries the weight of a settled bed",
          "[diagnostics]") {
  Simulation<2> sim;
  bed(sim, 120, 3);
  DiagnosticOptions o;
  o.strings["wall"] = "floor";
  o.numbers["every"] = 10;
  int id = sim.attach_diagnostic("wall_force", o);
  sim.advance(1);
  const double dt = sim.time_step();
  sim.advance(static_cast<std::int64_t>(0.4 / dt));  // settle 0.4 s
  sim.detach_diagnostic(id);
  // The walls carry the weight: in the mean, the vertical forces the bed puts
  // on the floor and on the side walls (friction there may push either way,
  // as the bed's history left its latched springs) add up to the weight,
  // downward. Horizontally the side walls' pushes balance.
  auto attach = [&](const char* wall) {
    DiagnosticOptions w;
    w.strings["wall"] = wall;
    return sim.attach_diagnostic("wall_force", w);
  };
  const int floor_id = attach("floor"), left_id = attach("left"), right_id = attach("right");
  sim.advance(static_cast<std::int64_t>(0.05 / dt));
  double weight = 0;
  for (auto pid : sim.particle_ids()) weight += sim.mass(pid) * 9.81;
  auto r = sim.diagnostic_results(floor_id);
  const auto left = sim.diagnostic_results(left_id), right = sim.diagnostic_results(right_id);
  const double vertical = r.at("mean_force_y") + left.at("mean_force_y") + right.at("mean_force_y");
  INFO("kinetic energy " << sim.stats().kinetic_translational << ", on the floor "
                         << r.at("mean_force_y") << ", on the sides "
                         << left.at("mean_force_y") + right.at("mean_force_y"));
  // 0.5%: the bed is not perfectly still.
  CHECK(-vertical == Approx(weight).epsilon(0.005));
  // The floor's normal force is its vertical force; the side walls' pushes cancel.
  CHECK(r.at("mean_normal_force") == Approx(-r.at("mean_force_y")).epsilon(1e-9));
  CHECK(r.at("mean_force_x") == Approx(0).margin(0.3 * r.at("mean_normal_force")));
  // Horizontally the side walls' pushes and the floor's friction balance.
  CHECK(r.at("mean_force_x") + left.at("mean_force_x") + right.at("mean_force_x") ==
        Approx(0).margin(0.005 * weight));
  CHECK(left.at("mean_force_x") < 0);  // the bed pushes the left wall to -x
  // Coulomb holds for the sum as for each contact (wall friction 0.3).
  CHECK(std::abs(r.at("mean_tangential_force")) <= 0.3 * r.at("mean_normal_force"));
  CHECK(std::abs(left.at("mean_force_y")) <= 0.3 * std::abs(left.at("mean_force_x")) + 1e-12);
  CHECK(r.at("samples") > 0);
}

TEST_CASE("diagnostics: unknown names and options are refused with a suggestion", "[diagnostics]") {
  Simulation<2> sim;
  DiagnosticOptions o;
  o.strings["wall"] = "floor";
  CHECK_THROWS_WITH(sim.attach_diagnostic("wall_forse", o),
                    Catch::Contains("did you mean 'wall_force'"));
  DiagnosticOptions typo;
  typo.strings["wall"] = "floor";
  typo.numbers["windw"] = 1;
  CHECK_THROWS_WITH(sim.attach_diagnostic("wall_force", typo),
                    Catch::Contains("did you mean 'window'"));
}

TEST_CASE("parallel: results are bit-identical for 1 and 2 threads", "[parallel]") {
  auto run = [](int threads) {
    Simulation<2> sim;
    bed(sim, 1500, 11, true);  // overlapping start: every loop busy from the first step
    sim.set_threads(threads);
    sim.set_parallel_thresholds(1024, 512);  // the parallel paths, on a small scene
    sim.advance(1500);
    REQUIRE(sim.stats().candidate_pairs >= 1024);  // the parallel contact loop ran
    return sim.flat_state();
  };
  auto one = run(1), two = run(2);
  REQUIRE(one.id == two.id);
  CHECK(std::memcmp(one.position.data(), two.position.data(),
                    one.position.size() * sizeof(double)) == 0);
  CHECK(std::memcmp(one.velocity.data(), two.velocity.data(),
                    one.velocity.size() * sizeof(double)) == 0);
  CHECK(std::memcmp(one.spin.data(), two.spin.data(), one.spin.size() * sizeof(double)) == 0);
}
