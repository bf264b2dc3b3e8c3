// The dimension-free face of a simulation: what the Lua layer, the output
// writers and the CLI see. Everything that loops over particles or contacts
// lives in Simulation<D> (simulation.hpp), instantiated for D = 2 and 3.
#pragma once

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "contact/pair_table.hpp"
#include "contact/parallel_bond.hpp"
#include "core/material.hpp"
#include "fields/damping.hpp"
#include "fields/schedule.hpp"
#include "geometry/triangles.hpp"
#include "geometry/walls.hpp"
#include "neighbor/cell_grid.hpp"

namespace granule {

class DiagnosticOptions;
struct StateBlob;
class OutputSink;

using Triple = std::array<double, 3>;  // a vector in 2D or 3D; z is ignored in 2D
inline bool finite3(const Triple& t) {
  return std::isfinite(t[0]) && std::isfinite(t[1]) && std::isfinite(t[2]);
}

struct ParticleSpec {
  Triple position{};
  Triple velocity{};
  Triple spin{};  // 2D: spin[2] is the spin about z
  double radius = 0;
  int material = -1;
  bool fixed = false;
};

struct WallSpec {
  std::string name;
  WallType type = WallType::plane;
  int material = -1;
  Triple point{}, normal{}, velocity{};  // plane
  Triple center{}, axis{0, 0, 1};        // cylinder
  double radius = 0;
  bool inside = true;
  double angular_velocity = 0;
  double angle = 0;  // mesh, polyline: turned about the axis since added [rad]
  // Finite walls (geometry/finite_walls.hpp); a disk uses center, normal and radius.
  bool bounded = false;                 // plane: a rectangle; cylinder: a tube
  Triple side{};                        // rectangle (3D): first side's direction; zero: default
  double size_a = 0, size_b = 0;        // rectangle's sides [m] (size_b: 3D)
  double inner_radius = 0;              // disk: its hole's radius [m]
  double z_lo = 0, z_hi = 0;            // tube, cone: the axial bounds from center [m]
  double radius_lo = 0, radius_hi = 0;  // cone: its radii at z_lo and z_hi [m]
  bool finite() const { return is_finite_wall(type, bounded); }
};

// A triangle-mesh wall (3D): its triangles (placed in the scene: read by
// io/mesh_file.hpp), and its rigid motion: translation at `velocity`, turning
// at `angular_velocity` about `axis` through `axis_point`.
struct MeshWallSpec {
  std::string name, file;  // the file: where the triangles came from
  int material = -1;
  Triple velocity{}, axis_point{}, axis{0, 0, 1};
  double angular_velocity = 0;
  double flat_angle = 20;             // degrees: MeshSurface::set_flat_angle
  std::vector<std::string> warnings;  // the file's harmless defects, passed on to the scene
};

// A polyline wall (2D): its points (x, y) in the scene, joined in order
// (and the last to the first when closed); an arc on segment k (from point
// k to point k + 1, counted from 1) of signed radius R, positive bulging to
// the left of the segment's direction; the same rigid motion as a mesh's,
// turning about z through `axis_point`.
struct PolylineWallSpec {
  struct Arc {
    std::int64_t segment = 0;  // from 1
    double radius = 0;         // m, signed
  };
  std::string name;
  int material = -1;
  std::vector<std::array<double, 2>> points;
  bool closed = false;
  bool solid = false;  // closed only: its inside is a body (fill{} places no particle there)
  std::vector<Arc> arcs;
  Triple velocity{}, axis_point{};
  double angular_velocity = 0;
};

// A mesh wall's triangles where they are now (output, pictures); a polyline's
// outline (its arcs in short pieces) as the vertices, the pieces as `lines`.
struct MeshView {
  int wall = -1;
  std::vector<Triple> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<std::array<std::uint32_t, 2>> lines;
};

enum class RegionShape { ball, box, cylinder };

struct FillSpec {
  RegionShape shape = RegionShape::ball;
  Triple center{}, lo{}, hi{};
  double radius = 0;            // ball / cylinder radius
  double z_min = 0, z_max = 0;  // cylinder (3D) extent along z
  std::int64_t count = 0;
  std::vector<double> radii;              // drawn uniformly from this list
  double radius_min = 0, radius_max = 0;  // or uniform in [min, max] when radii is empty
  int material = -1;
  std::uint64_t seed = 1;
  double max_speed = 0;  // m/s, random velocities in [0, max_speed], then zero net momentum
  std::int64_t max_attempts = 0;  // 0: 2000 per particle, in all
  bool allow_overlap = true;      // false: no new particle overlaps any other particle
  // Asked now and then: true ends the fill at once (a signal), fill() adding no
  // particle and returning an empty list.
  std::function<bool()> stop_requested;
};

struct GlobalStats {
  double time = 0;
  std::int64_t step = 0;
  std::int64_t particles = 0;
  double kinetic_translational = 0;  // J
  double kinetic_rotational = 0;     // J
  double free_mass = 0;              // kg, of the particles that are not fixed
  Triple momentum{};                 // kg m/s
  double angular_momentum_z = 0;     // kg m^2/s about the origin (z component)
  std::int64_t contacts_particle = 0;
  std::int64_t contacts_wall = 0;
  // of contacts_particle, those a model's batched kernel computed (3D pairs:
  // contact/contact_batch.hpp); the rest went one at a time
  std::int64_t contacts_batched = 0;
  std::int64_t contacts_wall_batched = 0;  // of contacts_wall, likewise
  double max_overlap_ratio = 0;            // largest overlap / smaller radius in the last step
  std::int64_t candidate_pairs = 0;  // neighbour-list entries (pairs and walls) within the skin
  std::int64_t list_rebuilds = 0;    // neighbour-list rebuilds since the start
  // times the threads' shares of the pair contacts were moved to even out their
  // work (more than one thread; see Simulation::rebalance)
  std::int64_t thread_rebalances = 0;
  // times the pair lists were pruned (set_pruning): all of them at once when
  // the particles may have closed the prune distance, one bucket at a time
  // after a rebuild or a rebalance
  std::int64_t pair_list_prunes = 0;
  // pair candidates the last step's listing pass visited: all of them, or
  // those the pruned lists kept
  std::int64_t pair_candidates_visited = 0;
};

// One contact as the last step saw it (recorded only when asked for).
struct ContactRecord {
  std::int64_t id_a = -1;
  std::int64_t id_b = -1;  // -1 for a wall contact
  int wall = -1;
  std::string model;
  double overlap = 0;
  double normal_force = 0;
  Triple tangential_force{};  // on a
  Triple normal{};            // from b (or the wall) to a
};

struct Hook {
  std::string name;
  std::int64_t every_steps = 0;  // fire when step % every_steps == 0 (if > 0)
  double every_time = 0;         // or every this many simulated seconds (if > 0)
  // A time hook is next due at origin_time + periods * every_time: counted from
  // when it was added, as a product rather than a running sum, whose round-off
  // would move a firing by a step over a long run.
  double origin_time = 0;
  std::int64_t periods = 0;
  double next_time() const { return origin_time + static_cast<double>(periods) * every_time; }
  // Also fires once before the first step of a run that starts at step 0 (the
  // snapshot of the initial state, t = 0).
  bool at_start = false;
  std::function<void()> fire;
  int id = 0;
  // True when the firing reads nothing but stats() (the output's series row):
  // a run spread over MPI ranks then reduces the totals over the ranks
  // instead of gathering the whole scene. Empty: the hook may read anything.
  std::function<bool()> totals_only;
  // True when the firing only reads the particles (flat_state, flat_forces,
  // particle_count), stats() and the scene's declarations, and changes
  // nothing (the output's snapshots): a spread run then gathers those
  // alone and keeps the ranks' shares.
  std::function<bool()> state_only;
  // A script's function (sim:every): it reaches the scene only through the
  // Lua API, whose calls make a spread scene whole when they need it
  // (set_pending_gather).
  bool script = false;
};

// What a firing hook reads (Hook::totals_only, Hook::state_only, Hook::script).
enum class HookReads { scene, totals, state, script };

// A pair in use whose law stiffens as it is pressed (the Hertzian laws): its
// stiffest mode at an overlap, which the rule and the limit (taken from the
// Rayleigh time, the contact as it begins) do not see grow.
struct DeepContactMode {
  std::string pair;                             // "a-b (model, kind)"
  double smaller_radius = 0;                    // m, of its smallest particles
  bool wall = false;                            // a particle-wall pair
  int material_a = -1, material_b = -1;         // the particle's, the other's (or the wall's)
  std::function<double(double)> omega_squared;  // at an overlap [m]: 1/s^2
};

// The automatic step's rule by name: Eq. 4.1's t_c / n for the laws whose rule is
// per contact (linear, Walton-Braun), Thornton's 8 T_R / n for Hertz's laws.
inline const char* time_step_rule_name(bool per_contact) {
  return per_contact ? "t_c / n (Eq. 4.1)" : "8 T_R / n (Eqs. 6.1-6.2)";
}

struct TimeStepReport {
  double rule = 0;             // Eq. 4.1 (or the model's analogue) over the pairs in use, s
  double stability_limit = 0;  // 1 / omega_max (half of leap-frog's 2 / omega_max), s
  std::string governing_pair;  // "a-b (model)": the pair whose rule is shortest
  bool per_contact = true;     // its model's rule is t_c / n (else 8 T_R / n: Hertz's laws)
  std::string limit_pair;      // the pair whose stability limit is shortest
  std::vector<DeepContactMode> deep_modes;
};

// What a prepared scene simulates, and so what its step pays for: the run
// header prints it and the output writes it as attributes of /scene/effects.
// "In use" means that the materials can meet: a material some particle has,
// against a material some particle or wall has.
struct ActiveEffects {
  int dimension = 0;
  bool periodic = false;
  std::vector<std::string> pairs;           // "a-b model" for every pair in use
  std::vector<std::string> adhesive_pairs;  // those whose model is adhesive (JKR)
  bool adhesion = false;                    // an adhesive pair is in use
  bool friction = false;                    // a pair in use has friction > 0
  bool rolling = false;                     // a pair in use has rolling resistance
  bool bonds = false;                       // parallel bonds are intact
  bool rotation =
      false;  // spins are integrated (friction, rolling, bonds or adhesion: else no torque)
  bool gravity = false;
  bool central_field = false;
  bool damping = false;  // sim:damping: viscous or local damping of the particles' motion
  std::vector<std::string> moving_walls;  // planes with a velocity, cylinders that turn
  std::vector<std::string> diagnostics;
  bool contacts_recorded = false;
  bool canonical_order = false;  // sums in particle-id order (SimulationBase::set_canonical_order)
  int hooks = 0;
  int threads = 1;
  int ranks = 1;              // MPI ranks the scene is spread over (SimulationBase::set_spread)
  std::string decomposition;  // how space is split among them ("" on one process)
};

class SimulationBase {
 public:
  virtual ~SimulationBase() = default;
  virtual int dimension() const = 0;

