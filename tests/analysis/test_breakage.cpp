// Fragment labelling and breakage measures of dissertation 7.4 on hand-built
// contact graphs, where the answer can be counted by eye.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

#include "analysis/breakage.hpp"

using namespace granule::analysis;

namespace {

// The partition of ids into fragments, as a set of sets (labels are arbitrary
// names; the partition is what the contact graph determines).
std::set<std::set<std::int64_t>> partition(const Fragments& f) {
  std::map<int, std::set<std::int64_t>> by_label;
  for (std::size_t k = 0; k < f.ids.size(); ++k) by_label[f.label[k]].insert(f.ids[k]);
  std::set<std::set<std::int64_t>> out;
  for (auto& [label, members] : by_label) out.insert(members);
  return out;
}

}  // namespace

TEST_CASE("bonds are ordered, sorted and counted once", "[breakage]") {
  auto b = normalized_bonds({{5, 2}, {2, 5}, {1, 3}, {3, 1}, {0, 9}});
  REQUIRE(b.size() == 3);
  CHECK(b[0] == Bond{0, 9});
  CHECK(b[1] == Bond{1, 3});
  CHECK(b[2] == Bond{2, 5});
  CHECK_THROWS_WITH(normalized_bonds({{4, 4}}), Catch::Contains("bonded to itself"));
  CHECK_THROWS_WITH(normalized_bonds({{-1, 4}}), Catch::Contains(">= 0"));
}

TEST_CASE("union-find joins exactly what is united", "[breakage]") {
  DisjointSets s(6);
  s.unite(0, 1);
  s.unite(2, 3);
  s.unite(1, 3);
  CHECK(s.find(0) == s.find(2));
  CHECK(s.find(4) != s.find(0));
  CHECK(s.find(4) != s.find(5));
  s.unite(4, 5);
  s.unite(5, 4);  // again: no change
  CHECK(s.find(4) == s.find(5));
  CHECK(s.find(4) != s.find(3));
}

TEST_CASE("fragments are the connected clusters of the contact graph", "[breakage]") {
  // Ids 10..18: a triangle (10, 11, 12), a chain 13-14-15-16, a pair (17, 18)
  // and a bond to particle 99 that is not analysed (a host particle).
  const std::vector<std::int64_t> ids{10, 11, 12, 13, 14, 15, 16, 17, 18};
  const std::vector<double> masses{1, 1, 1, 1, 1, 1, 1, 5, 0.5};
  const auto bonds = normalized_bonds(
      {{10, 11}, {11, 12}, {12, 10}, {13, 14}, {15, 14}, {15, 16}, {17, 18}, {12, 99}});
  const Fragments f = find_fragments(ids, masses, bonds);
  REQUIRE(f.count() == 3);
  CHECK(partition(f) == std::set<std::set<std::int64_t>>{{10, 11, 12}, {13, 14, 15, 16}, {17, 18}});
  // Heaviest first: the pair (5.5), the chain (4), the triangle (3).
  CHECK(f.mass == std::vector<double>{5.5, 4, 3});
  CHECK(f.members == std::vector<std::int64_t>{2, 4, 3});
  CHECK(f.label[7] == 0);  // id 17
  CHECK(f.label[3] == 1);  // id 13
  CHECK(f.label[0] == 2);  // id 10
}

TEST_CASE("an isolated primary is a fragment of its own, equal masses order by lowest id",
          "[breakage]") {
  const std::vector<std::int64_t> ids{7, 3, 5, 1};
  const Fragments f = find_fragments(ids, {1, 1, 1, 1}, normalized_bonds({{3, 7}}));
  REQUIRE(f.count() == 3);
  CHECK(f.label[0] == 0);  // {3, 7}, mass 2
  CHECK(f.label[1] == 0);
  CHECK(f.label[3] == 1);  // {1}
  CHECK(f.label[2] == 2);  // {5}
  CHECK(f.members == std::vector<std::int64_t>{2, 1, 1});
}

TEST_CASE("cluster labelling agrees with a breadth-first search on random graphs", "[breakage]") {
  std::mt19937_64 rng(42);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 150;
    std::vector<std::int64_t> ids(n);
    std::vector<double> masses(n);
    for (int k = 0; k < n; ++k) ids[k] = 1000 + 3 * k, masses[k] = 1 + (k % 7);
    std::vector<Bond> raw;
    std::uniform_int_distribution<int> pick(0, n - 1);
    for (int e = 0; e < 120; ++e) {
      int a = pick(rng), b = pick(rng);
      if (a != b) raw.push_back({ids[a], ids[b]});
    }
    const auto bonds = normalized_bonds(raw);
    // Breadth-first search over an adjacency list.
    std::map<std::int64_t, std::vector<std::int64_t>> adjacent;
    for (const Bond& b : bonds) adjacent[b.a].push_back(b.b), adjacent[b.b].push_back(b.a);
    std::set<std::set<std::int64_t>> expected;
    std::set<std::int64_t> seen;
    for (std::int64_t start : ids) {
      if (seen.count(start)) continue;
      std::set<std::int64_t> component{start};
      std::vector<std::int64_t> queue{start};
      seen.insert(start);
      while (!queue.empty()) {
        std::int64_t x = queue.back();
        queue.pop_back();
        for (std::int64_t y : adjacent[x])
          if (seen.insert(y).second) component.insert(y), queue.push_back(y);
      }
      expected.insert(component);
    }
    const Fragments f = find_fragments(ids, masses, bonds);
    CHECK(partition(f) == expected);
    CHECK(std::is_sorted(f.mass.rbegin(), f.mass.rend()));
  }
}

