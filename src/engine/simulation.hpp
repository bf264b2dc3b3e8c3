// Simulation<D>: the state of one scene and the step that advances it.
// step() (simulation.cpp) is the whole pipeline: neighbour lists, body forces,
// contacts per model, integration, hooks.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <tuple>
#include <unordered_set>
#include <vector>

#include "contact/models.hpp"
#include "core/particles.hpp"
#include "core/state.hpp"
#include "engine/simulation_base.hpp"
#include "fields/body_forces.hpp"
#include "geometry/mesh_set.hpp"
#include "geometry/walls.hpp"
#include "hooks/contact_log.hpp"
#include "hooks/diagnostic.hpp"
#include "kernel/buckets.hpp"
#include "kernel/pair_kernel.hpp"
#include "kernel/team.hpp"
#include "neighbor/cell_grid.hpp"

namespace granule {

template <int D, typename Tuple>
struct BucketsOf;
template <int D, typename... Ms>
struct BucketsOf<D, std::tuple<Ms...>> {
  using pairs = std::tuple<PairBucket<D, Ms>...>;
  using walls = std::tuple<WallBucket<D, Ms>...>;
  using pair_kernels = std::tuple<PairKernel<D, Ms>...>;
};

template <int D>
class Simulation final : public SimulationBase {
 public:
  using V = Vec<D>;
  using S = Spin<D>;

  int dimension() const override { return D; }

  int add_wall(const WallSpec& spec) override;
  int add_mesh_wall(const MeshWallSpec& spec, Triangles mesh) override;
  int add_polyline_wall(const PolylineWallSpec& spec) override;
  PolylineWallSpec polyline_wall(int w) const override;
  std::vector<MeshView> mesh_views() const override;
  std::int64_t mesh_triangles_tested() const override { return mesh_tested_; }
  const MeshSet<D>& meshes() const { return meshes_; }
  std::int64_t add_particle(const ParticleSpec& spec) override;
  std::vector<std::int64_t> fill(const FillSpec& spec) override;
  void remove_particle(std::int64_t id) override;

  void set_gravity(const Triple& g) override;
  void set_central_field(const Triple& point, double strength) override;
  void set_central_strength(double strength) override;
  void clear_central_field() override { body_.central_on = false; }
  double central_strength() const override { return body_.central_on ? body_.central_strength : 0; }

  int wall_count() const override { return static_cast<int>(walls_.size()); }
  int wall_id(const std::string& name) const override;
  WallSpec wall(int w) const override;
  void set_wall_velocity(int w, const Triple& v) override;
  void set_wall_angular_velocity(int w, double omega) override;
  Triple wall_force(int w) const override;
  double wall_axial_torque(int w) const override;

  std::int64_t particle_count() const override {
    return static_cast<std::int64_t>(state_override_ ? state_override_->state.id.size()
                                                     : p_.size());
  }
  // In increasing order: not the storage order, which the space-filling
  // curve's sorts and the ranks' shares change, so that a script that picks
  // the k-th id picks the same particle in every run of the scene.
  std::vector<std::int64_t> particle_ids() const override;
  bool has_particle(std::int64_t id) const override { return p_.index(id) >= 0; }
  std::int64_t ids_handed_out() const override { return p_.next_id; }
  Triple position(std::int64_t id) const override;
  Triple velocity(std::int64_t id) const override;
  Triple spin(std::int64_t id) const override;
  Triple force(std::int64_t id) const override;
  double radius(std::int64_t id) const override { return p_.radius[checked(id)]; }
  double mass(std::int64_t id) const override { return p_.mass[checked(id)]; }
  int material_of(std::int64_t id) const override { return p_.material[checked(id)]; }
  bool is_fixed(std::int64_t id) const override { return p_.fixed[checked(id)] != 0; }
  void set_position(std::int64_t id, const Triple& x) override;
  void set_velocity(std::int64_t id, const Triple& v) override;
  void set_spin(std::int64_t id, const Triple& w) override;
  void set_fixed(std::int64_t id, bool fixed) override;
  FlatState flat_state() const override;
  void flat_forces(std::vector<double>& force, std::vector<double>& torque) const override;
  BodyFields body_fields() const override {
    return {to_triple(body_.gravity), body_.central_on, to_triple(body_.central_point),
            body_.central_strength};
  }

