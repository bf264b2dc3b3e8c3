// Diagnostics' accumulators in checkpoints (SimulationBase::save_diagnostics /
// load_diagnostics, Diagnostic<D>::save_state / load_state): for every
// diagnostic in the registry, a run saved in the middle of an averaging
// window and continued in a fresh scene reports bit for bit what the run that
// never stopped reports (results, arrays and the rows it writes), and a
// checkpoint that cannot be continued (a missing or wrongly sized entry,
// other diagnostics or options, an older checkpoint) is refused by name.
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <random>
#include <set>

#include "engine/simulation.hpp"
#include "hooks/diagnostic.hpp"

using namespace granule;

namespace {
constexpr double R = 12.5e-3, r = 0.2e-3;

// Everything a diagnostic writes, by group.
struct RecordingSink final : OutputSink {
  std::map<std::string, std::vector<std::string>> columns;
  std::map<std::string, std::vector<std::vector<double>>> rows;
  std::map<std::string, std::vector<double>> attributes;  // "group@name"
  std::map<std::string, std::string> texts;
  void declare_series(const std::string& g, const std::vector<std::string>& c) override {
    columns[g] = c;
  }
  void append_series(const std::string& g, const std::vector<double>& row) override {
    rows[g].push_back(row);
  }
  void write_attribute(const std::string& g, const std::string& n, double v) override {
    attributes[g + "@" + n] = {v};
  }
  void write_attribute(const std::string& g, const std::string& n, const std::string& v) override {
    texts[g + "@" + n] = v;
  }
  void write_attribute(const std::string& g, const std::string& n,
                       const std::vector<double>& v) override {
    attributes[g + "@" + n] = v;
  }
};

// A spinning chamber with an inner piece and a ring of particles near the
// wall, moving at random: contacts begin and end every few steps, against
// each other, the chamber and the inner piece, in all four areas.
std::unique_ptr<Simulation<2>> scene(bool prepared = true) {
  auto sim = std::make_unique<Simulation<2>>();
  sim->set_warning_handler([](const std::string&) {});
  sim->add_material({"powder", 1200, 0, 0, 0});
  sim->add_material({"steel", 7800, 0, 0, 0});
  ParamValues law{{"k_load", 2e4}, {"restitution", 0.85}, {"friction", 0.4}};
  sim->set_contact("powder", "powder", "walton_braun", law);
  sim->set_contact("powder", "steel", "walton_braun", law);
  WallSpec c;
  c.name = "chamber", c.type = WallType::cylinder, c.material = 1, c.radius = R;
  c.angular_velocity = 200;
  sim->add_wall(c);
  WallSpec in;
  in.name = "inner_piece", in.type = WallType::cylinder, in.material = 1, in.radius = 5e-3;
  in.center = {5.9e-3, 0, 0}, in.inside = false;
  sim->add_wall(in);
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> speed(-1.5, 1.5);
  const double spacing = 2 * r + 40e-6;
  for (double x = -R; x <= R; x += spacing)
    for (double y = -R; y <= R; y += spacing) {
      const double l = std::hypot(x, y);
      if (l < 9.5e-3 || l > R - r - 20e-6) continue;
      if (std::hypot(x - 5.9e-3, y) < 5e-3 + r + 20e-6) continue;
      ParticleSpec s;
      s.position = {x, y, 0}, s.velocity = {speed(random), speed(random), 0};
      s.radius = r, s.material = 0;
      sim->add_particle(s);
    }
  if (prepared) sim->prepare();
  return sim;
}

// Options that make each diagnostic accumulate within the test's few
// thousand steps: windows of `window` seconds, sampling off step 1.
DiagnosticOptions options_for(const std::string& name, double window) {
  DiagnosticOptions o;
  o.numbers["window"] = window;
  if (name == "wall_force") {
    o.strings["wall"] = "inner_piece";
    o.numbers["every"] = 2;
  } else if (name == "zones") {
    o.numbers["every"] = 3;
    o.numbers["zones"] = 5;
  } else if (name == "areas") {
    o.numbers["every"] = 3;
  } else if (name == "contact_peaks") {
    o.numbers["force_max"] = 0.02;
    o.numbers["velocity_max"] = 2;
    o.numbers["keep_collisions"] = 100000;
  } else if (name == "gap_profile") {
    o.numbers["every"] = 2;
    o.numbers["sector"] = 30;
    o.numbers["bins"] = 4;
  } else if (name == "overlaps") {
    o.numbers["every"] = 3;
  } else {
    FAIL("give options_for() a setting that makes diagnostic '" << name << "' accumulate");
  }
  return o;
}

struct Run {
  std::unique_ptr<Simulation<2>> sim;
  RecordingSink sink;
  std::vector<int> ids;
  Run(const std::vector<std::string>& names, double window, bool prepared = true)
      : sim(scene(prepared)) {
    sim->set_output_sink(&sink);
    attach(names, window);
  }
  void attach(const std::vector<std::string>& names, double window) {
    for (const auto& n : names) {
      auto o = options_for(n, window);
      ids.push_back(sim->attach_diagnostic(n, o));
    }
  }
};

double time_step() {
  static const double dt = scene()->time_step();
  return dt;
}

constexpr std::int64_t n1 = 1100, n2 = 900;
// 170.5 steps: the checkpoint after n1 steps falls inside the seventh window.
double window() {
  return 170.5 * time_step();
}

StateBlob checkpoint_after(Run& run, std::int64_t steps) {
  run.sim->advance(steps);
  StateBlob blob = run.sim->save_state();
  run.sim->save_diagnostics(blob);
  return blob;
}

std::vector<std::string> catalogue_names() {
  std::vector<std::string> names;
  for (const auto& d : diagnostic_catalogue()) names.push_back(d.name);
  return names;
}

// A (uninterrupted) against B (saved after n1 steps) then C (a fresh scene
// continued from B's checkpoint for n2 steps). C attaches its diagnostics
// before or after loading the particles' state (which keeps the contact
// tracking only if something tracks events when it loads).
void require_restart_matches(const std::vector<std::string>& names, bool attach_after_load) {
  Run a(names, window());
  a.sim->advance(n1 + n2);
  a.sim->flush_diagnostics();

  Run b(names, window());
  const StateBlob blob = checkpoint_after(b, n1);
  Run c(attach_after_load ? std::vector<std::string>{} : names, window());
  c.sim->load_state(blob);
  if (attach_after_load) c.attach(names, window());
  c.sim->load_diagnostics(blob);
  c.sim->advance(n2);
  c.sim->flush_diagnostics();

  // Without the diagnostics' state the continued run reports something else:
  // the comparison below can see a lost accumulator.
  Run lost(names, window());
  lost.sim->load_state(blob);
  lost.sim->advance(n2);
  lost.sim->flush_diagnostics();

  REQUIRE(c.sim->time() == a.sim->time());
  for (std::size_t k = 0; k < names.size(); ++k) {
    INFO("diagnostic " << names[k]);
    const auto results = a.sim->diagnostic_results(a.ids[k]);
    const auto arrays = a.sim->diagnostic_arrays(a.ids[k]);
    CHECK(c.sim->diagnostic_results(c.ids[k]) == results);
    CHECK(c.sim->diagnostic_arrays(c.ids[k]) == arrays);
    CHECK(lost.sim->diagnostic_results(lost.ids[k]) != results);
  }
  // The rows: B's before the checkpoint, then C's, are A's; and B left a
  // window open (its last row is older than the checkpoint).
  REQUIRE(!a.sink.rows.empty());
  CHECK(c.sink.columns == a.sink.columns);
  CHECK(c.sink.attributes == a.sink.attributes);
  CHECK(c.sink.texts == a.sink.texts);
  for (const auto& [group, rows] : a.sink.rows) {
    INFO("series " << group);
    auto joined = b.sink.rows[group];
    REQUIRE(!joined.empty());
    CHECK(joined.back()[0] < b.sim->time());
    const auto& after = c.sink.rows[group];
    joined.insert(joined.end(), after.begin(), after.end());
    CHECK(joined == rows);
  }
}
}  // namespace

