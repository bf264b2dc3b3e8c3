// A checkpoint keeps the last step's results that a script reads between runs
// (Simulation::save_last_step): the recorded contacts, the walls' reactions and
// stats()' tallies read the same from a loaded state as from the state saved,
// in 2D and 3D; damaged entries are refused by name, and a checkpoint without
// them (an older build's) loads as before any step.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "engine/simulation.hpp"

using namespace granule;

namespace {
constexpr double r = 1e-3;

// A column of three spheres (disks) pressed onto a floor by gravity: pair and
// wall contacts from the first step, contact forces recorded.
template <int D>
void column(Simulation<D>& sim) {
  sim.set_warning_handler([](const std::string&) {});
  sim.set_record_contacts(true);
  sim.add_material({"glass", 2500, 0, 0, 0});
  sim.add_material({"steel", 0, 0, 0, 0});
  const ParamValues law{{"k_normal", 1e3}, {"restitution", 0.5}, {"friction", 0.3}};
  sim.set_contact("glass", "glass", "linear", law);
  sim.set_contact("glass", "steel", "linear", law);
  WallSpec w;
  w.name = "floor", w.material = 1;
  w.normal = D == 3 ? Triple{0, 0, 1} : Triple{0, 1, 0};
  w.point = {0, 0, 0};
  sim.add_wall(w);
  // Each sphere just touching the one below, slightly off the vertical, so that
  // friction and the tangential forces act.
  const double step_aside = 0.05 * r, step_up = std::sqrt(4 * r * r - step_aside * step_aside);
  for (int k = 0; k < 3; ++k) {
    ParticleSpec s;
    s.radius = r, s.material = 0;
    const double height = (r + step_up * k) * (1 - 1e-7), aside = step_aside * k;
    s.position = D == 3 ? Triple{aside, 0, height} : Triple{aside, height, 0};
    sim.add_particle(s);
  }
  sim.set_gravity(D == 3 ? Triple{0, 0, -9.81} : Triple{0, -9.81, 0});
  sim.set_time_step(1e-6);
}

void same_contacts(const std::vector<ContactRecord>& a, const std::vector<ContactRecord>& b) {
  REQUIRE(a.size() == b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    CHECK(a[k].id_a == b[k].id_a);
    CHECK(a[k].id_b == b[k].id_b);
    CHECK(a[k].wall == b[k].wall);
    CHECK(a[k].model == b[k].model);
    CHECK(a[k].overlap == b[k].overlap);
    CHECK(a[k].normal_force == b[k].normal_force);
    CHECK(a[k].tangential_force == b[k].tangential_force);
    CHECK(a[k].normal == b[k].normal);
  }
}
}  // namespace

TEMPLATE_TEST_CASE_SIG("last step: a checkpoint keeps the contacts, reactions and tallies",
                       "[checkpoint][last_step]", ((int D), D), 2, 3) {
  Simulation<D> sim;
  column(sim);
  sim.advance(2000);
  const StateBlob saved = sim.save_state();
  const auto contacts = sim.contacts();
  REQUIRE(contacts.size() == 3);  // two pairs and the floor
  REQUIRE(sim.wall_force(0)[D - 1] < 0);

  Simulation<D> resumed;
  column(resumed);
  resumed.load_state(saved);
  same_contacts(resumed.contacts(), contacts);
  CHECK(resumed.wall_force(0) == sim.wall_force(0));
  CHECK(resumed.wall_axial_torque(0) == sim.wall_axial_torque(0));
  const GlobalStats a = sim.stats(), b = resumed.stats();
  CHECK(b.contacts_particle == a.contacts_particle);
  CHECK(b.contacts_batched == a.contacts_batched);
  CHECK(b.contacts_wall == a.contacts_wall);
  CHECK(b.contacts_wall_batched == a.contacts_wall_batched);
  CHECK(b.max_overlap_ratio == a.max_overlap_ratio);
  CHECK(b.pair_list_prunes == a.pair_list_prunes);
  CHECK(b.pair_candidates_visited == a.pair_candidates_visited);
  CHECK(b.thread_rebalances == a.thread_rebalances);
  // And the next step is the whole run's.
  sim.advance(10), resumed.advance(10);
  same_contacts(resumed.contacts(), sim.contacts());
  CHECK(resumed.wall_force(0) == sim.wall_force(0));

  // A particle removed after the load leaves the saved contacts as it leaves the log's.
  Simulation<D> removed;
  column(removed);
  removed.load_state(saved);
  removed.remove_particle(2);
  for (const ContactRecord& c : removed.contacts()) CHECK((c.id_a != 2 && c.id_b != 2));
  CHECK(removed.contacts().size() == 2);

  // An older build's checkpoint: no last step, read as before any step.
  StateBlob older = saved;
  for (const char* key :
       {"last_step.max_overlap_ratio", "last_step.wall_reactions", "last_step.contacts"})
    older.doubles.erase(key);
  older.integers.erase("last_step.tallies"), older.integers.erase("last_step.contacts");
  older.texts.erase("last_step.contact_models");
  Simulation<D> old;
  column(old);
  old.load_state(older);
  CHECK(old.contacts().empty());
  CHECK(old.stats().contacts_particle == 0);
  CHECK(old.wall_force(0) == Triple{0, 0, 0});
}

