// Checkpoints: a run saved at step K, written to disk, read back into a freshly
// declared scene and continued is bit-identical to the run that never stopped; a
// damaged checkpoint is refused, naming the damaged entry.
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "engine/simulation.hpp"
#include "io/checkpoint.hpp"

using namespace granule;

namespace {
// A rotating drum with a stationary post, Walton-Braun with friction and a
// Thornton pair for a second material: histories of two models and walls, two
// of them with rolling resistance.
template <int D>
void scene(Simulation<D>& sim) {
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"powder", 1200, 0, 0, 0});
  sim.add_material({"glass", 2650, 70e6, 0.3, 0});  // soft: a larger Rayleigh step
  sim.add_material({"steel", 7800, 200e6, 0.3, 0});
  ParamValues wb{{"k_load", 2e4}, {"restitution", 0.85}, {"friction", 0.4}};
  sim.set_contact("powder", "powder", "walton_braun", wb);
  // Rolling resistance (contact/rolling.hpp) carries its own history: the
  // constant torque against the walls, the EPSD spring between glass spheres.
  ParamValues wb_rolling = wb;
  wb_rolling["rolling_friction"] = 0.05, wb_rolling["rolling_model"] = 1;
  sim.set_contact("powder", "steel", "walton_braun", wb_rolling);
  sim.set_contact("powder", "glass", "walton_braun", wb);
  sim.set_contact("glass", "glass", "thornton_elastic",
                  {{"friction", 0.3}, {"rolling_friction", 0.1}, {"rolling_damping", 0.2}});
  sim.set_contact("glass", "steel", "thornton_elastic", {{"friction", 0.3}});
  WallSpec drum;
  drum.name = "drum", drum.type = WallType::cylinder, drum.material = 2, drum.radius = 6e-3;
  drum.angular_velocity = 200;
  WallSpec post = drum;
  post.name = "post", post.inside = false, post.radius = 1.5e-3, post.center = {2.5e-3, 0, 0};
  post.angular_velocity = 0;
  sim.add_wall(drum), sim.add_wall(post);
  if constexpr (D == 3) sim.set_periodic(2, 0, 3e-3);
  FillSpec f;
  f.shape = D == 3 ? RegionShape::cylinder : RegionShape::ball;
  f.radius = 6e-3, f.z_min = 0, f.z_max = 3e-3;
  f.count = 150, f.radius_min = 0.18e-3, f.radius_max = 0.22e-3, f.material = 0;
  f.seed = 5, f.max_speed = 1.0;
  sim.fill(f);
  f.count = 50, f.material = 1, f.seed = 6;
  sim.fill(f);
  sim.set_threads(2);
}

template <int D>
bool same_state(const SimulationBase& a, const SimulationBase& b) {
  auto x = a.flat_state(), y = b.flat_state();
  auto eq = [](const std::vector<double>& u, const std::vector<double>& v) {
    return u.size() == v.size() && std::memcmp(u.data(), v.data(), u.size() * sizeof(double)) == 0;
  };
  return x.id == y.id && eq(x.position, y.position) && eq(x.velocity, y.velocity) &&
         eq(x.spin, y.spin);
}
}  // namespace

TEMPLATE_TEST_CASE_SIG("checkpoint: a continued run is bit-identical to an uninterrupted one",
                       "[checkpoint]", ((int D), D), 2, 3) {
  const std::string path =
      (std::filesystem::temp_directory_path() /
       ("granule_test_" + std::to_string(getpid()) + "_" + std::to_string(D) + ".chk.h5"))
          .string();
  Simulation<D> whole;
  scene(whole);
  std::int64_t wall_contacts = 0, pair_contacts = 0;
  auto advance = [&](Simulation<D>& sim) {
    for (int k = 0; k < 20; ++k) {
      sim.advance(1000);
      wall_contacts += sim.stats().contacts_wall;
      pair_contacts += sim.stats().contacts_particle;
    }
  };
  advance(whole);
  io::write_checkpoint(path, whole.save_state(), {{"scene", "test"}});
  advance(whole);

  Simulation<D> resumed;
  scene(resumed);  // declares the same materials and walls; its random fill is replaced
  std::map<std::string, std::string> attrs;
  resumed.load_state(io::read_checkpoint(path, &attrs));
  CHECK(attrs.at("scene") == "test");
  CHECK(resumed.step_count() == 20000);
  resumed.advance(20000);
  CHECK(resumed.time() == whole.time());
  CHECK(same_state<D>(whole, resumed));
  // Contacts did happen between particles and with the walls (so histories mattered).
  CHECK(pair_contacts > 0);
  CHECK(wall_contacts > 0);
  std::remove(path.c_str());
}