  // ---- set-up ----
  int add_material(const Material& m);
  int material_id(const std::string& name) const;  // throws InputError with a suggestion
  const std::vector<Material>& materials() const { return materials_; }
  void set_contact(const std::string& a, const std::string& b, const std::string& model,
                   const ParamValues& given);
  void update_contact(const std::string& a, const std::string& b, const ParamValues& changes);
  // A scene's declaration of the law between a and b, made at `where` (its
  // file:line): a second one for the pair, in either order, is refused naming
  // both places, so that a law is never replaced by accident (set_contact
  // changes parameters on purpose).
  void declare_contact(const std::string& a, const std::string& b, const std::string& model,
                       const ParamValues& given, const std::string& where);
  const PairTable& pair_table() const { return pairs_; }

  virtual int add_wall(const WallSpec& spec) = 0;
  // 3D only; returns the wall's index (simulation_meshes.cpp).
  virtual int add_mesh_wall(const MeshWallSpec& spec, Triangles mesh) = 0;
  // 2D only; returns the wall's index (simulation_polylines.cpp).
  virtual int add_polyline_wall(const PolylineWallSpec& spec) = 0;
  // Polyline wall w as declared (its own frame); refused for other walls.
  virtual PolylineWallSpec polyline_wall(int w) const = 0;
  virtual std::vector<MeshView> mesh_views() const = 0;
  // Triangles examined by the mesh contact searches so far (neighbour lists and steps).
  virtual std::int64_t mesh_triangles_tested() const = 0;
  virtual std::int64_t add_particle(const ParticleSpec& spec) = 0;
  virtual std::vector<std::int64_t> fill(const FillSpec& spec) = 0;
  virtual void remove_particle(std::int64_t id) = 0;

