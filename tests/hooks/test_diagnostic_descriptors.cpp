// The diagnostics' option descriptors are the one source of truth for their
// options: every diagnostic reads exactly the options it declares, with the
// declared defaults; the scene's keys are checked against them (nearest-key
// hints); help("diagnostics") and help("<name>") list them.
#include <catch2/catch.hpp>
#include <set>
#include <stdexcept>

#include "hooks/diagnostic.hpp"

using namespace granule;

namespace {
// The options a diagnostic cannot be built without (2D and 3D).
DiagnosticOptions minimal(const std::string& name) {
  DiagnosticOptions o;
  if (name == "wall_force") o.strings["wall"] = "drum";
  if (name == "zones" || name == "gap_profile") o.numbers["depth"] = 1e-3;
  return o;
}

template <int D>
void check_reads_what_it_declares() {
  for (const auto& info : diagnostic_catalogue()) {
    INFO("diagnostic " << info.name << ", " << D << "D");
    DiagnosticOptions o = minimal(info.name);
    o.set_context("diagnostic '" + info.name + "'");
    auto made = make_diagnostic<D>(info.name, o);
    REQUIRE(made);
    std::set<std::string> declared, read(o.read_keys().begin(), o.read_keys().end());
    for (const auto& d : info.options) declared.insert(d.key);
    CHECK(read == declared);
    CHECK(o.declared().size() == info.options.size());
    for (const auto& d : info.options) {
      CHECK(std::string(d.doc).size() > 5);
      CHECK((d.required || std::string(d.key) == "label" || std::string(d.fallback).size() > 0 ||
             std::string(d.key) == "inner_piece"));
    }
  }
}
}  // namespace

TEST_CASE("every diagnostic reads exactly the options it declares, with their defaults",
          "[hooks][descriptors]") {
  REQUIRE(diagnostic_catalogue().size() == 6);
  check_reads_what_it_declares<2>();
  check_reads_what_it_declares<3>();
}

TEST_CASE("a getter for an undeclared option, or with another default, is a programming error",
          "[hooks][descriptors]") {
  DiagnosticOptions o("diagnostic 'x'");
  o.declare({{"window", "s", "0.01", "averaging window"}, {"every", "steps", "10", "period"}});
  CHECK(o.number("window", 0.01) == 0.01);
  CHECK(o.integer("every", 10, 1) == 10);
  CHECK_THROWS_AS(o.number("window", 0.02), std::logic_error);
  CHECK_THROWS_AS(o.integer("every", 1, 1), std::logic_error);
  CHECK_THROWS_AS(o.string("label", "x"), std::logic_error);
}

TEST_CASE("a scene's unknown diagnostic option is refused with the nearest declared key",
          "[hooks][descriptors]") {
  DiagnosticOptions o;
  o.set_context("diagnostic 'overlaps'");
  o.numbers["windw"] = 0.1;
  try {
    make_diagnostic<2>("overlaps", o);
    o.finish();
    FAIL("accepted an unknown option");
  } catch (const InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains("unknown option 'windw'") &&
                             Catch::Contains("did you mean 'window'") &&
                             Catch::Contains("diagnostic 'overlaps'"));
  }
  // A declared option the constructor reads only on some paths is still known.
  DiagnosticOptions ok;
  ok.numbers["window"] = 0.1;
  make_diagnostic<2>("overlaps", ok);
  CHECK_NOTHROW(ok.finish());
}

TEST_CASE("help lists each diagnostic's options from its descriptors", "[hooks][descriptors]") {
  const std::string all = diagnostics_help("diagnostics", false);
  for (const auto& info : diagnostic_catalogue()) {
    CHECK_THAT(all, Catch::Contains(info.name));
    const std::string one = diagnostics_help(info.name, false);
    CHECK_THAT(one, Catch::Contains(info.doc));
    for (const auto& d : info.options) {
      CHECK_THAT(one, Catch::Contains(d.key) && Catch::Contains(d.doc));
      CHECK_THAT(one, Catch::Contains(d.required ? std::string("required")
                                                 : "'" + std::string(d.fallback) + "'"));
    }
    const std::string md = diagnostics_help("diagnostics", true);
    CHECK_THAT(md, Catch::Contains("### `" + info.name + "`"));
  }
  CHECK_THAT(diagnostics_help("zones", false), Catch::Contains("depth") && Catch::Contains("m "));
  CHECK(diagnostics_help("no_such_diagnostic", false).empty());
  CHECK(diagnostics_help("sim:run", false).empty());
}

TEST_CASE("the shared trigger: every_time samples the step nearest each multiple of T",
          "[hooks][descriptors]") {
  const double dt = 1e-4, T = 3.3e-3;  // T is 33 steps
  DiagnosticOptions o("diagnostic 'x'");
  o.numbers["every_time"] = T;
  Sampling s;
  s.read(o, {10, 0.01});
  CHECK(s.period() == 1);
  std::vector<int> due;
  for (int n = 0; n < 1000; ++n)
    if (s.due(n * dt, dt)) due.push_back(n);
  // Step k * 33 is nearest k T (the multiples fall on steps exactly, to round-off).
  REQUIRE(due.size() == 31);  // k = 0 .. 30 (30 T = 0.099 s, step 990)
  for (std::size_t k = 0; k < due.size(); ++k) CHECK(std::abs(due[k] - 33 * int(k)) <= 1);
  // T below the step: every step.
  DiagnosticOptions fast("diagnostic 'x'");
  fast.numbers["every_time"] = dt / 3;
  Sampling f;
  f.read(fast, {10, 0.01});
  for (int n = 0; n < 50; ++n) CHECK(f.due(n * dt, dt));
  // Both triggers at once: refused by name.
  DiagnosticOptions both("diagnostic 'x'");
  both.numbers["every_time"] = T, both.numbers["every"] = 5;
  Sampling b;
  CHECK_THROWS_WITH(b.read(both, {10, 0.01}),
                    Catch::Contains("'every'") && Catch::Contains("'every_time'"));
}

// Windows keep their length on average when the sample period does not divide
// it: sampled every 3 steps from step 3, 10-step windows are due to end at
// steps 13, 23, 33, ... and close at 15, 24, 33, ... (a window starts where
// the last was due to end), not at 15, 27, 39, ... (where the last closed).
TEST_CASE("the shared window: its length on average whatever the sample period",
          "[hooks][descriptors]") {
  const double dt = 1e-4;
  DiagnosticOptions o("diagnostic 'x'");
  o.numbers["every"] = 3;
  o.numbers["window"] = 10 * dt;
  Sampling s;
  s.read(o, {10, 0.01});
  std::vector<double> closed;
  for (int n = 3; n <= 3000; n += 3) {
    const double t = n * dt;
    s.note(t);
    if (s.full(t, dt)) closed.push_back(t), s.close(t, false);
  }
  // The k-th window closes at the first sample at or past its due end, 3 + 10 k steps.
  REQUIRE(closed.size() >= 290);
  for (std::size_t k = 0; k < closed.size(); ++k) {
    const double due = (3 + 10.0 * static_cast<double>(k + 1)) * dt;
    INFO("window " << k << " closed at " << closed[k] << " s, due at " << due << " s");
    CHECK(closed[k] >= due - 0.5 * dt);
    CHECK(closed[k] < due + 3 * dt - 0.5 * dt);
  }
  // A flush (a run's end) cuts a window short: the next starts at its last sample.
  s.note(3003 * dt);
  s.close(3003 * dt, true);
  s.note(3006 * dt);
  CHECK_FALSE(s.full(3006 * dt, dt));
  CHECK(s.full(3013 * dt, dt));
}
