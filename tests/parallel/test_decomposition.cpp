// Recursive coordinate bisection and the choice of ghosts (src/parallel), on
// one process: the boxes tile the domain, balance the weight to one point,
// do not depend on the order of the points, and the ghosts chosen are exactly
// those a brute-force distance test over every box and image finds.
#include <algorithm>
#include <catch2/catch.hpp>
#include <random>
#include <set>
#include <tuple>

#include "parallel/decomposition.hpp"
#include "parallel/exchange.hpp"
#include "parallel/ghosts.hpp"

using namespace granule;
using namespace granule::parallel;

namespace {

template <int D>
struct Cloud {
  std::vector<Vec<D>> x;
  std::vector<double> w;
  std::vector<std::int64_t> id;
};

// A heap of points crowded towards the low corner (as a settled bed is), in a box.
template <int D>
Cloud<D> cloud(std::size_t n, unsigned seed, const Box<D>& box) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  Cloud<D> c;
  for (std::size_t k = 0; k < n; ++k) {
    Vec<D> p;
    for (int a = 0; a < D; ++a) {
      const double t = a == D - 1 ? u(rng) * u(rng) : u(rng);
      p[a] = box.lo[a] + t * (box.hi[a] - box.lo[a]);
    }
    c.x.push_back(p);
    c.w.push_back(0.5 + u(rng));
    c.id.push_back(static_cast<std::int64_t>(1000 + 7 * k));
  }
  return c;
}

template <int D>
Box<D> unit_box() {
  Box<D> b;
  b.lo.setConstant(-0.01);
  b.hi.setConstant(0.02);
  return b;
}

}  // namespace

TEMPLATE_TEST_CASE_SIG("parallel: the bisection tiles the domain and balances the weight",
                       "[parallel]", ((int D), D), 2, 3) {
  const Box<D> domain = unit_box<D>();
  const auto c = cloud<D>(2000, 3, domain);
  const double heaviest = *std::max_element(c.w.begin(), c.w.end());
  double total = 0;
  for (double w : c.w) total += w;
  for (int ranks : {1, 2, 3, 4, 5, 7, 8}) {
    INFO("ranks " << ranks);
    const auto d = bisect<D>(domain, {}, ranks, c.x, c.w, c.id);
    REQUIRE(d.ranks() == ranks);
    double volume = 0;
    for (const auto& b : d.boxes) volume += b.volume();
    CHECK(volume == Approx(domain.volume()).epsilon(1e-12));
    // Every point lies in exactly one box, the one owner() names, and the
    // weights the boxes hold are what the cut recorded.
    std::vector<double> held(static_cast<std::size_t>(ranks), 0.0);
    for (std::size_t k = 0; k < c.x.size(); ++k) {
      int inside = 0, which = -1;
      for (int r = 0; r < ranks; ++r)
        if (d.boxes[static_cast<std::size_t>(r)].contains(c.x[k])) ++inside, which = r;
      REQUIRE(inside == 1);
      REQUIRE(d.owner(c.x[k]) == which);
      held[static_cast<std::size_t>(which)] += c.w[k];
    }
    for (int r = 0; r < ranks; ++r)
      CHECK(held[static_cast<std::size_t>(r)] ==
            Approx(d.rank_weight[static_cast<std::size_t>(r)]).epsilon(1e-12));
    // Balanced to within one point per level of cuts.
    const double levels = std::ceil(std::log2(ranks));
    for (double w : held) CHECK(std::abs(w - total / ranks) <= (levels + 1) * heaviest);
    CHECK(d.imbalance() < 1.0 + (levels + 1) * heaviest * ranks / total);
  }
}

TEST_CASE("parallel: the bisection does not depend on the order of the points", "[parallel]") {
  const Box<3> domain = unit_box<3>();
  auto c = cloud<3>(500, 5, domain);
  const auto d1 = bisect<3>(domain, {}, 6, c.x, c.w, c.id);
  std::vector<std::size_t> order(c.x.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::shuffle(order.begin(), order.end(), std::mt19937_64(9));
  Cloud<3> s;
  for (std::size_t k : order) s.x.push_back(c.x[k]), s.w.push_back(c.w[k]), s.id.push_back(c.id[k]);
  const auto d2 = bisect<3>(domain, {}, 6, s.x, s.w, s.id);
  REQUIRE(d1.cuts.size() == d2.cuts.size());
  for (std::size_t k = 0; k < d1.cuts.size(); ++k) {
    CHECK(d1.cuts[k].axis == d2.cuts[k].axis);
    CHECK(d1.cuts[k].position == d2.cuts[k].position);  // bit for bit
  }
}

TEST_CASE("parallel: a lattice is cut between its planes, never through one", "[parallel]") {
  Box<2> domain;
  domain.lo = Vec<2>(0, 0);
  domain.hi = Vec<2>(1, 1);
  Cloud<2> c;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) {
      c.x.push_back(Vec<2>(0.05 + 0.1 * i, 0.05 + 0.1 * j));
      c.id.push_back(10 * i + j);
    }
  const auto d = bisect<2>(domain, {}, 3, c.x, {}, c.id);
  // Points with the same coordinate along a cut's axis share a side of it.
  for (const Cut& cut : d.cuts)
    for (std::size_t a = 0; a < c.x.size(); ++a)
      for (std::size_t b = 0; b < c.x.size(); ++b)
        if (c.x[a][cut.axis] == c.x[b][cut.axis])
          CHECK((c.x[a][cut.axis] < cut.position) == (c.x[b][cut.axis] < cut.position));
  int total = 0;
  for (double w : d.rank_weight) total += static_cast<int>(w);
  CHECK(total == 100);
  CHECK(d.imbalance() < 1.25);  // 30 / 30 / 40 at worst for whole lattice rows
}