  // ---- settings ----
  void set_time_step(double dt);  // > 0 fixed; 0 = Eq. 4.1 rule (default)
  void set_steps_per_contact(double n);
  void set_skin(double skin);  // m; 0 = automatic (half the median radius)
  // Pair overlaps above this fraction of the smaller radius are warned of once (0 < f <= 1).
  void set_overlap_warning(double fraction);
  double overlap_warning() const { return overlap_warning_; }
  void set_periodic(int axis, double origin, double length);
  bool is_periodic() const { return periodic_.on(); }
  const Periodicity& periodicity() const { return periodic_; }
  void set_record_contacts(bool on) { record_contacts_ = on; }
  // Threads for the contact and integration loops. The results do not depend
  // on it: each contact force is computed once and the forces on a particle are
  // summed in a fixed order. 0 (the default) means OMP_NUM_THREADS if it is set,
  // else 1: on a shared machine a second thread that is not scheduled stalls
  // every parallel loop, so using more cores is the user's explicit choice.
  void set_threads(std::int64_t threads);  // (wide: a script's 2^32 + 3 is refused, not 3)
  int threads() const { return threads_; }
  int thread_count() const;  // what the loops use
  // Below these sizes a loop runs on one thread whatever set_threads() says: a
  // parallel region costs microseconds (more on a shared machine), more than a
  // small scene's whole step (the 2D base case's contact loop takes ~10 us).
  // The results are the same either way; tests lower them to exercise the
  // parallel paths on small scenes.
  void set_parallel_thresholds(std::int64_t min_candidates, std::int64_t min_particles) {
    parallel_min_candidates_ = min_candidates;
    parallel_min_particles_ = min_particles;
  }
  // 3D pair contacts of a model with a batched kernel take it (default), or
  // one contact at a time: the same results to round-off (tests compare the two).
  void set_batched_contacts(bool on) { batched_contacts_ = on; }
  // Pruned pair lists (default on): between prunes the contact loop's listing
  // pass visits only the candidates that were within the prune distance of
  // touching (or in contact) when last pruned, and no particle can have closed
  // that gap since. The distance, 1/32 to 1/4 of the skin, is tuned as the run
  // goes (Simulation::tune_prune_distance). The results are the same bit for
  // bit either way.
  void set_pruning(bool on) { pruning_ = on; }
  // Canonical order (default off): at each neighbour-list rebuild the pair
  // candidates are sorted by (lower id, higher id) and the wall candidates by
  // particle id, and stats() sums over the particles in id order, so every
  // particle's force and torque sums, and so the whole run, are the same bit
  // for bit whatever order the particles are stored in (and whatever the
  // threads). Costs a sort per rebuild and the caches' Morton-order locality
  // (docs/parallel.md, "Canonical order"). Takes effect at the next prepare().
  void set_canonical_order(bool on) {
    if (on != canonical_order_) unprepare();  // the lists are rebuilt in the new order
    canonical_order_ = on;
  }
  bool canonical_order() const { return canonical_order_; }
  bool record_contacts() const { return record_contacts_; }
  void set_warning_handler(std::function<void(const std::string&)> f) { warn_ = std::move(f); }
  // A warning through the handler (the bindings' too: what a file they read holds).
  void warn(const std::string& message) const;