TEST_CASE("last step: damaged entries are refused by name", "[checkpoint][last_step]") {
  Simulation<3> sim;
  column(sim);
  sim.advance(500);
  const StateBlob saved = sim.save_state();
  auto refused = [&](const StateBlob& damaged, const std::string& key) {
    Simulation<3> other;
    column(other);
    CHECK_THROWS_WITH(other.load_state(damaged), Catch::Contains("'" + key + "'"));
  };
  {
    StateBlob d = saved;
    d.integers["last_step.tallies"][2] = -1;
    refused(d, "last_step.tallies");
    d.integers["last_step.tallies"] = {1, 2};
    refused(d, "last_step.tallies");
  }
  {
    StateBlob d = saved;
    d.doubles["last_step.max_overlap_ratio"] = {NAN};
    refused(d, "last_step.max_overlap_ratio");
  }
  {
    StateBlob d = saved;
    d.doubles["last_step.wall_reactions"][1] = INFINITY;
    refused(d, "last_step.wall_reactions");
    d.doubles["last_step.wall_reactions"].pop_back();
    refused(d, "last_step.wall_reactions");
  }
  {
    StateBlob d = saved;
    d.integers["last_step.contacts"][0] = 99;  // no such particle
    refused(d, "last_step.contacts");
    d = saved;
    d.integers["last_step.contacts"][3] = 5;  // no such model in the list
    refused(d, "last_step.contacts");
    d = saved;
    d.doubles["last_step.contacts"][1] = NAN;
    refused(d, "last_step.contacts");
    d = saved;
    d.doubles["last_step.contacts"].pop_back();
    refused(d, "last_step.contacts");
    d = saved;
    d.texts["last_step.contact_models"] = "no_such_law\n";
    refused(d, "last_step.contact_models");
  }
}

TEST_CASE("last step: without recorded contacts, and after a removal between runs",
          "[checkpoint][last_step]") {
  // Not recording: the tallies and reactions travel, no contacts.
  Simulation<3> plain;
  column(plain);
  plain.set_record_contacts(false);
  plain.advance(2000);
  const StateBlob unrecorded = plain.save_state();
  CHECK(unrecorded.integers.count("last_step.contacts") == 0);
  Simulation<3> resumed;
  column(resumed);
  resumed.set_record_contacts(false);
  resumed.load_state(unrecorded);
  CHECK(resumed.stats().contacts_particle == plain.stats().contacts_particle);
  CHECK(resumed.stats().contacts_particle == 2);
  CHECK(resumed.wall_force(0) == plain.wall_force(0));
  CHECK_THROWS_AS(resumed.contacts(), InputError);  // not recorded: refused as before

  // Recording, a particle removed between runs: the checkpoint holds the contacts
  // left (kept by id), which a restart reads as the whole run does.
  Simulation<3> sim;
  column(sim);
  sim.advance(2000);
  sim.remove_particle(2);
  const auto left = sim.contacts();
  REQUIRE(left.size() == 2);
  Simulation<3> again;
  column(again);
  again.load_state(sim.save_state());
  same_contacts(again.contacts(), left);
}