// The random fill overlaps pairs by more than a radius; while they relax, the guard
// that stops pairs passing through each other must know those overlaps are the
// scene's own, also in a run continued from a checkpoint taken then.
TEMPLATE_TEST_CASE_SIG(
    "checkpoint: a run continued while its fill's overlaps relax goes on as "
    "the uninterrupted one",
    "[checkpoint]", ((int D), D), 2, 3) {
  Simulation<D> whole;
  scene(whole);
  whole.advance(2);
  REQUIRE(whole.stats().max_overlap_ratio >
          1);  // deeper than a radius: a pass-through if not the scene's
  const StateBlob saved = whole.save_state();
  whole.advance(3000);
  Simulation<D> resumed;
  scene(resumed);
  resumed.load_state(saved);
  REQUIRE_NOTHROW(resumed.advance(3000));
  CHECK(same_state<D>(whole, resumed));
}

// A run lets a particle pressed into a wall have its centre beyond it by less than its
// radius (check_escapes); its checkpoint must restart. One further beyond is refused.
TEST_CASE("checkpoint: a particle pressed into a wall restarts, one through it is refused",
          "[checkpoint]") {
  for (const double beyond : {0.5, 1.5}) {
    Simulation<2> first;
    scene(first);
    first.advance(10);
    const auto id = first.particle_ids().front();
    // The drum's wall is at 6 mm. set_position refuses a centre beyond a wall,
    // which a run's contact can press a particle to: written into the state.
    StateBlob saved = first.save_state();
    const auto& ids = saved.integers.at("particles.id");
    const auto at = static_cast<std::size_t>(std::find(ids.begin(), ids.end(), id) - ids.begin());
    REQUIRE(at < ids.size());
    const double r = saved.doubles.at("particles.radius").at(at);
    saved.doubles.at("particles.position").at(2 * at) = 6e-3 + beyond * r;
    saved.doubles.at("particles.position").at(2 * at + 1) = 0;
    Simulation<2> again;
    scene(again);
    if (beyond < 1) {
      REQUIRE_NOTHROW(again.load_state(saved));
    } else {
      REQUIRE_THROWS_WITH(again.load_state(saved),
                          Catch::Contains("particles.position") && Catch::Contains("drum"));
    }
  }
}

TEST_CASE("checkpoint: a scene that does not match the checkpoint is refused by name",
          "[checkpoint]") {
  Simulation<2> a;
  scene(a);
  a.advance(10);
  StateBlob state = a.save_state();
  Simulation<2> b;
  b.add_material({"powder", 1200, 0, 0, 0});
  CHECK_THROWS_WITH(b.load_state(state), Catch::Contains("materials"));
  Simulation<3> c;
  CHECK_THROWS_WITH(c.load_state(state), Catch::Contains("2D"));
  CHECK_THROWS_WITH(io::read_checkpoint("/nonexistent/x.h5"), Catch::Contains("no such file"));
}