TEST_CASE("diagnostics' state: each diagnostic restarted mid-window reports as if never stopped",
          "[diagnostics][checkpoint]") {
  const auto names = catalogue_names();
  REQUIRE(names.size() >= 4);
  for (const auto& name : names) {
    INFO("diagnostic " << name);
    require_restart_matches({name}, false);
    require_restart_matches({name}, true);
  }
}

TEST_CASE("diagnostics' state: all diagnostics at once, each under its own prefix",
          "[diagnostics][checkpoint]") {
  require_restart_matches(catalogue_names(), false);
}

TEST_CASE("diagnostics' state: a missing or wrongly sized entry is refused by its key",
          "[diagnostics][checkpoint]") {
  // wall_force's long-time force vector: checkpoints written before it was kept lack it.
  const std::set<std::string> optional_entries{"diagnostics.0.sum_total"};
  for (const auto& name : catalogue_names()) {
    INFO("diagnostic " << name);
    Run b({name}, window());
    const StateBlob blob = checkpoint_after(b, n1);
    Run c({name}, window());
    c.sim->load_state(blob);
    int entries = 0;
    auto each_key = [&](auto& map_of, auto change) {
      for (const auto& entry : map_of(blob)) {
        const std::string& key = entry.first;
        if (key.rfind("diagnostics.0.", 0) != 0) continue;
        INFO("key " << key);
        StateBlob bad = blob;
        change(map_of(bad), key);
        // Entries that older checkpoints lack load without them (a test below).
        if (optional_entries.count(key) && map_of(bad).count(key) == 0) continue;
        CHECK_THROWS_WITH(c.sim->load_diagnostics(bad), Catch::Contains(key));
        ++entries;
      }
    };
    auto doubles = [](auto& s) -> auto& {
      return s.doubles;
    };
    auto integers = [](auto& s) -> auto& {
      return s.integers;
    };
    auto texts = [](auto& s) -> auto& {
      return s.texts;
    };
    auto erase = [](auto& m, const std::string& key) { m.erase(key); };
    auto grow = [](auto& m, const std::string& key) { m[key].push_back(0); };
    each_key(doubles, erase);
    each_key(integers, erase);
    each_key(texts, erase);
    each_key(doubles, grow);
    each_key(integers, grow);
    CHECK(entries > 4);
    // The untouched checkpoint loads.
    c.sim->load_diagnostics(blob);
    c.sim->advance(1);
  }
}

