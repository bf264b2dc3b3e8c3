// Checkpoints: a run saved at step K, written to disk, read back into a freshly
// declared scene and continued is bit-identical to the run that never stopped.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/errors.hpp"
#include "core/simulation.hpp"
#include "io/checkpoint.hpp"

using namespace granule;

namespace {
// A rotating drum with a stationary post, Walton-Braun with friction and a
// Thornton pair for a second material: histories of two models and walls.
template <int D>
void scene(Simulation<D>& sim) {
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"powder", 1200, 0, 0, 0});
  sim.add_material({"glass", 2650, 70e6, 0.3, 0});  // soft: a larger Rayleigh step
  sim.add_material({"steel", 7800, 200e6, 0.3, 0});
  ParamValues wb{{"k_load", 2e4}, {"restitution", 0.85}, {"friction", 0.4}};
  sim.set_contact("powder", "powder", "walton_braun", wb);
  sim.set_contact("powder", "steel", "walton_braun", wb);
  sim.set_contact("powder", "glass", "walton_braun", wb);
  sim.set_contact("glass", "glass", "thornton_elastic", {{"friction", 0.3}});
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