namespace {
// One damaged copy of a checkpoint, and the entry its refusal must name.
struct Corruption {
  std::string what;  // for the report: "particles.radius[3] = nan"
  std::string key;   // the entry the message must name, quoted
  StateBlob state;
};

// Every entry of a valid checkpoint, damaged one way at a time: left out, one value
// short or over, NaN, -1 or huge where those cannot be, every index table entry just
// out of range. Each must be refused before the engine takes the state.
template <int D>
std::vector<Corruption> corruptions(const StateBlob& valid, double stability_limit) {
  std::vector<Corruption> out;
  auto add = [&](const std::string& what, const std::string& key, StateBlob s) {
    out.push_back({what, key, std::move(s)});
  };
  for (const auto& [k, v] : valid.doubles) {
    StateBlob s = valid;
    s.doubles.erase(k);
    add(k + " (doubles) left out", k, s);
  }
  // canonical_order, guards.wall_overlap_warned and time_step.per_contact may be
  // absent (a checkpoint from before the setting, the warning or the entry: off, not
  // given, found anew); so may rolling_springs (builds that held the rolling
  // springs' torques: refused only where one is wound, test_rolling.cpp).
  for (const auto& [k, v] : valid.integers) {
    if (k == "canonical_order" || k == "guards.wall_overlap_warned" ||
        k == "time_step.per_contact" || k == "rolling_springs")
      continue;
    StateBlob s = valid;
    s.integers.erase(k);
    add(k + " (integers) left out", k, s);
  }
  for (const auto& [k, v] : valid.bytes) {
    StateBlob s = valid;
    s.bytes.erase(k);
    add(k + " left out", k, s);
  }
  for (const auto& [k, v] : valid.texts) {
    StateBlob s = valid;
    s.texts.erase(k);
    add(k + " (text) left out", k, s);
  }
  // Sizes: one short (or one over when empty).
  auto resize = [&](auto&& map, const std::string& k, const StateBlob& base, const char* kind) {
    StateBlob s = base;
    auto& v = map(s).at(k);
    if (v.empty())
      v.push_back({});
    else
      v.pop_back();
    add(k + " (" + kind + ") resized to " + std::to_string(v.size()), k, s);
  };
  for (const auto& [k, v] : valid.doubles)
    resize(
        [](StateBlob & s) -> auto& { return s.doubles; }, k, valid, "doubles");
  for (const auto& [k, v] : valid.integers)
    resize(
        [](StateBlob & s) -> auto& { return s.integers; }, k, valid, "integers");
  for (const auto& [k, v] : valid.bytes)
    resize(
        [](StateBlob & s) -> auto& { return s.bytes; }, k, valid, "bytes");

  auto set_double = [&](const std::string& k, std::size_t e, double x) {
    StateBlob s = valid;
    auto& v = s.doubles.at(k);
    if (e >= v.size()) return;
    v[e] = x;
    add(fmt::format("{}[{}] = {}", k, e, x), k, s);
  };
  auto set_integer = [&](const std::string& k, std::size_t e, std::int64_t x) {
    StateBlob s = valid;
    auto& v = s.integers.at(k);
    if (e >= v.size()) return;
    v[e] = x;
    add(fmt::format("{}[{}] = {}", k, e, x), k, s);
  };
  auto some = [](std::size_t size) {  // the first, a middle and the last element
    return std::vector<std::size_t>{0, size / 2, size ? size - 1 : 0};
  };
  const double nan = std::numeric_limits<double>::quiet_NaN(), huge = 1e300;
  const std::int64_t huge_index = std::int64_t{1} << 40;
  const std::vector<std::string> particle_doubles = {
      "particles.position",   "particles.velocity", "particles.spin",
      "particles.force",      "particles.torque",   "particles.position_at_rebuild",
      "particles.radius",     "particles.mass",     "particles.inv_mass",
      "particles.inv_inertia"};
  // NaN: nowhere.
  for (const auto& [k, v] : valid.doubles) {
    const bool small = k == "meta" || k == "walls" || k == "body" || k == "materials";
    std::vector<std::size_t> at = some(v.size());
    if (small) {
      at.clear();
      for (std::size_t e = 0; e < v.size(); ++e) at.push_back(e);
    }
    for (std::size_t e : at) set_double(k, e, nan);
  }
  // Huge: no particle, wall or body force that far out, no time step that long.
  for (const auto& k : particle_doubles)
    for (std::size_t e : some(valid.doubles.at(k).size())) set_double(k, e, huge);
  for (std::size_t e = 0; e < valid.doubles.at("walls").size(); ++e) set_double("walls", e, huge);
  for (std::size_t e : {1, 2, 3, 5, 6, 7, 8}) set_double("body", e, huge);
  for (std::size_t e : {1, 2, 10}) set_double("meta", e, huge);  // dt, dt set, contact reach
  set_double("meta", 1, 1.01 * stability_limit);  // just above the engine's own limit
  // -1 where values are positive (radius, masses, material properties, time, time step, skin).
  for (const auto& k :
       {"particles.radius", "particles.mass", "particles.inv_mass", "particles.inv_inertia"})
    for (std::size_t e : some(valid.doubles.at(k).size())) set_double(k, e, -1);
  for (std::size_t e = 0; e < valid.doubles.at("materials").size(); ++e)
    set_double("materials", e, -1);
  for (std::size_t e : {0, 1, 2, 3, 4, 5, 6, 10}) set_double("meta", e, -1);
  if (D == 3) set_double("meta", 9, -1);                      // the periodic length, when periodic
  for (std::size_t e : {0, 4, 8}) set_double("body", e, -1);  // flags, central strength
  // Integers: -1 and huge in every table (indices, ids, flags, the header).
  for (const auto& [k, v] : valid.integers) {
    if (k == "meta") continue;
    for (std::size_t e : some(v.size())) {
      set_integer(k, e, -1);
      set_integer(k, e, huge_index);
    }
  }
  for (std::size_t e : {0, 1, 2, 3, 4, 5}) set_integer("meta", e, -1);
  for (std::size_t e : {0, 1, 3, 5}) set_integer("meta", e, huge_index);
  // Every entry of every index table one past its range.
  const auto n = static_cast<std::int64_t>(valid.integers.at("particles.id").size());
  const auto walls = static_cast<std::int64_t>(valid.doubles.at("walls").size() / 10);
  const auto materials = static_cast<std::int64_t>(valid.doubles.at("materials").size() / 4);
  for (const auto& [k, v] : valid.integers) {
    std::int64_t limit = -1;
    auto ends = [&](const char* tail) {
      return k.size() > std::strlen(tail) &&
             k.compare(k.size() - std::strlen(tail), std::string::npos, tail) == 0;
    };
    if (k == "particles.material")
      limit = materials;
    else if (k == "particles.index_of_id")
      limit = n;
    else if (k.rfind("pairs.", 0) == 0 && (ends(".i") || ends(".j")))
      limit = n;
    else if (k.rfind("walls.", 0) == 0 && ends(".particle"))
      limit = n;
    else if (k.rfind("walls.", 0) == 0 && ends(".wall"))
      limit = walls;
    if (limit < 0) continue;
    for (std::size_t e = 0; e < v.size(); ++e) set_integer(k, e, limit);
  }
  // A contact law's value hand-edited into text that is not a number.
  {
    StateBlob s = valid;
    std::string& laws = s.texts.at("contacts");
    const auto eq = laws.find('=');
    laws.replace(eq + 1, laws.find_first_of("\t\n", eq) - eq - 1, "nan");
    add("contacts: a value made 'nan'", "contacts", s);
  }
  return out;
}
}  // namespace