TEST_CASE("damage and debris ratios of a hand-built fragment set (7.4)", "[breakage]") {
  // Initial agglomerate: 1000 kg in total (units do not matter). After the
  // test: one large fragment (600 kg, 60 %), one medium (50 kg, 5 %), two
  // small (20 kg = 2 % and 1 kg = 0.1 %, the latter also fines), and 329 kg
  // of primaries no longer analysed (e.g. counted elsewhere) - only the
  // fragments given are classified, against the initial mass.
  Fragments f;
  f.ids = {1, 2, 3, 4, 5, 6};
  f.label = {0, 0, 1, 2, 3, 3};
  f.mass = {600, 50, 20, 1};
  f.members = {2, 1, 1, 2};
  // 10 initial bonds; now 6 of them remain and 2 new contacts have formed.
  std::vector<Bond> initial, now;
  for (int k = 0; k < 10; ++k) initial.push_back({k, k + 100});
  for (int k = 0; k < 6; ++k) now.push_back({k, k + 100});
  now.push_back({50, 60});
  now.push_back({51, 61});
  initial = normalized_bonds(initial);
  now = normalized_bonds(now);
  const BreakageSummary s = summarize_breakage(initial, now, f, 1000.0);
  CHECK(s.initial_bonds == 10);
  CHECK(s.bonds == 8);
  CHECK(s.broken_bonds == 4);
  CHECK(s.new_bonds == 2);
  CHECK(s.damage_ratio == Approx(0.4));  // broken / initial, not 1 - now / initial
  CHECK(s.debris_mass == Approx(21));
  CHECK(s.debris_ratio == Approx(0.021));
  CHECK(s.fines_ratio == Approx(0.001));
  CHECK(s.largest_fraction == Approx(0.6));
  CHECK(s.fragments == 4);
  CHECK(s.large == 1);
  CHECK(s.medium == 1);
  CHECK(s.small == 2);
  CHECK(s.fines == 1);
  CHECK(s.singles == 2);
}

TEST_CASE("class boundaries: exactly 10 % is medium, exactly 2.5 % is not debris", "[breakage]") {
  Fragments f;
  f.ids = {1, 2, 3};
  f.label = {0, 1, 2};
  f.mass = {100, 25, 2};  // of 1000: 10 %, 2.5 %, 0.2 %
  f.members = {1, 1, 1};
  const BreakageSummary s = summarize_breakage({}, {}, f, 1000.0);
  CHECK(s.large == 0);
  CHECK(s.medium == 2);
  CHECK(s.small == 1);
  CHECK(s.fines == 0);  // fines are below 0.2 %
  CHECK(s.debris_ratio == Approx(0.002));
  CHECK(s.damage_ratio == 0);  // no initial bonds: nothing to break
}

