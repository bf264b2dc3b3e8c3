// Breakage of a bonded agglomerate (dissertation 7.4; SPEC 6): fragments are the
// connected clusters of the contact graph, the damage ratio counts the initial
// bonds that have broken, the debris ratio weighs the fragments below 2.5 % of
// the initial mass. Plain data in, plain data out: no simulation, no Lua. The
// Lua layer (src/lua/wrap_agglomerate.cpp) gathers the bonds from the engine's
// contact list only when a scene asks, so a scene that never calls it pays
// nothing.
#pragma once

#include <cstdint>
#include <vector>

namespace granule::analysis {

// Two particles in contact, named by persistent id. Stored with a < b.
struct Bond {
  std::int64_t a = -1;
  std::int64_t b = -1;
  bool operator==(const Bond& o) const { return a == o.a && b == o.b; }
  bool operator<(const Bond& o) const { return a < o.a || (a == o.a && b < o.b); }
};

// Orders each pair (a < b), sorts the list and drops repeats. Throws
// std::invalid_argument for a particle bonded to itself or a negative id.
std::vector<Bond> normalized_bonds(std::vector<Bond> bonds);

// The bonds of `initial` that are also in `now` (both normalised): the graph of
// the original bonds that survive, which ignores contacts made during a test
// (fragments pressed together between two walls stay apart in it).
std::vector<Bond> surviving_bonds(const std::vector<Bond>& initial, const std::vector<Bond>& now);

// Union-find over indices 0..n-1 (union by size, path halving): near-constant
// time per operation, so labelling is linear in the number of bonds.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n);
  std::size_t find(std::size_t i);
  void unite(std::size_t i, std::size_t j);

 private:
  std::vector<std::size_t> parent_, size_;
};

// The clusters of particles joined by bonds. Fragments are numbered 0, 1, ...
// from the heaviest (ties: the one holding the lowest id first), so label 0
// is the largest surviving piece.
struct Fragments {
  std::vector<std::int64_t> ids;      // the particles analysed, in the order given
  std::vector<int> label;             // per particle: its fragment
  std::vector<double> mass;           // per fragment, kg, non-increasing
  std::vector<std::int64_t> members;  // per fragment: number of primaries
  std::size_t count() const { return mass.size(); }
};

// Connected components of the graph (ids, bonds). Bonds naming a particle not in
// `ids` are ignored (a contact with a host particle joins nothing). Throws
// std::invalid_argument if ids repeat, sizes differ or a mass is not > 0.
Fragments find_fragments(const std::vector<std::int64_t>& ids, const std::vector<double>& masses,
                         const std::vector<Bond>& bonds);

// Fragment classes as fractions of the initial agglomerate mass (7.4): large
// above `large`, medium between `debris` and `large`, small fragments (debris)
// below `debris`, and among those the fines below `fines`.
struct FragmentClasses {
  double large = 0.10;
  double debris = 0.025;
  double fines = 0.002;
};

struct BreakageSummary {
  std::int64_t initial_bonds = 0;  // contacts before the test
  std::int64_t bonds = 0;          // contacts now (among the agglomerate's particles)
  std::int64_t broken_bonds = 0;   // initial bonds no longer in contact
  std::int64_t new_bonds = 0;      // contacts now that were not there initially
  double damage_ratio = 0;         // broken_bonds / initial_bonds (7.4)
  double initial_mass = 0;         // kg
  double debris_mass = 0;          // kg in fragments below classes.debris
  double debris_ratio = 0;         // debris_mass / initial_mass (7.4)
  double fines_ratio = 0;          // mass in fragments below classes.fines / initial_mass
  double largest_fraction = 0;     // heaviest fragment / initial_mass
  std::int64_t fragments = 0;      // all clusters, single primaries included
  std::int64_t large = 0, medium = 0, small = 0, fines = 0;  // counts; fines are among small
  std::int64_t singles = 0;                                  // clusters of one primary
  // By fragment size in primaries, n, against the initial count N (the reading of
  // 7.4 with 7.6's words): debris has n < debris N (217 primaries: n <= 5); within
  // it the singles (n = 1) and the bonded debris (n >= 2), 7.6's "fines where
  // single primary particle still had some connecting bonds with others". The
  // mass classes above cannot hold that: with 217 primaries one primary is 0.46 %
  // of the mass, above the 0.2 % of fines.
  std::int64_t initial_count = 0;   // N
  std::int64_t debris_by_size = 0;  // fragments with n < debris N
  std::int64_t bonded_debris = 0;   // ... of them with n >= 2
  double debris_ratio_by_size = 0;  // their mass / initial_mass
  double singles_ratio = 0;         // mass in fragments of one primary / initial_mass
  double bonded_debris_ratio = 0;   // mass in debris_by_size fragments with n >= 2 / initial_mass
};

// Damage ratio and fragment statistics. initial_bonds and bonds must be
// normalised (normalized_bonds). initial_mass > 0 is the agglomerate's mass
// before the test; `classes` must satisfy 0 < fines <= debris <= large < 1;
// initial_count is the number of primaries before the test (0: the number in
// `fragments`).
BreakageSummary summarize_breakage(const std::vector<Bond>& initial_bonds,
                                   const std::vector<Bond>& bonds, const Fragments& fragments,
                                   double initial_mass, const FragmentClasses& classes = {},
                                   std::int64_t initial_count = 0);

// Parallel bonds (contact/parallel_bond.hpp) as the breakage analysis counts
// them: a bonded agglomerate's damage is the share of its parallel bonds that
// have broken (Potyondy and Cundall 2004, 2.2: a broken bond never heals), and
// its fragments are the clusters of the intact ones. Plain records, as
// SimulationBase::bond_records() gives them, so that this file needs no engine.
struct ParallelBondRecord {
  std::int64_t a = -1, b = -1;
  bool broken = false;
};

struct ParallelBondState {
  std::int64_t made = 0;     // parallel bonds between two of the particles analysed
  std::int64_t broken = 0;   // ... of them broken
  double damage_ratio = 0;   // broken / made (0 without bonds)
  std::vector<Bond> intact;  // the intact ones, normalised: the fragments' graph
};

// The records between two of `ids` (a bond to a particle not listed, a host or
// another agglomerate, is left out). Throws std::invalid_argument for a record
// naming a particle bonded to itself or a negative id.
ParallelBondState parallel_bond_state(const std::vector<std::int64_t>& ids,
                                      const std::vector<ParallelBondRecord>& records);

}  // namespace granule::analysis