TEMPLATE_TEST_CASE_SIG("checkpoint: every damaged entry is refused with its name",
                       "[checkpoint][corrupt]", ((int D), D), 2, 3) {
  Simulation<D> original;
  scene(original);
  original.advance(3000);
  const std::string path =
      (std::filesystem::temp_directory_path() /
       ("granule_corrupt_" + std::to_string(getpid()) + "_" + std::to_string(D) + ".chk.h5"))
          .string();
  io::write_checkpoint(path, original.save_state());
  const StateBlob valid = io::read_checkpoint(path);  // through the file, as a restart reads it
  std::remove(path.c_str());
  const double limit = original.time_step_rule().stability_limit;
  // The lists hold contacts of both models with particles and walls, so their index
  // tables have entries to damage.
  std::size_t listed = 0;
  for (const auto& [k, v] : valid.integers)
    if (k.rfind("pairs.", 0) == 0 || k.rfind("walls.", 0) == 0) listed += v.size();
  REQUIRE(listed > 100);
  {
    Simulation<D> intact;
    scene(intact);
    REQUIRE_NOTHROW(intact.load_state(valid));
  }
  const auto cases = corruptions<D>(valid, limit);
  REQUIRE(cases.size() > 500);
  std::size_t refused = 0;
  for (const auto& c : cases) {
    Simulation<D> target;
    scene(target);
    std::string message;
    bool input_error = false;
    try {
      target.load_state(c.state);
    } catch (const InputError& e) {
      message = e.what(), input_error = true;
    } catch (const std::exception& e) {
      message = e.what();
    }
    INFO(c.what << ": " << (message.empty() ? "accepted" : message));
    CHECK(input_error);
    CHECK(message.find("'" + c.key + "'") != std::string::npos);
    refused += input_error;
  }
  CHECK(refused == cases.size());
}