  // body forces
  virtual void set_gravity(const Triple& g) = 0;
  virtual void set_central_field(const Triple& point, double strength) = 0;
  virtual void set_central_strength(double strength) = 0;
  virtual void clear_central_field() = 0;
  virtual double central_strength() const = 0;
  // Damping of the particles' motion (fields/damping.hpp): checked, in effect from the next step.
  void set_damping(const Damping& d);
  const Damping& damping() const { return damping_; }

  // walls
  virtual int wall_count() const = 0;
  virtual int wall_id(const std::string& name) const = 0;
  virtual WallSpec wall(int w) const = 0;
  virtual void set_wall_velocity(int w, const Triple& v) = 0;
  virtual void set_wall_angular_velocity(int w, double omega) = 0;
  virtual Triple wall_force(int w) const = 0;  // N, by the particles on the wall, last step
  virtual double wall_axial_torque(int w) const = 0;

  // ---- particle access by persistent id ----
  virtual std::int64_t particle_count() const = 0;
  virtual std::vector<std::int64_t> particle_ids() const = 0;
  virtual bool has_particle(std::int64_t id) const = 0;
  // Ids run from 0 to this less one: every particle the scene ever had, removed or not.
  virtual std::int64_t ids_handed_out() const = 0;
  virtual Triple position(std::int64_t id) const = 0;
  virtual Triple velocity(std::int64_t id) const = 0;
  virtual Triple spin(std::int64_t id) const = 0;
  virtual Triple force(std::int64_t id) const = 0;
  virtual double radius(std::int64_t id) const = 0;
  virtual double mass(std::int64_t id) const = 0;
  virtual int material_of(std::int64_t id) const = 0;
  virtual bool is_fixed(std::int64_t id) const = 0;
  virtual void set_position(std::int64_t id, const Triple& x) = 0;
  virtual void set_velocity(std::int64_t id, const Triple& v) = 0;
  virtual void set_spin(std::int64_t id, const Triple& w) = 0;
  // Fixes a particle where it is (at rest, infinite mass) or frees it (at rest).
  virtual void set_fixed(std::int64_t id, bool fixed) = 0;

