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