TEST_CASE("checkpoint: a periodic scene's central field resumes pulling towards its line",
          "[checkpoint]") {
  // Periodic along z: the field pulls towards the line through its point along z
  // (body_forces.hpp), which the resumed run must know before its first step; a
  // checkpoint taken mid-run resumes without a prepare().
  auto make = [](Simulation<3>& sim, bool field) {
    sim.set_warning_handler([](const std::string&) {});
    sim.add_material({"p", 2500, 0, 0, 0});
    sim.set_contact("p", "p", "linear", {{"k_normal", 1e3}, {"restitution", 0.5}});
    sim.set_periodic(2, 0, 10e-3);
    for (int k = 0; k < 4; ++k) {
      ParticleSpec s;
      s.position = {(k % 2 ? 2e-3 : -2e-3), (k < 2 ? 2e-3 : -2e-3), 1e-3 + 2.5e-3 * k};
      s.velocity = {0, 0, 0.01 * (k - 1.5)};
      s.radius = 0.4e-3, s.material = 0;
      sim.add_particle(s);
    }
    if (field) sim.set_central_field({0, 0, 0}, 50);
    sim.set_time_step(1e-5);
  };
  Simulation<3> whole;
  make(whole, true);
  whole.advance(200);
  const StateBlob blob = whole.save_state();
  whole.advance(300);
  Simulation<3> resumed;
  make(resumed, false);  // the field comes from the checkpoint alone
  resumed.load_state(blob);
  resumed.advance(300);
  CHECK(same_state<3>(whole, resumed));
  for (std::int64_t id = 0; id < 4; ++id) CHECK(whole.velocity(id)[2] == 0.01 * (id - 1.5));
}

