// Schedules (fields/schedule.hpp, engine/simulation_schedules.cpp): each
// form against its closed form inside and outside the ramp; bad schedules
// refused naming the parameter; the engine sets the target before every step
// to the value at that step's time; checkpoints refuse other schedules.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "core/state.hpp"
#include "engine/simulation.hpp"
#include "fields/schedule.hpp"

using namespace granule;

TEST_CASE("a constant schedule holds its value at every time", "[schedule]") {
  const Schedule s = Schedule::constant(2.5, "c");
  for (double t : {-1.0, 0.0, 1e-9, 3.0, 1e6}) CHECK(s.at(t) == 2.5);
}

TEST_CASE("a linear schedule: v0 before t0, the line between, v1 after t1", "[schedule]") {
  const double t0 = 0.1, v0 = 1, t1 = 0.3, v1 = 5;
  const Schedule s = Schedule::linear(t0, v0, t1, v1, "l");
  CHECK(s.at(-1) == v0);
  CHECK(s.at(0) == v0);
  CHECK(s.at(t0) == v0);
  for (double t : {0.12, 0.2, 0.25, 0.2999})
    CHECK(s.at(t) == Approx(v0 + (v1 - v0) * (t - t0) / (t1 - t0)).epsilon(1e-14));
  CHECK(s.at(0.2) == Approx(3).epsilon(1e-14));  // the midpoint, by hand
  CHECK(s.at(t1) == v1);
  CHECK(s.at(10) == v1);
  // Falling ramps too (the field removed gradually).
  const Schedule down = Schedule::linear(0, 5e5, 1e-4, 0, "down");
  CHECK(down.at(2.5e-5) == Approx(3.75e5).epsilon(1e-14));
  CHECK(down.at(2e-4) == 0);
}

TEST_CASE("a piecewise schedule: linear through its points, a jump at a repeated time",
          "[schedule]") {
  const Schedule s = Schedule::piecewise({0, 1, 1, 3}, {0, 2, 5, 1}, "p");
  CHECK(s.at(-1) == 0);
  CHECK(s.at(0.5) == Approx(1).epsilon(1e-14));
  CHECK(s.at(0.999) == Approx(1.998).epsilon(1e-14));
  CHECK(s.at(1) == 5);  // from the jump's time on, the later value
  CHECK(s.at(2) == Approx(3).epsilon(1e-14));
  CHECK(s.at(2.5) == Approx(2).epsilon(1e-14));
  CHECK(s.at(3) == 1);
  CHECK(s.at(7) == 1);
  // One point: a constant.
  CHECK(Schedule::piecewise({2}, {4}, "one").at(0) == 4);
  // A jump at the first point holds from its time on too (a 0/1 switch, { t, 1, t, 0 }),
  // also when later points follow, and at t = 0.
  const Schedule first = Schedule::piecewise({1, 1, 3}, {0, 100, 40}, "first");
  CHECK(first.at(0.999) == 0);
  CHECK(first.at(1) == 100);
  CHECK(first.at(2) == Approx(70).epsilon(1e-14));
  const Schedule at_zero = Schedule::piecewise({0, 0}, {1, 0}, "switch");
  CHECK(at_zero.at(-1e-9) == 1);
  CHECK(at_zero.at(0) == 0);
}

TEST_CASE("a bad schedule is refused naming the parameter and the point", "[schedule]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(Schedule::piecewise({0, 2, 1}, {0, 1, 2}, "schedule 'friction', piecewise"),
                    Catch::Contains("schedule 'friction', piecewise") &&
                        Catch::Contains("time goes backwards at point 3"));
  CHECK_THROWS_WITH(Schedule::piecewise({0, 1}, {0, nan}, "schedule 'friction', points"),
                    Catch::Contains("schedule 'friction', points") && Catch::Contains("value 2"));
  CHECK_THROWS_WITH(Schedule::piecewise({0, nan}, {0, 1}, "s"), Catch::Contains("time 2"));
  CHECK_THROWS_WITH(Schedule::piecewise({}, {}, "s"), Catch::Contains("at least one point"));
  CHECK_THROWS_WITH(Schedule::piecewise({0, 1}, {0}, "s"), Catch::Contains("one value per time"));
  CHECK_THROWS_WITH(Schedule::linear(1, 0, 1, 2, "schedule 'x', linear"),
                    Catch::Contains("schedule 'x', linear") && Catch::Contains("t1 > t0"));
  CHECK_THROWS_WITH(Schedule::linear(0, nan, 1, 2, "s"), Catch::Contains("value 1"));
  CHECK_THROWS_WITH(Schedule::constant(std::numeric_limits<double>::infinity(), "s"),
                    Catch::Contains("must be finite"));
}

