// Cell-list candidate pairs against brute force, for polydisperse sets up to
// 80:1 in size, with and without a periodic axis.
#include <algorithm>
#include <catch2/catch.hpp>
#include <set>

#include "core/random.hpp"
#include "engine/simulation.hpp"
#include "neighbor/cell_grid.hpp"

using namespace granule;

namespace {
template <int D>
std::set<std::pair<int, int>> brute(const Particles<D>& p, double skin, const Periodicity& per) {
  std::set<std::pair<int, int>> out;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      if (p.fixed[i] && p.fixed[j]) continue;
      Vec<D> d = p.position[i] - p.position[j];
      if (per.on()) d[per.axis] -= per.length * std::nearbyint(d[per.axis] / per.length);
      double reach = p.radius[i] + p.radius[j] + skin;
      if (d.squaredNorm() < reach * reach) out.insert({int(i), int(j)});
    }
  return out;
}

template <int D>
void compare(double size_ratio, bool periodic, std::uint64_t seed) {
  Random rng(seed);
  Particles<D> p;
  const double small = 1e-3, box = D == 2 ? 0.03 : 0.015;
  for (int k = 0; k < 600; ++k) {
    Vec<D> x;
    for (int d = 0; d < D; ++d) x[d] = rng.uniform(0, box);
    double r = small * rng.uniform(0.8, 1.2);
    p.add(x, Vec<D>::Zero(), Dim<D>::zero_spin(), r, 1000, 0, k % 50 == 0);
  }
  for (int k = 0; k < 3; ++k) {  // a few giants
    Vec<D> x;
    for (int d = 0; d < D; ++d) x[d] = rng.uniform(0, box);
    p.add(x, Vec<D>::Zero(), Dim<D>::zero_spin(), small * size_ratio * rng.uniform(0.5, 1.0), 1000,
          0, false);
  }
  Periodicity per;
  if (periodic) per = {D - 1, 0.0, box};
  const double skin = 0.3e-3;
  CellGrid<D> grid;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  grid.build(p, skin, per, pairs);
  std::set<std::pair<int, int>> found;
  for (auto [a, b] : pairs) {
    auto key = std::make_pair(int(std::min(a, b)), int(std::max(a, b)));
    INFO("pair " << key.first << "," << key.second << " listed twice");
    REQUIRE(found.insert(key).second);
  }
  auto expected = brute(p, skin, per);
  CHECK(found == expected);
  CHECK(expected.size() > 100);
}
}  // namespace

TEST_CASE("neighbors: cell lists find exactly the brute-force pairs", "[neighbors]") {
  for (double ratio : {1.0, 10.0, 80.0}) {
    for (bool periodic : {false, true}) {
      INFO("ratio " << ratio << " periodic " << periodic);
      compare<2>(ratio, false, 11);
      compare<3>(ratio, periodic && ratio == 1.0,
                 12);  // a giant wider than half the period has no minimum image
    }
  }
}

TEST_CASE("neighbors: a particle larger than any grid meets every small one, once", "[neighbors]") {
  // Its reach in cells would overflow an int: it must cover the grid, no more.
  Particles<2> p;
  Random rng(5);
  for (int k = 0; k < 30; ++k)
    p.add(Vec<2>(rng.uniform(0, 0.01), rng.uniform(0, 0.01)), Vec<2>::Zero(), Dim<2>::zero_spin(),
          1e-3, 1000, 0, false);
  p.add(Vec<2>(0.005, 0.005), Vec<2>::Zero(), Dim<2>::zero_spin(), 1e300, 1000, 0, false);
  CellGrid<2> grid;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  grid.build(p, 1e-4, Periodicity{}, pairs);
  std::set<std::pair<int, int>> found;
  for (auto [a, b] : pairs)
    REQUIRE(found.insert({int(std::min(a, b)), int(std::max(a, b))}).second);
  for (int k = 0; k < 30; ++k) CHECK(found.count({k, 30}) == 1);
}

TEST_CASE("neighbors: particles spread beyond any grid are refused, not a hang", "[neighbors]") {
  Simulation<2> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"p", 1000, 0, 0, 0});
  sim.set_contact("p", "p", "linear", {{"k_normal", 1e3}, {"restitution", 0.5}});
  ParticleSpec a, b;
  a.radius = b.radius = 1e-3, a.material = b.material = 0;
  a.position = {-1e308, 0, 0};
  b.position = {1e308, 0, 0};
  sim.add_particle(a), sim.add_particle(b);
  CHECK_THROWS_WITH(sim.prepare(), Catch::Contains("escaped or was placed absurdly far away"));
}