TEST_CASE("parallel: bad decompositions are refused with the reason", "[parallel][errors]") {
  const Box<2> domain = unit_box<2>();
  const std::vector<Vec<2>> x{Vec<2>(0, 0)};
  CHECK_THROWS_WITH(bisect<2>(domain, {}, 0, x, {}, {1}), Catch::Contains("0 ranks"));
  CHECK_THROWS_WITH(bisect<2>(domain, {}, 2, x, {}, {}), Catch::Contains("differ in length"));
  CHECK_THROWS_WITH(bisect<2>(domain, {}, 2, x, {-1.0}, {1}), Catch::Contains("weight is -1"));
  Box<2> flat = domain;
  flat.hi[1] = flat.lo[1];
  CHECK_THROWS_WITH(bisect<2>(flat, {}, 2, x, {}, {1}), Catch::Contains("empty along axis 1"));
  const auto d = bisect<2>(domain, {true, false}, 2, x, {}, {1});
  CHECK_THROWS_WITH(check_reach(d, 0.016),
                    Catch::Contains("half the periodic length along axis 0"));
}

TEMPLATE_TEST_CASE_SIG("parallel: the ghosts chosen are those within reach of each box, images too",
                       "[parallel]", ((int D), D), 2, 3) {
  const Box<D> domain = unit_box<D>();
  const auto c = cloud<D>(800, 11, domain);
  std::array<bool, D> periodic{};
  periodic[0] = true;  // one periodic axis
  const double reach = 0.003;
  for (int ranks : {1, 2, 3, 5}) {
    INFO("ranks " << ranks);
    const auto d = bisect<D>(domain, periodic, ranks, c.x, {}, c.id);
    check_reach(d, reach);
    const auto shifts = periodic_shifts(d);
    REQUIRE(shifts.size() == 3);
    std::vector<GhostTarget<D>> got;
    for (std::size_t k = 0; k < c.x.size(); ++k) {
      const int owner = d.owner(c.x[k]);
      got.clear();
      ghost_targets(d, shifts, c.x[k], reach, owner, got);
      // Brute force: every box, every image, by the distance alone.
      std::set<std::tuple<int, double>> want, have;
      for (const auto& s : shifts)
        for (int r = 0; r < ranks; ++r) {
          if (r == owner && s.isZero()) continue;
          if (d.boxes[static_cast<std::size_t>(r)].distance(c.x[k] + s) < reach)
            want.insert({r, s[0]});
        }
      for (const auto& g : got) have.insert({g.rank, g.shift[0]});
      REQUIRE(have == want);
      REQUIRE(got.size() == want.size());  // no target twice
    }
  }
}

TEST_CASE("parallel: a particle record packs and unpacks bit for bit", "[parallel]") {
  ParticleRecord<3> r;
  r.id = 123456789012345;
  r.position = Vec<3>(0.1, -2e-300, 1.0 / 3.0);
  r.velocity = Vec<3>(-0.0, 5e-324, 7.25);
  r.spin = Vec<3>(1, 2, 3);
  r.radius = 4.5e-5;
  r.mass = 1.234e-12;
  r.inv_mass = 1 / r.mass;
  r.inv_inertia = 3.0e20;
  r.fixed = 3;
  r.material = 3;
  r.image = 2;
  r.payload = std::string("\0history\xff", 10);
  std::string bytes;
  pack(r, bytes);
  pack(r, bytes);
  std::size_t at = 0;
  CHECK(unpack<3>(bytes, at) == r);
  CHECK(unpack<3>(bytes, at) == r);
  CHECK(at == bytes.size());
  std::size_t cut = 0;
  const std::string short_bytes = bytes.substr(0, 20);
  CHECK_THROWS_WITH(unpack<3>(short_bytes, cut), Catch::Contains("cut short"));
}