  void prepare() override;
  void advance(std::int64_t steps) override;
  TimeStepReport time_step_rule() override;
  GlobalStats stats() const override;
  // stats() without the sums over the particles (energies, momenta): the
  // time, the step and the counters, as this process holds them.
  GlobalStats counters() const;
  std::vector<ContactRecord> contacts() const override;
  std::vector<std::string> describe() const override;
  ActiveEffects effects() const override;

  int attach_diagnostic(const std::string& name, DiagnosticOptions& options) override;
  // Attaches a diagnostic built in C++ (tests, embedding programs); returns its id.
  int attach(std::unique_ptr<Diagnostic<D>> diagnostic, const std::string& name);
  void detach_diagnostic(int id) override;
  std::map<std::string, double> diagnostic_results(int id) const override;
  std::map<std::string, std::vector<double>> diagnostic_arrays(int id) const override;
  void set_output_sink(OutputSink* sink) override;
  void flush_diagnostics() override;

  std::int64_t create_bonds(const BondSpec& spec) override;
  BondCounts bond_counts() const override {
    return {bonds_.intact, static_cast<std::int64_t>(bonds_.size()) - bonds_.intact};
  }
  std::vector<BondRecord> bond_records() const override;
  const ParallelBonds<D>& bonds() const { return bonds_; }

  // The complete state, for checkpoints (simulation_state.cpp). load_state()
  // needs the scene to have declared the same materials and walls.
  StateBlob save_state() const override;
  void settle_moved_bonds() override;
  void load_state(const StateBlob& state) override;
  std::string wound_legacy_rolling_springs(const StateBlob& saved) const override;
  // The diagnostics' accumulators and the contact tracking their events come
  // from (simulation_diagnostics.cpp).
  void save_diagnostics(StateBlob& blob) const override;
  void load_diagnostics(const StateBlob& blob) override;

  // One step of the pipeline.
  void step();
  // Re-sorts particle storage along cells (locality); histories follow by id.
  void sort_particles();
  // Stores the particles in the order of `ids` (every live id once; InputError
  // naming `ids` otherwise), the lists rebuilt if built: for tests that run one
  // scene in several storage orders (simulation_setup.cpp).
  void reorder_storage(const std::vector<std::int64_t>& ids);