namespace {
// A drum with a few grains and a central field, ready to step.
void drum(Simulation<2>& sim) {
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"p", 2500, 0, 0, 0});
  sim.add_material({"w", 7800, 0, 0, 0});
  ParamValues law{{"k_load", 1e3}, {"restitution", 0.5}, {"friction", 0.3}};
  sim.set_contact("p", "p", "walton_braun", law);
  sim.set_contact("p", "w", "walton_braun", law);
  WallSpec w;
  w.type = WallType::cylinder, w.name = "drum", w.material = 1, w.radius = 0.01;
  sim.add_wall(w);
  FillSpec f;
  f.shape = RegionShape::ball;  // a disc in 2D
  f.center = {0, 0, 0}, f.radius = 0.008;
  f.count = 20;
  f.radius_min = f.radius_max = 0.5e-3;
  f.material = 0;
  f.seed = 3;
  sim.fill(f);
  sim.set_central_field({0, 0, 0}, 10);
}

ScheduleSpec spec(const std::string& target, Schedule s, const std::string& a = "",
                  const std::string& b = "") {
  ScheduleSpec out;
  out.target = target, out.a = a, out.b = b, out.schedule = std::move(s);
  return out;
}
}  // namespace

TEST_CASE("the engine sets a scheduled value before every step to its value at that time",
          "[schedule]") {
  Simulation<2> sim;
  drum(sim);
  sim.prepare();
  const double dt = sim.time_step();
  const Schedule spin = Schedule::linear(5 * dt, 0, 25 * dt, 40, "spin");
  const Schedule field = Schedule::piecewise({0, 10 * dt, 10 * dt}, {10, 4, 0}, "field");
  sim.add_schedule(spec("wall_angular_velocity", spin, "drum"));
  sim.add_schedule(spec("central_strength", field));
  CHECK(sim.wall(0).angular_velocity == 0);
  CHECK(sim.central_strength() == 10);
  for (int n = 0; n < 40; ++n) {
    INFO("step " << n);
    // Before step n: the values at t_n.
    CHECK(sim.wall(0).angular_velocity == spin.at(sim.time()));
    CHECK(sim.central_strength() == field.at(sim.time()));
    sim.advance(1);
  }
  CHECK(sim.wall(0).angular_velocity == 40);
  CHECK(sim.central_strength() == 0);
}

TEST_CASE("a schedule with an unknown target, wall or parameter is refused naming it",
          "[schedule]") {
  Simulation<2> sim;
  drum(sim);
  const Schedule s = Schedule::constant(0.4, "s");
  CHECK_THROWS_WITH(sim.add_schedule(spec("frction", s)),
                    Catch::Contains("'frction'") && Catch::Contains("not a known target"));
  CHECK_THROWS_WITH(sim.add_schedule(spec("frction", s, "p", "p")), Catch::Contains("frction"));
  CHECK_THROWS_WITH(sim.add_schedule(spec("friction", s, "p", "glass")), Catch::Contains("glass"));
  CHECK_THROWS_WITH(sim.add_schedule(spec("wall_angular_velocity", s, "drun")),
                    Catch::Contains("drun"));
  CHECK(sim.schedules().empty());
  sim.add_schedule(spec("friction", s, "p", "p"));
  CHECK(sim.schedules().size() == 1);
}

TEST_CASE("a checkpoint holds the schedules, a restart with other ones is refused", "[schedule]") {
  Simulation<2> a;
  drum(a);
  a.prepare();
  const double dt = a.time_step();
  const Schedule spin = Schedule::linear(0, 0, 100 * dt, 50, "spin");
  a.add_schedule(spec("wall_angular_velocity", spin, "drum"));
  a.advance(30);
  const StateBlob blob = a.save_state();
  a.advance(30);

  Simulation<2> b;
  drum(b);
  b.add_schedule(spec("wall_angular_velocity", spin, "drum"));
  b.load_state(blob);
  b.advance(30);
  CHECK(b.wall(0).angular_velocity == a.wall(0).angular_velocity);
  CHECK(b.position(0) == a.position(0));

  Simulation<2> c;
  drum(c);
  c.add_schedule(
      spec("wall_angular_velocity", Schedule::linear(0, 0, 100 * dt, 60, "spin"), "drum"));
  CHECK_THROWS_WITH(c.load_state(blob), Catch::Contains("schedules differ"));
  Simulation<2> none;
  drum(none);
  CHECK_THROWS_WITH(none.load_state(blob), Catch::Contains("schedules differ"));
}

TEST_CASE("a schedule that stiffens a law past the time step is refused saying when",
          "[schedule]") {
  Simulation<2> sim;
  drum(sim);
  sim.prepare();
  const double dt = sim.time_step();
  sim.set_time_step(dt);  // fixed: a stiffer law must not shorten it
  // k_load 1000 times the drum's at step 10: the step is then far past the stability limit.
  sim.add_schedule(
      spec("k_load", Schedule::piecewise({0, 10 * dt, 10 * dt}, {1e4, 1e4, 1e7}, "k"), "p", "p"));
  CHECK_THROWS_WITH(sim.advance(20), Catch::Contains("schedule 'k_load' of p-p at t = ") &&
                                         Catch::Contains("(step 1") &&
                                         Catch::Contains("stability limit"));
}