TEST_CASE("diagnostics' state: other diagnostics, other options or an older checkpoint are refused",
          "[diagnostics][checkpoint]") {
  const auto names = catalogue_names();
  Run b({"areas"}, window());
  const StateBlob blob = checkpoint_after(b, n1);
  {  // another diagnostic
    Run c({"zones"}, window());
    c.sim->load_state(blob);
    CHECK_THROWS_WITH(c.sim->load_diagnostics(blob),
                      Catch::Contains("(areas) differ from the scene's (zones)"));
  }
  {  // one more
    Run c({"areas", "zones"}, window());
    c.sim->load_state(blob);
    CHECK_THROWS_WITH(c.sim->load_diagnostics(blob), Catch::Contains("(areas, zones)"));
  }
  {  // none attached now
    Run c({}, window());
    c.sim->load_state(blob);
    CHECK_THROWS_WITH(c.sim->load_diagnostics(blob),
                      Catch::Contains("(areas) differ from the scene's (none)"));
  }
  {  // the same diagnostic with another window
    Run c({}, window());
    auto o = options_for("areas", 2 * window());
    c.sim->attach_diagnostic("areas", o);
    c.sim->load_state(blob);
    CHECK_THROWS_WITH(c.sim->load_diagnostics(blob),
                      Catch::Contains("diagnostic 'areas' was attached with other options"));
  }
  {  // a checkpoint from before diagnostics were saved
    StateBlob old = b.sim->save_state();
    Run c({"areas"}, window());
    c.sim->load_state(old);
    CHECK_THROWS_WITH(c.sim->load_diagnostics(old),
                      Catch::Contains("no diagnostics' state") && Catch::Contains("areas"));
    Run none({}, window());
    none.sim->load_state(old);
    CHECK_NOTHROW(none.sim->load_diagnostics(old));
  }
  {  // the diagnostics' state before the particles': the contact lists are not there yet
    Run c({"areas"}, window(), false);
    CHECK_THROWS_WITH(c.sim->load_diagnostics(blob), Catch::Contains("load_state()"));
  }
}