  // One scene over MPI ranks (parallel/distributed_run.hpp, simulation_share.cpp).
  // A rank's share is its owned particles followed by its ghosts: copies of
  // other ranks' particles within reach, marked by `ghost_flag` in `fixed`
  // (bit 0 stays "fixed"), which the step neither moves (their owners do) nor
  // lists against walls or against each other. The run, not the step, decides when the lists
  // are rebuilt, from every rank's displacements.
  static constexpr std::uint8_t ghost_flag = 2;
  // The lists need rebuilding before the next step (on this rank's share).
  bool lists_due() const { return !lists_valid_ || lists_stale(); }
  // On the ranks of a distributed run the particles of other ranks are ghosts,
  // which this rank does not integrate, so its last step's fastest speed
  // (m^2/s^2) is its own particles'. DistributedRun::advance hands every
  // rank the fastest of all, and the pruned lists' travel takes that: a
  // ghost must not close the prune distance unseen.
  double last_fastest_speed_sq() const { return last_fastest_speed_sq_; }
  // Whether this rank's next step will note its pruned lists afresh (before
  // widen_prune_travel): the ranks then note on the same steps
  // (note_pruned_lists_with), rather than each waiting at the next forward
  // for the other's noting step.
  bool prune_due_next() const { return pruning_ && prune_distance_closed(); }
  // Some rank notes its pruned lists at the coming step: this one too (noting
  // early never changes a result: a pruned candidate cannot touch before the
  // next note).
  void note_pruned_lists_with(bool another_rank_notes) { prune_with_others_ = another_rank_notes; }
  // The grace of the scene's own overlaps (check_overlaps) ends at the first step whose
  // pairs are all under overlap_warning: on a distributed run, all ranks' pairs. The run
  // then ends it (set_external_overlap_grace), handing every rank the deepest pair
  // overlap / smaller radius of the last step anywhere, so that every rank fails on
  // the pass-throughs one process fails on, and on no other.
  double last_pair_overlap_ratio() const { return last_pair_overlap_ratio_; }
  void set_external_overlap_grace(bool on) { external_overlap_grace_ = on; }
  void end_overlap_grace_with(double deepest_pair_ratio_anywhere) {
    if (!(deepest_pair_ratio_anywhere > overlap_warning_)) end_overlap_grace();
  }
  // Likewise for a grace of particles placed mid-run: the deepest of the last
  // step's pairs with a placed particle (infinite while the grace is for all).
  double last_placed_pair_ratio() const { return last_placed_pair_ratio_; }
  void end_placed_grace_with(double deepest_placed_ratio_anywhere) {
    if (scene_overlaps_ && !grace_for_all_ && !(deepest_placed_ratio_anywhere > overlap_warning_))
      end_overlap_grace();
  }
  void widen_prune_travel(double fastest_speed_sq_anywhere) {
    if (fastest_speed_sq_anywhere > last_fastest_speed_sq_)
      prune_travel_ +=
          (std::sqrt(fastest_speed_sq_anywhere) - std::sqrt(last_fastest_speed_sq_)) * dt_;
  }
  // The farthest centre distance at which two particles can interact before
  // the next rebuild: twice the largest radius, the skin and the adhesive reach.
  double interaction_reach() const;
  Particles<D>& share() { return p_; }
  // The lists built anew where their storage indices went stale (a removal:
  // list_indices_stale_), before a share packs them.
  void renew_lists_if_indices_stale() {
    if (list_indices_stale_) rebuild_lists();
  }
  // Per storage index, the pair and wall histories of the contacts an owned
  // particle had at the last step, packed to travel with it; with `only`, just
  // those of the particles it marks (the others' strings stay empty).
  std::vector<std::string> pack_histories(const std::vector<std::uint8_t>* only = nullptr) const;
  // Stores `share` (owned particles, then ghosts) in place of the particles and
  // rebuilds the lists, each contact's history taken from the packed lists
  // (every rank's packing of the same contact is the same bytes). With
  // `keep_own`, the contacts of the current lists that were in contact at the
  // last step are carried too (by id, as the packed ones), so that the
  // particles staying on this rank need not pack theirs.
  void install_share(Particles<D> share, const std::vector<std::string>& histories,
                     bool keep_own = false);
  // Rebuilds the lists of the share in place (a run on one rank: nothing moves
  // between ranks, and the histories stay where they are).
  void rebuild_share_lists() { rebuild_lists(); }
  // The next step is one an attached diagnostic looks at (a sample due, or
  // contact events, which it follows every step): a distributed run takes it
  // on the whole scene.
  bool whole_step_due() const;
  // The pair contacts of the last step that this rank leads: those whose
  // lower-id particle it owns (every pair is led by one rank); with
  // `batched`, also how many of them the batched kernels computed.
  std::int64_t led_pair_contacts(std::int64_t* batched = nullptr) const;
  // The last step's tallies and the walls' reactions, as reduced over the
  // ranks, in place of this rank's (a scene gathered from its ranks).
  void set_step_tallies(std::int64_t pair_contacts, std::int64_t pair_batched,
                        std::int64_t wall_contacts, std::int64_t wall_batched,
                        double max_overlap_ratio);
  void set_wall_reactions(const std::vector<Vec<D>>& force,
                          const std::vector<double>& axial_torque);
  // Every wall contact leaves its reaction in its list (the kernels' unfused
  // path, also on one thread), and pack_wall_reactions() gives the last
  // step's, in slot order: model, particle id, wall, force on the particle,
  // axial torque on the wall. Summed over the ranks in (model, id) order they
  // are the one-process sums bit for bit (canonical order lists each
  // particle's wall contacts in id order).
  void set_keep_wall_reactions(bool on) { keep_wall_reactions_ = on; }
  // The terms of stats()' totals of particles which[0..count), a column
  // each, rounded as stats() adds them. Written to memory by a call the
  // compiler does not inline, so that no sum fuses with a product
  // differently in stats() and in a reduction over ranks that adds the same
  // terms; columns, so that no term is read back wider than it was stored.
  struct StatColumns {
    std::vector<double> kinetic_translational, kinetic_rotational, angular_momentum_z, mass;
    std::array<std::vector<double>, D> momentum;
    void resize(std::size_t count) {
      kinetic_translational.resize(count), kinetic_rotational.resize(count);
      angular_momentum_z.resize(count), mass.resize(count);
      for (auto& column : momentum) column.resize(count);
    }
  };
  void stat_columns(const std::uint32_t* which, std::size_t count, StatColumns& out) const;
  // flat_state(), flat_forces() and particle_count() give `state` (every
  // particle, gathered from the ranks in id order) until reset.
  struct StateOverride {
    FlatState state;
    std::vector<double> force, torque;
  };
  void set_state_override(std::optional<StateOverride> state) {
    state_override_ = std::move(state);
  }
  // stats() gives `totals` (reduced over the ranks) until reset.
  void set_stats_override(std::optional<GlobalStats> totals) {
    stats_override_ = std::move(totals);
  }
  std::string pack_wall_reactions() const;
  // The last step's contacts (contacts()) that this rank leads: pairs whose
  // lower-id particle it owns, and its owned particles' wall contacts, each
  // with its model and its place in the canonical slot order. Empty unless
  // the scene records contacts and a step was logged, or the whole scene kept
  // them by id (pack_kept_contacts: a checkpoint's, or those before a removal).
  std::string pack_led_contacts() const;
  std::string pack_kept_contacts() const;
  // Each stored particle's contacts at the last step (pairs it is in, and its
  // wall contacts), for weighing a rank's share of the work; zeros before any step.
  std::vector<std::uint32_t> contacts_per_particle() const;
  // Parallel bonds over ranks (simulation_bonds.cpp): every rank keeps every
  // bond and steps those with a particle it owns. break_orphan_bonds() breaks,
  // on the whole scene, the bonds of removed particles (what the next step
  // would do); pack_led_bonds() gives the state (broken, loads) of the bonds
  // whose first particle this rank owns, set_bond_states() takes every rank's;
  // led_bond_reach() is the longest centre distance of those bonds (m), which
  // the ghosts' reach must cover.
  void break_orphan_bonds();
  std::string pack_led_bonds() const;
  void set_bond_states(const std::string& all);
  double led_bond_reach() const;
  // contacts() gives the records every rank packed (`all`, pack_led_contacts()
  // concatenated in any order), in the canonical slot order, until the next
  // step or share: a scene gathered from its ranks lists the contacts as one
  // process in canonical order does.
  void set_gathered_contacts(const std::string& all);
  // The gathered list while it stands in for the log, else null (sim:contact_arrays()).
  const std::vector<ContactRecord>* gathered_contacts() const {
    drop_removed_contacts();
    return gathered_contacts_ ? &*gathered_contacts_ : nullptr;
  }