  // Flat copies of the state, ids in storage order; position/velocity rows of `dimension()`.
  struct FlatState {
    std::vector<std::int64_t> id;
    std::vector<double> radius, position, velocity, spin;
    std::vector<std::int32_t> material;
    std::vector<std::uint8_t> fixed;
  };
  virtual FlatState flat_state() const = 0;
  // The force [N] and torque [N m] on each particle in the last step, in flat_state()'s
  // order: rows of dimension() and of 1 (2D, about z) or 3 components.
  virtual void flat_forces(std::vector<double>& force, std::vector<double>& torque) const = 0;
  // Gravity [m/s^2] and the central field (point [m], strength), as the output records them.
  struct BodyFields {
    Triple gravity{};
    bool central_on = false;
    Triple central_point{};
    double central_strength = 0;
  };
  virtual BodyFields body_fields() const = 0;

  // ---- running ----
  // Validates the scene (contact laws for every pair in use, particles inside
  // the walls, periodic box large enough), chooses dt, builds neighbour lists.
  virtual void prepare() = 0;
  // Whether a change since the last prepare() still waits for one (step() makes it).
  bool prepared() const { return prepared_; }
  void set_external_rebuilds(bool on) { external_rebuilds_ = on; }
  // Whether this process holds its share of a scene spread over several ranks (a step
  // of a distributed run is under way), not the whole scene.
  void set_holds_share(bool on) { holds_share_ = on; }
  bool holds_share() const { return holds_share_; }
  void ensure_prepared() {
    if (!prepared_) prepare();
  }
  virtual void advance(std::int64_t steps) = 0;  // prepare() if needed, then `steps` steps
  virtual TimeStepReport time_step_rule() = 0;
  double time() const { return time_; }
  std::int64_t step_count() const { return step_; }
  double time_step() const { return dt_; }
  // The step and the time from which the time step has been what it is (the
  // last prepare() that changed it, or a checkpoint's load): a run counting its
  // steps again from there gets the same count wherever it looks.
  std::int64_t time_step_from_step() const { return dt_from_step_; }
  double time_step_from_time() const { return dt_from_time_; }
  bool time_step_is_automatic() const { return dt_fixed_ == 0; }
  double steps_per_contact() const { return steps_per_contact_; }
  double skin() const { return skin_; }
  virtual GlobalStats stats() const = 0;
  virtual std::vector<ContactRecord> contacts() const = 0;
  // Lines describing what this scene simulates (models in use, walls, fields, hooks).
  virtual std::vector<std::string> describe() const = 0;
  // What the scene simulates (see ActiveEffects); valid before and after prepare().
  virtual ActiveEffects effects() const = 0;