TEST_CASE("debris by fragment size: singles and bonded debris (7.4 with 7.6's words)",
          "[breakage]") {
  // 200 primaries of 1 kg before the test. Debris by size: n < 2.5 % of 200 = 5
  // primaries. Fragments after it, by hand: 150 (large), 20 (medium: exactly
  // 10 %), 5 (exactly 2.5 %: not debris), 4, 2 and 2 (bonded debris: 8 primaries)
  // and 17 singles. Debris = 8 + 17 = 25 primaries, 12.5 % of the mass.
  Fragments f;
  f.mass = {150, 20, 5, 4, 2, 2};
  f.members = {150, 20, 5, 4, 2, 2};
  for (int k = 0; k < 17; ++k) f.mass.push_back(1), f.members.push_back(1);
  for (std::int64_t id = 0; id < 200; ++id) f.ids.push_back(id);
  f.label.assign(200, 0);  // not read by the summary
  const BreakageSummary s = summarize_breakage({}, {}, f, 200.0, {}, 200);
  CHECK(s.initial_count == 200);
  CHECK(s.debris_by_size == 20);  // 3 bonded + 17 singles
  CHECK(s.bonded_debris == 3);
  CHECK(s.bonded_debris_ratio == Approx(8.0 / 200));
  CHECK(s.singles_ratio == Approx(17.0 / 200));
  CHECK(s.debris_ratio_by_size == Approx(25.0 / 200));
  CHECK(s.debris_ratio == Approx(25.0 / 200));  // equal masses: the mass classes agree
  CHECK(s.fines == 0);                          // 0.2 % of 200 kg is below one primary
  CHECK(s.large == 1);
  CHECK(s.medium == 2);

  // Size, not mass: with debris below 10 % and N = 20, a single heavy primary
  // (30 kg of 200, 15 %: medium by mass) is debris by size (1 < 2 primaries).
  Fragments g;
  g.ids = {1, 2, 3, 4};
  g.label = {0, 0, 0, 1};
  g.mass = {170, 30};
  g.members = {3, 1};
  const BreakageSummary t = summarize_breakage({}, {}, g, 200.0, {0.5, 0.1, 0.01}, 20);
  CHECK(t.debris_ratio == 0);
  CHECK(t.medium == 1);
  CHECK(t.debris_by_size == 1);
  CHECK(t.singles_ratio == Approx(0.15));
  CHECK(t.bonded_debris == 0);
  // Without a count, N is the number of primaries in the fragments: 4, and
  // 1 < 0.1 x 4 fails, so nothing is debris by size.
  const BreakageSummary u = summarize_breakage({}, {}, g, 200.0, {0.5, 0.1, 0.01});
  CHECK(u.initial_count == 4);
  CHECK(u.debris_by_size == 0);
  CHECK_THROWS_WITH(summarize_breakage({}, {}, g, 200.0, {}, -1), Catch::Contains("initial_count"));
}

TEST_CASE("surviving bonds ignore contacts made during the test", "[breakage]") {
  const auto initial = normalized_bonds({{1, 2}, {2, 3}, {3, 4}});
  const auto now = normalized_bonds({{1, 2}, {3, 4}, {1, 4}});
  CHECK(surviving_bonds(initial, now) == normalized_bonds({{1, 2}, {3, 4}}));
  // In the contact graph {1, 2, 3, 4} is one piece; in the surviving bonds, two.
  const std::vector<std::int64_t> ids{1, 2, 3, 4};
  CHECK(find_fragments(ids, {1, 1, 1, 1}, now).count() == 1);
  CHECK(find_fragments(ids, {1, 1, 1, 1}, surviving_bonds(initial, now)).count() == 2);
}

TEST_CASE("bad input is refused with a message naming it", "[breakage]") {
  CHECK_THROWS_WITH(find_fragments({1, 2}, {1}, {}), Catch::Contains("2 ids but 1 masses"));
  CHECK_THROWS_WITH(find_fragments({1, 1}, {1, 1}, {}), Catch::Contains("listed twice"));
  CHECK_THROWS_WITH(find_fragments({1}, {0}, {}), Catch::Contains("mass"));
  Fragments f = find_fragments({1}, {1}, {});
  CHECK_THROWS_WITH(summarize_breakage({}, {}, f, 0), Catch::Contains("initial_mass"));
  FragmentClasses bad;
  bad.fines = 0.05;  // above debris
  CHECK_THROWS_WITH(summarize_breakage({}, {}, f, 1, bad), Catch::Contains("fines <= debris"));
}

TEST_CASE("parallel bonds: damage is broken over made, fragments the intact bonds' clusters",
          "[breakage][bond]") {
  // A chain 1-2-3-4 and a pair 5-6, all bonded; 2-3 and 5-6 broken; a bond to
  // particle 9 (not analysed, a host) is left out.
  const std::vector<std::int64_t> ids = {1, 2, 3, 4, 5, 6};
  const std::vector<ParallelBondRecord> records = {
      {2, 1, false}, {2, 3, true}, {4, 3, false}, {5, 6, true}, {6, 9, false}};
  const ParallelBondState s = parallel_bond_state(ids, records);
  CHECK(s.made == 4);
  CHECK(s.broken == 2);
  CHECK(s.damage_ratio == 0.5);
  REQUIRE(s.intact.size() == 2);
  CHECK(s.intact[0] == Bond{1, 2});
  CHECK(s.intact[1] == Bond{3, 4});
  const Fragments f = find_fragments(ids, std::vector<double>(6, 1.0), s.intact);
  CHECK(f.count() == 4);  // {1,2}, {3,4}, {5}, {6}
  CHECK(f.label[0] == f.label[1]);
  CHECK(f.label[2] == f.label[3]);
  CHECK(f.label[0] != f.label[2]);
  CHECK(f.label[4] != f.label[5]);
  CHECK(parallel_bond_state(ids, {}).damage_ratio == 0);
  CHECK_THROWS_AS(parallel_bond_state(ids, {{3, 3, false}}), std::invalid_argument);
}