  // Direct access for C++ tests and diagnostics.
  const Particles<D>& particles() const { return p_; }
  const std::vector<Wall<D>>& walls() const { return walls_; }
  const ContactLog<D>& contact_log() const { return log_; }

 private:
  int checked(std::int64_t id) const;
  V to_vec(const Triple& t) const;
  Triple to_triple(const V& v) const;
  S to_spin(const Triple& t) const;
  Triple spin_triple(const S& s) const;
  V separation(const V& a, const V& b) const {
    V d = a - b;
    if (periodic_.on()) d[periodic_.axis] = periodic_.wrap(d[periodic_.axis]);
    return d;
  }
  // Material pairs (a <= b) that can meet: a particle material against a
  // particle or wall material (simulation_effects.cpp).
  std::vector<std::pair<int, int>> pairs_in_use() const;
  void check_particle_input(const ParticleSpec& s, const std::string& context) const;
  void rebuild_lists();
  void build_slots();
  bool lists_stale() const;
  // Which loops run on how many threads (kernel/team.hpp).
  ThreadPolicy thread_policy() const {
    return {thread_count(), parallel_min_candidates_, parallel_min_particles_};
  }
  template <typename Bucket>
  void track_bucket(Bucket& bucket);
  void track_contacts();
  void observe(bool contacts_logged);
  void scatter_forces();
  void list_logged_slots();  // the contact log's active slots, from the kernels' lists
  void integrate();
  // The parallel bonds' loads onto their particles, in bond order (simulation_bonds.cpp).
  void apply_bonds();
  // The stiffest particle's bonded mode (simulation_bonds.cpp).
  struct BondMode {
    double omega_sq = 0;  // 1/s^2
    std::size_t particle = 0;
    int bonds = 0;
  };
  BondMode stiffest_bond_mode(const std::vector<std::pair<std::int64_t, std::int64_t>>& fresh,
                              const std::vector<BondProperties>& made) const;
  void check_bond_step();
  // set_position's bonds: bond index -> the pair's surface gap before its first move
  // since the last step (settle_moved_bonds).
  std::map<std::size_t, double> moved_bond_gaps_;
  // What check_bond_step() last found stable: a ramp re-prepares every step.
  double bond_step_checked_ = 0;
  std::size_t bond_count_checked_ = 0, bonds_intact_checked_ = 0;
  // What the bonds' next increments read (apply_bonds): a bond's load follows
  // the motion the particles made over the step before, at the velocities and
  // spins that moved them. A script that sets a bonded particle's velocity or
  // spin between steps (set_velocity, set_spin, scale_velocities) leaves here
  // the ones it moved with, by id; bonds from `bonds_unmoved_from_` on were
  // made since the last step, at the particles' present places, and have seen
  // no motion yet. Both hold until the next step's bonds are applied.
  struct MovedWith {
    V velocity;
    S spin;
  };
  std::map<std::int64_t, MovedWith> bond_moved_with_;
  std::size_t bonds_unmoved_from_ = 0;
  void note_bonded_motion(int index) {
    if (bonds_.intact > 0)
      bond_moved_with_.try_emplace(p_.id[index], MovedWith{p_.velocity[index], p_.spin[index]});
  }
  void save_bonds(StateBlob& s) const;
  // The checkpoint's bonds, checked (InputError naming the entry); none in one without them.
  ParallelBonds<D> read_bonds(const StateBlob& s) const;
  // The checkpoint's bond_moved_with_ and bonds_unmoved_from_, checked against its
  // `bonds` bonds (InputError naming the entry) before anything is replaced.
  struct BondMotionState {
    std::map<std::int64_t, MovedWith> moved_with;
    std::size_t unmoved_from = 0;
  };
  BondMotionState read_bond_motion(const StateBlob& s, std::size_t bonds) const;
  void report_non_finite(std::size_t index);
  void refuse_beyond_memory(std::int64_t particles, const char* what) const;
  // At each list rebuild and on any step with a wall contact deeper than a
  // radius: stops the run if a centre passed a wall.
  void check_escapes();
  // A moving particle (id; -1: one being added) placed at x inside solid polyline
  // w (it `starts` there at the start of a scene, else `lies`) is warned of, the
  // message led by `caller` ("set_position: " or ""): the polyline's contact throws it out through
  // the nearest side, as fast as that overlap drives it (pushing out a centre the run's motion took
  // in is by design). simulation_setup.cpp.
  void check_placed_in_walls(const V& at, double radius, bool fixed, std::int64_t id,
                             const char* caller) const;
  void warn_if_inside_solid(std::size_t w, const V& x, std::int64_t id, const char* caller = "",
                            bool starts = false) const;
  // Steps whose deepest pair overlap exceeds overlap_warning: warns once, stops
  // a pass-through (simulation_checks.cpp).
  void check_overlaps(double pair_ratio);
  // The thin walls' contacts (simulation_checks.cpp): on a step whose deepest
  // wall contact is over wall_through_ratio of the particle's radius, stops the
  // run where such a particle goes on into the wall (`pressed`); on a step with
  // one deeper than thin_watch_ratio, and the step after, where a centre crossed
  // a thin wall's surface within the step (`crossed`). Each names the particle
  // and the wall.
  static constexpr double wall_through_ratio = 0.9;
  static constexpr double thin_watch_ratio = 0.5;
  bool thin_deep_last_step_ = false;
  void check_thin_walls(bool pressed, bool crossed);
  // Event tracking began since the last step: its contacts going on are to be marked
  // (mark_ongoing_contacts, simulation.cpp), at the next step.
  bool ongoing_marks_due_ = false;
  void mark_ongoing_contacts();
  // A mesh's (or polyline's) contacts are found within the step (resolve_meshes):
  // those the marking step finds touching are marked there.
  bool mesh_marks_due_ = false;
  void mark_ongoing_mesh_contacts();
  // Deep contacts of the Hertzian laws (simulation_checks.cpp): their modes at the
  // step's deepest overlap, looked at again each time it has grown by 2 %.
  std::vector<DeepContactMode> deep_modes_;
  double deep_checked_pair_ = 0, deep_checked_wall_ = 0;  // ratios looked at again above these
  // A law the step's deepest overlap would put past the bound, whose own
  // contacts were not that deep: their depth is looked at again from this step.
  std::int64_t deep_rescan_step_ = -1;
  std::vector<std::string> deep_warned_;                 // pairs already warned of
  static constexpr double deep_mode_bound = 0.8;         // omega dt warned above
  static constexpr std::int64_t deep_rescan_every = 64;  // steps
  void check_deep_contact_modes(double pair_ratio, double wall_ratio);
  // The deepest overlap / radius of each material pair's touching contacts
  // (pairs: by the smaller radius; walls: particle material by wall material).
  void deepest_by_materials(std::vector<double>& pairs, std::vector<double>& walls) const;
  void warn_deep_wall_contact();
  Diagnostic<D>& diagnostic(int id) const;