namespace {
// One sphere and a square plate of linear contacts; the plate's motion and the
// gravity given.
void plate_scene(Simulation<3>& sim, double plate_z, double plate_speed, double gravity,
                 double k_normal, bool bounded = true) {
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"glass", 2500, 0, 0, 0});
  sim.add_material({"steel", 7800, 0, 0, 0});
  for (const char* other : {"glass", "steel"})
    sim.set_contact("glass", other, "linear", {{"k_normal", k_normal}, {"restitution", 0.5}});
  WallSpec w;
  w.name = "plate", w.material = 1, w.normal = {0, 0, 1}, w.velocity = {0, 0, plate_speed};
  w.point = {0, 0, plate_z}, w.bounded = bounded, w.size_a = w.size_b = 0.01;
  sim.add_wall(w);
  ParticleSpec p;
  p.radius = 1e-3, p.material = 0;
  sim.add_particle(p);
  sim.set_gravity({0, 0, -gravity});
  sim.set_time_step(1e-5);
}
std::string failure_of(Simulation<3>& sim, std::int64_t steps) {
  try {
    sim.advance(steps);
  } catch (const RunError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

// What prepare() notes from the particles and laws, a restart that needs no
// prepare() must know too: the step-over check's smallest free radius, and the
// kind of rule that chose the step (sim:describe()).
TEST_CASE("checkpoint: a restart keeps the step-over check and the time-step rule's kind",
          "[checkpoint]") {
  // A plate at 500 m/s (5 mm a step, five radii) 1 m below: it would step over
  // the sphere about 200 steps on. The whole run stops there; so must a restart
  // from step 100.
  Simulation<3> whole;
  plate_scene(whole, -1.0, 500, 0, 1e4);
  whole.advance(100);
  const StateBlob saved = whole.save_state();
  const std::string stopped = failure_of(whole, 300);
  REQUIRE_THAT(stopped, Catch::Contains("wall 'plate' moves") &&
                            Catch::Contains("more than the smallest free particle's radius"));
  Simulation<3> resumed;
  plate_scene(resumed, -1.0, 500, 0, 1e4);
  resumed.load_state(saved);
  CHECK(failure_of(resumed, 300) == stopped);

  // Hertz-Mindlin's step is 8 T_R / n, not Eq. 4.1's t_c / n: described so after a restart.
  auto hertz = [](Simulation<3>& sim) {
    sim.set_warning_handler([](const std::string&) {});
    sim.add_material({"glass", 2500, 5e7, 0.3, 0});
    sim.set_contact("glass", "glass", "hertz_mindlin", {{"restitution", 0.5}, {"friction", 0.3}});
    for (double x : {0.0, 1.99e-3}) {
      ParticleSpec p;
      p.radius = 1e-3, p.material = 0, p.position = {x, 0, 0};
      sim.add_particle(p);
    }
  };
  Simulation<3> a;
  hertz(a);
  a.advance(10);
  Simulation<3> b;
  hertz(b);
  b.load_state(a.save_state());
  REQUIRE_THAT(fmt::format("{}", fmt::join(a.describe(), "\n")), Catch::Contains("8 T_R / n"));
  CHECK(b.describe() == a.describe());
}

// A run that failed with a particle escaped through a wall (the script caught the
// failure) leaves a state a checkpoint written then must restart from, as the
// whole run went on from it: the next run stops again the same way.
TEST_CASE("checkpoint: the state a failed run left restarts and fails again the same way",
          "[checkpoint]") {
  // A contact far too soft for the load (a static overlap of 10 radii): the sphere
  // sinks through the floor (an infinite plane: one side), and the run stops once
  // its centre is a radius beyond.
  Simulation<3> whole;
  plate_scene(whole, -1e-3, 0, 1000, 1.0, false);
  const std::string failed = failure_of(whole, 2000000);
  REQUIRE_THAT(failed, Catch::Contains("plate"));
  const StateBlob saved = whole.save_state();
  CHECK(saved.integers.count("guards.failed_at_step") == 1);
  Simulation<3> resumed;
  plate_scene(resumed, -1e-3, 0, 1000, 1.0, false);
  REQUIRE_NOTHROW(resumed.load_state(saved));
  const std::string again = failure_of(whole, 10);
  CHECK_FALSE(again.empty());
  CHECK(failure_of(resumed, 10) == again);
  // The same state without the entry is refused, naming the particle's position.
  StateBlob damaged = saved;
  damaged.integers.erase("guards.failed_at_step");
  Simulation<3> refused;
  plate_scene(refused, -1e-3, 0, 1000, 1.0, false);
  CHECK_THROWS_WITH(refused.load_state(damaged),
                    Catch::Contains("particles.position") && Catch::Contains("plate"));
}