  // ---- parallel bonds (contact/parallel_bond.hpp; simulation_bonds.cpp) ----
  // Bonds every pair that matches `spec` and has none yet (prepares the scene
  // first); returns how many were made. InputError naming the parameter for
  // bad values, or a time step the bonds' stiffness makes unstable.
  virtual std::int64_t create_bonds(const BondSpec& spec) = 0;
  struct BondCounts {
    std::int64_t intact = 0, broken = 0;
  };
  virtual BondCounts bond_counts() const = 0;
  // Every bond in the order made: the ids it joins (a < b) and whether it has broken.
  struct BondRecord {
    std::int64_t id_a = -1, id_b = -1;
    bool broken = false;
  };
  virtual std::vector<BondRecord> bond_records() const = 0;

  // ---- checkpoints ----
  virtual StateBlob save_state() const = 0;
  // Bonds whose particles sim:set_position moved since the last step: each that the
  // moves widened by more than the pair's smaller radius breaks (warned). Done at
  // the next step and before a checkpoint, so that moving a bonded cluster one
  // particle at a time keeps its bonds.
  virtual void settle_moved_bonds() = 0;
  virtual void load_state(const StateBlob& state) = 0;
  // Contact histories from a file (io/contact_histories.hpp) that lack the
  // "rolling_springs" entry, as older builds wrote them: the first rolling
  // law whose springs they hold wound as torques where this build holds
  // M / sqrt(k) (rolling.hpp), or "" (nothing this build would misread).
  virtual std::string wound_legacy_rolling_springs(const StateBlob& saved) const = 0;
  // The attached diagnostics' accumulators (simulation_diagnostics.cpp).
  // load_diagnostics() needs the same diagnostics attached, in the same order
  // and with the same options, and the particles' state loaded first.
  virtual void save_diagnostics(StateBlob& blob) const = 0;
  virtual void load_diagnostics(const StateBlob& blob) = 0;

  // ---- diagnostics (src/hooks): C++ observers attached by name ----
  virtual int attach_diagnostic(const std::string& name, DiagnosticOptions& options) = 0;
  virtual void detach_diagnostic(int id) = 0;
  virtual std::map<std::string, double> diagnostic_results(int id) const = 0;
  virtual std::map<std::string, std::vector<double>> diagnostic_arrays(int id) const = 0;
  // Where diagnostics write their rows (the run's HDF5 output); nullptr detaches.
  virtual void set_output_sink(OutputSink* sink) = 0;
  // Writes partly filled windows (end of a run).
  virtual void flush_diagnostics() = 0;