  struct AttachedDiagnostic {
    int id = 0;
    std::string name;
    std::unique_ptr<Diagnostic<D>> diagnostic;
    typename Diagnostic<D>::Needs needs;
    std::int64_t every = 1;
  };
  Particles<D> p_;
  std::vector<Wall<D>> walls_;
  // Mesh walls (3D) and polyline walls (2D): their surfaces and poses
  // (simulation_meshes.cpp, simulation_polylines.cpp).
  MeshSet<D> meshes_;
  double mesh_grid_reach_ = 0;  // the query reach the meshes' grids were built for
  std::int64_t mesh_tested_ = 0;
  void prepare_meshes();  // (re)builds the grids for the particles' reach
  void resolve_meshes();  // this step's mesh contacts, before the wall kernels
  void save_meshes(StateBlob& s) const;
  void load_meshes(const StateBlob& s);
  BodyForces<D> body_;
  ParallelBonds<D> bonds_;
  CellGrid<D> grid_;
  typename BucketsOf<D, ContactModels>::pairs pair_buckets_;
  typename BucketsOf<D, ContactModels>::walls wall_buckets_;
  // One pair kernel per model: its thread ranges and pruned lists.
  typename BucketsOf<D, ContactModels>::pair_kernels pair_kernels_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> candidates_;
  // One slot per candidate contact (pairs, then walls): whether it touched at
  // the last step, and its place in the contact log. Each particle's force is
  // the sum of its contacts' in slot order whatever the number of threads.
  std::size_t slot_count_ = 0;
  HotArray<std::uint8_t> slot_in_contact_;  // 0: history cleared
  bool fused_ = true;  // this step adds contact forces to particles directly (one thread)
  void zero_forces();
  ContactLog<D> log_;
  std::vector<AttachedDiagnostic> diagnostics_;
  // Each label attached while the output is this sink's, with its diagnostic's
  // options: a label comes back (after remove_diagnostic) only with the same
  // options, or its group's rows and attributes would describe two diagnostics.
  std::vector<std::pair<std::string, std::string>> labels_used_;
  int next_diagnostic_id_ = 1;
  bool tracking_ = false;  // an attached diagnostic needs contact events
  OutputSink* sink_ = nullptr;
  HotArray<V> position_at_rebuild_;
  double max_displacement_sq_ = 0;
  bool any_fixed_ = true;  // a fixed particle exists (refreshed at every list rebuild)
  bool lists_valid_ = false;
  // The particles' storage changed since the lists were built (a removal, a
  // re-order, a checkpoint of such lists): their storage indices may name
  // another particle or none until the next rebuild; their ids still hold.
  bool list_indices_stale_ = false;
  // The smallest radius at prepare(): no particle may move farther in a step
  // (report_step_over, simulation_checks.cpp).
  double smallest_radius_ = INFINITY;
  // Of the free particles: a fixed one touches no wall, so no wall steps over it.
  double smallest_free_radius_ = INFINITY;
  void note_smallest_radii();  // both, from the particles (prepare(), load_state())
  // A free particle escaped through a wall (storage index) and the wall, or -1, -1.
  std::pair<std::int64_t, std::int64_t> escaped_particle_and_wall() const;
  bool far_warned_ = false;  // particles far enough from the origin to lose digits
  void report_step_over();
  // Nor may a wall come that far towards a particle (each wall's farthest point's travel
  // in the last step, and their largest; checked against the particles only past it).
  std::vector<double> wall_travel_;
  double last_wall_travel_ = 0;
  void report_wall_step_over();
  // Before storage indices change between steps: the last step's contacts kept by id.
  void keep_contacts_by_id();
  std::vector<std::pair<std::size_t, const char*>> slot_models() const;  // (first slot, name)
  // The last step's results in a checkpoint (simulation_last_step.cpp).
  void save_last_step(StateBlob& s) const;
  void load_last_step(const StateBlob& s);
  // RunError naming `what` while list_indices_stale_.
  void require_current_indices(const char* what) const;
  std::size_t rebuilds_ = 0;
  std::int64_t rebalances_ =
      0;  // moves of the threads' shares of pair contacts (ThreadRanges::rebalance)
  // Pruning (PrunedLists): how far any particle can have moved since the pair
  // lists were last pruned all at once (the fastest speed of each step times
  // dt, summed), whether this step prunes them all, and how many prunes so far.
  double prune_travel_ = 0;
  bool prune_with_others_ = false;    // note_pruned_lists_with
  double last_fastest_speed_sq_ = 0;  // m^2/s^2, of the particles this rank integrates
  bool prune_due_ = true;
  std::int64_t prunes_ = 0;
  // The prune distance, a fraction of the skin tuned as the run goes
  // (tune_prune_distance): the nearer, the fewer candidates the pruned lists
  // keep, but the sooner the particles may close it and all are noted again.
  // The candidates visited per step over each cycle between global prunes
  // judge the last move of the fraction. None of it changes a result.
  double prune_fraction_ = 0.25;
  int prune_direction_ = -1;  // the fraction's next move: -1 nearer, +1 farther
  std::int64_t prune_cycle_steps_ = 0, prune_cycle_visited_ = 0;
  double prune_cycle_cost_ = -1;  // visited per step over the last whole cycle; -1: none yet
  double prune_distance() const { return prune_fraction_ * skin_; }
  // Two particles may have closed the prune distance since the last note,
  // each having moved at most prune_travel_.
  bool prune_distance_closed() const { return !(2 * prune_travel_ < prune_distance()); }
  void tune_prune_distance();
  // per-step counters
  std::int64_t contacts_particle_ = 0, contacts_wall_ = 0, contacts_batched_ = 0;
  std::int64_t contacts_wall_batched_ = 0;
  std::int64_t candidates_visited_ = 0;  // by the pair loops' listing passes
  double max_overlap_ratio_ = 0;
  // Of this rank's pairs, the last step; infinite until a step has followed the
  // last arm_overlap_grace(), so that no verdict older than the grace ends it.
  double last_pair_overlap_ratio_ = INFINITY;
  bool external_overlap_grace_ = false;  // set_external_overlap_grace
  // The scene made overlaps (placed particles): pushed apart, not stopped, until a
  // step has all pairs under overlap_warning (check_overlaps). Armed for all the
  // particles (the scene's start, a restart), or for those just placed: then it
  // ends too on a step whose pairs with a placed particle are all under it, so
  // that a particle added beside a bed pressed deep by its load does not lift
  // the guards from the bed (placed_pairs_deepest).
  void arm_overlap_grace(bool on = true) {
    scene_overlaps_ = on;
    last_pair_overlap_ratio_ = INFINITY;
    last_placed_pair_ratio_ = INFINITY;
    grace_for_all_ = on;
    placed_ids_.clear();
    placed_ids_unique_ = 0;
  }
  template <typename Ids>
  void arm_overlap_grace_for(const Ids& ids) {
    if (!scene_overlaps_) grace_for_all_ = false;
    scene_overlaps_ = true;
    last_pair_overlap_ratio_ = INFINITY;
    last_placed_pair_ratio_ = INFINITY;
    if (grace_for_all_) return;
    // Appended in any order, O(1) per id however the calls come (1e5
    // add_particle or set_position calls in any order), and made sorted and
    // unique once the list has doubled, so that a set_position every step
    // keeps it short; the checkpoint writes it sorted.
    for (const std::int64_t id : ids)
      if (placed_ids_.empty() || id != placed_ids_.back()) placed_ids_.push_back(id);
    if (placed_ids_.size() > 2 * placed_ids_unique_ + 64) {
      std::sort(placed_ids_.begin(), placed_ids_.end());
      placed_ids_.erase(std::unique(placed_ids_.begin(), placed_ids_.end()), placed_ids_.end());
      placed_ids_unique_ = placed_ids_.size();
    }
  }
  void end_overlap_grace() {
    scene_overlaps_ = false;
    grace_for_all_ = false;
    placed_ids_.clear();
    placed_ids_unique_ = 0;
  }
  bool grace_for_all_ = false;
  double last_placed_pair_ratio_ = INFINITY;
  std::vector<std::int64_t> placed_ids_;  // the particles the grace is for, unless for all
  std::size_t placed_ids_unique_ = 0;     // its length when last made sorted and unique
  bool scene_launched_ = false;           // an overlap the scene made was seen deep
  // Overlap / smaller radius of the deepest pair with a placed particle, or of
  // the first found deeper than overlap_warning (all its callers ask only that).
  double placed_pairs_deepest() const;
  std::size_t non_finite_index_ = SIZE_MAX;
  std::string dt_governing_pair_;  // the pair whose rule sets the automatic time step
  bool dt_per_contact_ = true;     // its rule is t_c / n (else 8 T_R / n)
  // The run header's words for the automatic step.
  std::string automatic_step_rule() const;
  std::string dt_warned_;  // the last warning of a time_step above the rule
  // Parts of prepare() (simulation_prepare.cpp).
  double adhesive_reach() const;  // m, contact_reach_ for the particles and laws now
  void choose_time_step();        // dt_ by Eq. 4.1 or time_step, against the stability limit
  bool prepare_parameters();      // after a law's parameters alone changed; false: prepare all
  // With a periodic axis: every wall the same along it (or, moving_only, the
  // walls whose motion carries them along it: a rectangle or mesh that spanned
  // the period when the run began uncovers its seam as it slides).
  void check_walls_repeat(bool moving_only = false) const;
  void report_walls_leave_period();   // check_walls_repeat(true) as a run's failure
  bool periodic_walls_move_ = false;  // some wall's motion carries it along the periodic axis
  double contact_reach_ = 0;          // m, how far apart adhesive contacts persist (<= skin)
  bool keep_wall_reactions_ = false;  // set_keep_wall_reactions
  std::optional<GlobalStats> stats_override_;                            // set_stats_override
  std::optional<StateOverride> state_override_;                          // set_state_override
  mutable std::optional<std::vector<ContactRecord>> gathered_contacts_;  // set_gathered_contacts
  // Particles removed since the gathered list was made: their contacts are dropped
  // from it when it is next read (one pass for any number of removals).
  mutable std::unordered_set<std::int64_t> removed_from_gathered_;
  void drop_removed_contacts() const {
    if (removed_from_gathered_.empty() || !gathered_contacts_) return;
    auto& kept = *gathered_contacts_;
    kept.erase(std::remove_if(kept.begin(), kept.end(),
                              [&](const ContactRecord& c) {
                                return removed_from_gathered_.count(c.id_a) ||
                                       removed_from_gathered_.count(c.id_b);
                              }),
               kept.end());
    removed_from_gathered_.clear();
  }
  bool rotation_ = true;  // integrate spins: false when no pair in use has friction (prepare())
};

}  // namespace granule