TEST_CASE(
    "diagnostics' state: a wall_force checkpoint without the force vector loads, the "
    "vector's mean counting from the restart",
    "[diagnostics][checkpoint]") {
  Run b({"wall_force"}, window());
  StateBlob blob = checkpoint_after(b, n1);
  REQUIRE(blob.doubles.count("diagnostics.0.sum_total") == 1);
  blob.doubles.erase("diagnostics.0.sum_total");  // as an older checkpoint
  Run c({"wall_force"}, window());
  c.sim->load_state(blob);
  c.sim->load_diagnostics(blob);
  // The same continuation with a diagnostic attached fresh at the restart:
  // its vector means are those of the older checkpoint's continuation.
  Run fresh({}, window());
  fresh.sim->load_state(blob);
  fresh.attach({"wall_force"}, window());
  c.sim->advance(n2);
  fresh.sim->advance(n2);
  b.sim->advance(n2);
  const auto old = c.sim->diagnostic_results(c.ids[0]);
  const auto restarted = fresh.sim->diagnostic_results(fresh.ids[0]);
  const auto whole = b.sim->diagnostic_results(b.ids[0]);
  CHECK(old.at("mean_force_x") == restarted.at("mean_force_x"));
  CHECK(old.at("mean_force_y") == restarted.at("mean_force_y"));
  CHECK(old.at("mean_force_x") != whole.at("mean_force_x"));
  // The scalar means are kept whole.
  CHECK(old.at("mean_normal_force") == whole.at("mean_normal_force"));
  CHECK(old.at("samples") == whole.at("samples"));
}

TEST_CASE("diagnostics: the group's attributes say the trigger, by steps or by time",
          "[diagnostics]") {
  for (const std::string name : {"wall_force", "zones", "areas", "gap_profile", "overlaps"}) {
    INFO("diagnostic " << name);
    for (const bool by_time : {false, true}) {
      INFO("by time " << by_time);
      auto sim = scene();
      RecordingSink sink;
      sim->set_output_sink(&sink);
      DiagnosticOptions o = options_for(name, 1e-4);
      const double every_time = 7 * sim->time_step();
      if (by_time) {
        o.numbers.erase("every");
        o.numbers["every_time"] = every_time;
      }
      const double steps = by_time ? 0 : o.numbers.at("every");
      sim->attach_diagnostic(name, o);
      sim->advance(30);  // zones declares its series at its first sample
      std::string group;
      for (const auto& [key, value] : sink.attributes)
        if (key.size() > 7 && key.compare(key.size() - 7, 7, "@window") == 0)
          group = key.substr(0, key.size() - 7);
      REQUIRE(!group.empty());
      CHECK(sink.attributes.at(group + "@window") == std::vector<double>{1e-4});
      CHECK(sink.attributes.at(group + "@every_steps") == std::vector<double>{steps});
      CHECK(sink.attributes.at(group + "@every_time") ==
            std::vector<double>{by_time ? every_time : 0.0});
    }
  }
}