  // ---- schedules (simulation_schedules.cpp): values that follow time ----
  // Checks the target, sets it to its value now, and from then on before every step.
  // Returns the schedule's id (1, 2, ...).
  int add_schedule(ScheduleSpec spec);
  // Ends a schedule: its target keeps the value it has now.
  void remove_schedule(int id);
  // A value set by hand takes its target from a schedule that has set its last
  // value: wall w's "velocity" or "angular_velocity", a contact parameter of a-b,
  // or the central field's strength. Refused (InputError) while the schedule
  // will still set it (before its last point).
  void claim_scheduled_wall(int w, const std::string& key);
  void claim_scheduled_contact(const std::string& a, const std::string& b, const std::string& key);
  void claim_scheduled_field(const char* caller);
  // A new schedule of a target another schedule still sets (before its last point):
  // refused (InputError), as each would set its own value. Not while a restart
  // replays: the replay's engine is not at the time the first run checked it.
  void claim_schedule_target(const ScheduleSpec& spec);
  // Sets every scheduled value to its value at the current time.
  void apply_schedules();
  const std::vector<ScheduleSpec>& schedules() const { return schedules_; }
  // Checkpoints: the schedules as declared; a restart that declares others is refused.
  void save_schedules(StateBlob& blob) const;
  void load_schedules(const StateBlob& blob);

  // ---- hooks ----
  int add_hook(Hook hook);
  void remove_hook(int id);
  std::size_t hook_count() const { return hooks_.size(); }
  bool has_hook(int id) const {
    for (const auto& h : hooks_)
      if (h.id == id) return true;
    return false;
  }
  // A run spread over MPI ranks (engine/spread_run.hpp) fires the hooks on the
  // whole scene: `wrapper` is called with each firing (it gathers the scene,
  // then calls the firing). An empty function fires them directly again.
  using HookWrapper = std::function<void(HookReads reads, const std::function<void()>& fire)>;
  void set_hook_wrapper(HookWrapper wrapper) { hook_wrapper_ = std::move(wrapper); }
  bool hooks_wrapped() const { return static_cast<bool>(hook_wrapper_); }
  // The at_start hooks, before step 0 (advance() fires them itself).
  void fire_start_hooks();
  // A script callback on a scene spread over ranks, fired with the shares
  // kept: the first script call that reads or changes the scene calls
  // `gather` (the scene made whole, as for any other hook), while stats()
  // needs only `totals` (reduced over the ranks, the shares kept), and the
  // time, the step and setting a wall's velocities (what every rank holds
  // alike) need neither. Every rank runs the same callback, so every rank
  // makes the same calls and the same collectives. Empty functions: nothing pending.
  void set_pending_gather(std::function<void()> gather, std::function<void()> totals) {
    pending_gather_ = std::move(gather);
    pending_totals_ = std::move(totals);
  }
  void ensure_whole() {
    if (!pending_gather_) return;
    const std::function<void()> gather = std::move(pending_gather_);
    pending_gather_ = nullptr;
    pending_totals_ = nullptr;
    gather();
  }
  void ensure_totals() {
    if (!pending_totals_) return;
    const std::function<void()> totals = std::move(pending_totals_);
    pending_totals_ = nullptr;
    totals();
  }
  // The scene is spread over `ranks` MPI ranks, space split as `how`: the run
  // header and /scene/effects say so.
  void set_spread(int ranks, std::string how) {
    spread_ranks_ = ranks;
    spread_how_ = std::move(how);
  }
  int spread_ranks() const { return spread_ranks_; }

  // Called when a run fails (NaN, escape) just before the error propagates.
  void set_failure_handler(std::function<void(const std::string&)> f) {
    on_failure_ = std::move(f);
  }

  // Wall-clock seconds spent per stage of step() since construction.
  struct StageTimes {
    double neighbor = 0, force = 0, diagnostics = 0, integrate = 0, hooks = 0;
    // part of `force`, threads > 1: what keeps the sums per particle in slot
    // order (marking the particles two threads share, adding their deferred
    // forces, summing the reactions on the walls)
    double scatter = 0;
    double walls = 0;  // part of `force`: the particle-wall contacts
    // threads > 1: thread-seconds the pair loop's threads waited for one
    // another at its barrier, summed over the threads (how unevenly they finished)
    double pair_wait = 0;
  };
  const StageTimes& stage_times() const { return stage_times_; }

 protected:
  void fire_hooks();
  // Calls the failure handler and throws RunError: `what` went wrong, then what the
  // output keeps of the state ("this state", or the particles' "last finite state").
  void fail(const std::string& what, const char* kept = "this state");

  std::vector<Material> materials_;
  PairTable pairs_;
  std::map<std::pair<int, int>, std::string> contact_declared_at_;  // (a <= b) -> file:line
  double dt_ = 0;
  std::int64_t dt_from_step_ = 0;
  double dt_from_time_ = 0;
  // The clock: time_ = clock_time_ + (step_ - clock_step_) dt_, taken afresh
  // from where the step changed (clock_dt_: the step it was taken with). A
  // running sum of dt would drift by round-off, ~1e-7 dt after 1e5 steps,
  // enough to move a firing at a time that dt divides by a step.
  double clock_time_ = 0;
  std::int64_t clock_step_ = 0;
  double clock_dt_ = 0;
  double dt_fixed_ = 0;
  double steps_per_contact_ = 40;  // Eq. 4.1, n = 40 in the dissertation
  double skin_ = 0;
  double skin_set_ = 0;
  double overlap_warning_ = 0.1;
  bool overlap_warned_ = false;
  bool wall_overlap_warned_ = false;  // the once-only warning of a deep wall contact
  // Set by what places particles (Simulation::arm_overlap_grace): overlaps deeper than
  // a radius are then the scene's (coincident particles, an overlapping fill) until
  // every pair is back under overlap_warning, or, for particles placed mid-run,
  // every pair with one of them (check_overlaps, Simulation::end_placed_grace_with).
  bool scene_overlaps_ = false;
  Periodicity periodic_;
  bool record_contacts_ = false;
  int threads_ = 0;
  std::int64_t parallel_min_candidates_ = 32768, parallel_min_particles_ = 16384;
  bool batched_contacts_ = true;
  std::function<void()> pending_gather_, pending_totals_;  // set_pending_gather
  bool pruning_ = true;
  bool canonical_order_ = false;
  bool prepared_ = false;
  // The only change since the last prepare() is a contact law's parameters
  // (update_contact: a schedule's ramp, sim:set_contact): the lists still
  // hold, so prepare() re-chooses the time step, the spin flag and the
  // adhesive reach and keeps them (simulation_prepare.cpp).
  bool lists_kept_ = false;
  void unprepare() { prepared_ = false, lists_kept_ = false; }
  bool external_rebuilds_ = false;  // a distributed run rebuilds the lists (install_share)
  bool holds_share_ = false;        // holds_share()
  double time_ = 0;
  std::int64_t step_ = 0;
  std::int64_t failed_at_step_ = -1;  // the step a run failed at (fail()), -1 for none
  Damping damping_;
  std::vector<Hook> hooks_;
  std::vector<ScheduleSpec> schedules_;
  int next_schedule_id_ = 1;
  int next_hook_id_ = 1;
  HookWrapper hook_wrapper_;
  int spread_ranks_ = 1;
  std::string spread_how_;
  std::function<void(const std::string&)> warn_;
  std::function<void(const std::string&)> on_failure_;
  StageTimes stage_times_;
};

std::unique_ptr<SimulationBase> make_simulation(int dimension);
// Memory the machine can give this process now (MemAvailable, else sysconf's
// free pages), in bytes; 0 when unknown.
double available_memory_bytes();

}  // namespace granule
