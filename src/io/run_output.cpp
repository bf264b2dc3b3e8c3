#include "io/run_output.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "core/errors.hpp"
#include "core/fnv1a.hpp"
#include "io/output_units.hpp"
#include "io/rank_files.hpp"

namespace granule::io {

namespace {
// A digest of the particles' state (and the snapshot's flags), defined below.
std::int64_t state_digest(const SimulationBase::FlatState& s, bool forces, bool contacts);

const std::vector<std::string> series_columns = {"time",
                                                 "step",
                                                 "kinetic_energy_translational",
                                                 "kinetic_energy_rotational",
                                                 "contacts_particle",
                                                 "contacts_wall",
                                                 "max_overlap_ratio",
                                                 "momentum_x",
                                                 "momentum_y",
                                                 "momentum_z",
                                                 "angular_momentum_z"};
std::vector<std::string> units_of(const std::vector<std::string>& columns) {
  std::vector<std::string> units;
  for (const auto& c : columns) units.emplace_back(unit_of(c));  // io/output_units.hpp
  return units;
}

std::vector<std::string> split_units(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = text.find(',', start);
    std::string part = text.substr(start, comma == std::string::npos ? comma : comma - start);
    part.erase(0, part.find_first_not_of(' '));
    part.erase(part.find_last_not_of(' ') + 1);
    out.push_back(part);
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}
}  // namespace

RunOutput::RunOutput(SimulationBase& sim, RunOutputSettings settings)
    : sim_(sim), settings_(std::move(settings)) {
  if (settings_.path.empty()) throw InputError("output: 'file' must not be empty");
  if (settings_.snapshot_every < 0 || !std::isfinite(settings_.snapshot_every))
    throw InputError(
        fmt::format("output: snapshot_every must be >= 0 [s], got {}", settings_.snapshot_every));
  if (settings_.series_every < 0 || !std::isfinite(settings_.series_every))
    throw InputError(
        fmt::format("output: series_every must be >= 0 [s], got {}", settings_.series_every));
  if (settings_.contacts && !sim_.record_contacts())
    throw InputError(
        "output: contacts = true writes the contact network, which needs "
        "simulation { record_contacts = true }");
  if (!settings_.muted) {
    file_ = std::make_unique<H5Output>(settings_.path);
    if (settings_.xdmf) xdmf_ = std::make_unique<XdmfIndex>(settings_.path);
    file_->series_declare("/series", series_columns, units_of(series_columns));
  }
  Hook series;
  series.name = "output.series";
  if (settings_.series_every > 0)
    series.every_time = settings_.series_every;
  else
    series.every_steps = 100;
  // A row of the initial state too, as of the final one (end_of_run): a run
  // shorter than the cadence still has its start and end in /series.
  series.at_start = true;
  series.fire = [this] { write_series_row(); };
  // Once the header is written the row reads stats() alone (a run spread over
  // MPI ranks then reduces the totals rather than gathering the scene).
  series.totals_only = [this] { return header_written_; };
  hook_ids_.push_back(sim_.add_hook(series));
  // Snapshots: the initial state (t = 0, before the first step), then every
  // snapshot_every seconds, or (0) only the last besides.
  Hook snap;
  snap.name = "output.snapshot";
  snap.every_time = settings_.snapshot_every > 0 ? settings_.snapshot_every
                                                 : std::numeric_limits<double>::infinity();
  snap.at_start = true;
  snap.fire = [this] {
    if (sim_.particle_count() > 0) write_snapshot();
  };
  // Once the header is written a snapshot reads only the particles (a run
  // spread over MPI ranks then gathers them alone); the contact network is the
  // scene's (and refused on ranks).
  snap.state_only = [this] { return header_written_ && !settings_.contacts; };
  hook_ids_.push_back(sim_.add_hook(snap));
  sim_.set_failure_handler([this](const std::string& m) { write_failure(m); });
  sim_.set_output_sink(this);
  // Opened after the scene has stepped (a later stage's file, at the REPL): the
  // start's hooks fire only before step 0, so the next run (or the end, if none
  // follows) records the state it starts from (record_opening).
  opening_due_ = file_ && sim_.step_count() > 0;
}

void RunOutput::record_opening() {
  if (!opening_due_ || !file_) return;
  opening_due_ = false;
  write_series_row(true);
  if (sim_.particle_count() > 0) write_snapshot();
}

RunOutput::~RunOutput() {
  for (int id : hook_ids_) sim_.remove_hook(id);
  sim_.set_failure_handler(nullptr);
  try {
    finish();
  } catch (...) {
    // A destructor must not throw; finish() already reported through the file it could write.
  }
  sim_.set_output_sink(nullptr);
}

void RunOutput::note_scene_error(const std::string& message) noexcept {
  if (finished_ || !file_ || failure_step_ == sim_.step_count()) return;
  try {
    write_header();
  } catch (...) {
    // The file refuses writes (the error may be that refusal): the reason may still fit.
  }
  try {
    // The reason without Lua's traceback, which names the scene's lines, not the file's state.
    const std::string reason = message.substr(0, message.find("\nstack traceback:"));
    file_->record_failure(fmt::format("the scene ended on an error at t = {} s (step {}): {}",
                                      sim_.time(), sim_.step_count(), reason));
  } catch (...) {
    // The error itself is reported on the terminal; finish() reports a file it cannot write.
  }
}

void RunOutput::finish() {
  if (finished_ || !file_) return;
  finished_ = true;
  record_opening();  // opened after the scene had stepped, and no run since
  write_header();
  write_new_walls();
  // Partly filled windows, while the file is open (not those a failure just cut).
  if (failure_step_ != sim_.step_count()) sim_.flush_diagnostics();
  // The final state, unless the last snapshot holds it: one of this step whose
  // particles a callback changed after it was written (a removal, a new velocity)
  // does not.
  if (sim_.particle_count() > 0 && failure_step_ != sim_.step_count() &&
      (sim_.step_count() != last_snapshot_step_ ||
       state_digest(sim_.flat_state(), false, false) != last_snapshot_state_))
    write_snapshot();
  file_->flush();
  if (xdmf_) xdmf_->flush();
}

void RunOutput::flush() {
  if (finished_ || !file_) return;
  write_header();
  // Not the walls a script added since the header: their geometry is written as
  // it stands when written (a platen that has moved), so at the snapshots and
  // the end, steps the scene sets, never at a flush that wall time sets.
  file_->flush();
  // The index after the groups it names are on disk, and only when due: a long
  // run's index rewritten every second would cost as much as at every snapshot.
  if (xdmf_) xdmf_->flush_if_due();
  last_flush_ = std::chrono::steady_clock::now();
}

void RunOutput::flush_if_due() {
  const auto now = std::chrono::steady_clock::now();
  if (std::chrono::duration<double>(now - last_flush_).count() >= 1.0) flush();
}

SnapshotView RunOutput::view(const SimulationBase::FlatState& s,
                             std::vector<std::string> names) const {
  SnapshotView v;
  v.step = sim_.step_count();
  v.time = sim_.time();
  v.dimension = sim_.dimension();
  v.spin_components = sim_.dimension() == 2 ? 1 : 3;
  v.count = s.id.size();
  v.id = s.id.data();
  v.radius = s.radius.data();
  v.position = s.position.data();
  v.velocity = s.velocity.data();
  v.spin = s.spin.data();
  v.material = s.material.data();
  v.fixed = s.fixed.data();
  v.material_names = std::move(names);
  return v;
}

// The walls not yet in the file, each as /walls/<name> with its geometry when
// first written: at the header, and at every snapshot and the end for walls a
// script adds later (walls are never removed, so a count is enough).
void RunOutput::write_new_walls() {
  if (header_written_) write_new_laws();  // a later stage's materials and laws, as its walls
  if (sim_.wall_count() <= walls_written_) return;
  H5Output& f = *file_;
  const auto& mats = sim_.materials();
  for (int w = walls_written_; w < sim_.wall_count(); ++w) {
    WallSpec s = sim_.wall(w);
    std::string g = "/walls/" + s.name;
    std::vector<double> centre(s.center.begin(), s.center.begin() + sim_.dimension());
    std::vector<double> point(s.point.begin(), s.point.begin() + sim_.dimension());
    std::vector<double> normal(s.normal.begin(), s.normal.begin() + sim_.dimension());
    f.write_attribute(g, "type", std::string(wall_type_name(s.type)));
    // The number contacts/wall and sim:contact_arrays() give this wall (0-based,
    // in declaration order; HDF5 lists the groups by name).
    f.write_attribute(g, "index", static_cast<std::int64_t>(w));
    f.write_attribute(g, "material", mats[s.material].name);
    const bool finite = s.finite();
    auto vec = [&](const Triple& t) {
      return std::vector<double>(t.begin(), t.begin() + sim_.dimension());
    };
    if (s.type == WallType::mesh) {
      f.write_attribute(g, "axis_point", centre);
    } else if (s.type == WallType::polyline) {
      f.write_attribute(g, "axis_point", centre);
      // As declared, in the polyline's own frame: points (x1, y1, x2, ...),
      // closed, and each segment's signed arc radius (0: straight).
      const PolylineWallSpec line = sim_.polyline_wall(w);
      std::vector<double> points;
      for (const auto& x : line.points) points.insert(points.end(), {x[0], x[1]});
      std::vector<double> radius(line.closed ? line.points.size() : line.points.size() - 1, 0.0);
      for (const auto& a : line.arcs) radius[static_cast<std::size_t>(a.segment - 1)] = a.radius;
      f.write_attribute(g, "points", points);
      f.write_attribute(g, "closed", static_cast<std::int64_t>(line.closed ? 1 : 0));
      f.write_attribute(g, "solid", static_cast<std::int64_t>(line.solid ? 1 : 0));
      f.write_attribute(g, "arc_radius", radius);
    } else if (s.type == WallType::plane) {
      f.write_attribute(g, "point", point);
      f.write_attribute(g, "normal", normal);
      if (finite) {
        f.write_attribute(g, "size", std::vector<double>{s.size_a, s.size_b});
        f.write_attribute(g, "side", vec(s.side));
      }
    } else if (s.type == WallType::disk) {
      f.write_attribute(g, "center", centre);
      f.write_attribute(g, "normal", normal);
      f.write_attribute(g, "radius", s.radius);
      f.write_attribute(g, "inner_radius", s.inner_radius);
    } else if (s.type == WallType::cone) {
      f.write_attribute(g, "center", centre);
      f.write_attribute(g, "axis", vec(s.axis));
      f.write_attribute(g, "bounds", std::vector<double>{s.z_lo, s.z_hi});
      f.write_attribute(g, "radii", std::vector<double>{s.radius_lo, s.radius_hi});
    } else {
      f.write_attribute(g, "center", centre);
      f.write_attribute(g, "radius", s.radius);
      f.write_attribute(g, "inside", static_cast<std::int64_t>(s.inside ? 1 : 0));
      if (finite) f.write_attribute(g, "bounds", std::vector<double>{s.z_lo, s.z_hi});
    }
    if (s.type != WallType::plane) f.write_attribute(g, "angular_velocity", s.angular_velocity);
  }
  walls_written_ = sim_.wall_count();
}

namespace {
// A digest of a state's particles (and of what the snapshot adds).
std::int64_t state_digest(const SimulationBase::FlatState& s, bool forces, bool contacts) {
  Fnv1a h;
  auto add_all = [&h](const auto& v) { h.add(v.data(), v.size() * sizeof(v[0])); };
  add_all(s.id), add_all(s.position), add_all(s.velocity), add_all(s.spin);
  add_all(s.radius), add_all(s.material), add_all(s.fixed);
  const unsigned char flags[2] = {forces, contacts};
  h.add(flags, 2);
  return static_cast<std::int64_t>(h.value() & 0x7fffffffffffffffull);
}
}  // namespace

void RunOutput::write_snapshot() {
  write_snapshot(settings_.forces, settings_.contacts);
}

void RunOutput::write_snapshot(bool forces, bool contacts) {
  if (!file_) return;
  if (contacts && !sim_.record_contacts())
    throw InputError(
        "snapshot: contacts = true writes the contact network, which needs "
        "simulation { record_contacts = true }");
  write_header();
  write_new_walls();
  SimulationBase::FlatState s = sim_.flat_state();
  // A snapshot at the step of the last one, of the same particles in the same
  // state (the run's first beside a scene's sim:snapshot() before it), would be
  // its copy: two grids at one time in the XDMF index, of which viewers show one.
  const std::int64_t digest = state_digest(s, forces, contacts);
  if (sim_.step_count() == last_snapshot_step_ && digest == last_snapshot_digest_) return;
  std::vector<std::string> names;
  for (const auto& m : sim_.materials()) names.push_back(m.name);
  SnapshotView v = view(s, names);
  std::vector<double> force, torque;
  if (forces) {
    sim_.flat_forces(force, torque);
    v.force = force.data();
    v.torque = torque.data();
  }
  // The contact network of the last step, as the engine recorded it.
  std::vector<std::int64_t> ci, cj;
  std::vector<std::int32_t> cw;
  std::vector<double> overlap, fn, ft, normal;
  if (contacts) {
    const int d = sim_.dimension();
    for (const ContactRecord& c : sim_.contacts()) {
      ci.push_back(c.id_a);
      cj.push_back(c.wall >= 0 ? -1 : c.id_b);
      cw.push_back(c.wall);
      overlap.push_back(c.overlap);
      fn.push_back(c.normal_force);
      for (int k = 0; k < d; ++k) {
        ft.push_back(c.tangential_force[k]);
        normal.push_back(c.normal[k]);
      }
    }
    v.with_contacts = true;
    v.contacts = ci.size();
    v.contact_i = ci.data();
    v.contact_j = cj.data();
    v.contact_wall = cw.data();
    v.contact_overlap = overlap.data();
    v.contact_normal_force = fn.data();
    v.contact_tangential_force = ft.data();
    v.contact_normal = normal.data();
  }
  // The parallel bonds, once a scene has made any (intact and broken: the damage).
  std::vector<std::int64_t> bond_a, bond_b;
  std::vector<std::uint8_t> bond_broken;
  for (const SimulationBase::BondRecord& r : sim_.bond_records()) {
    bond_a.push_back(r.id_a);
    bond_b.push_back(r.id_b);
    bond_broken.push_back(r.broken ? 1 : 0);
  }
  if (!bond_a.empty()) {
    v.bonds = bond_a.size();
    v.bond_a = bond_a.data();
    v.bond_b = bond_b.data();
    v.bond_broken = bond_broken.data();
  }
  const std::string group = file_->write_snapshot(v);
  write_wall_states(group);
  index_snapshot(group, s);
  last_snapshot_step_ = sim_.step_count();
  last_snapshot_digest_ = digest;
  last_snapshot_state_ = state_digest(s, false, false);
}

// Where each wall is and how it moves at the snapshot's step: /walls/<name>
// holds it as first written, and a moving or scheduled wall is elsewhere now.
void RunOutput::write_wall_states(const std::string& snapshot) {
  H5Output& f = *file_;
  const int d = sim_.dimension();
  auto vec = [d](const Triple& t) { return std::vector<double>(t.begin(), t.begin() + d); };
  for (int w = 0; w < sim_.wall_count(); ++w) {
    const WallSpec s = sim_.wall(w);
    const std::string g = snapshot + "/walls/" + s.name;
    f.write_attribute(g, "index", static_cast<std::int64_t>(w));
    const char* where = s.type == WallType::plane                                  ? "point"
                        : s.type == WallType::mesh || s.type == WallType::polyline ? "axis_point"
                                                                                   : "center";
    f.write_attribute(g, where, vec(s.type == WallType::plane ? s.point : s.center));
    f.write_attribute(g, std::string(where) + "_units", std::string("m"));
    f.write_attribute(g, "velocity", vec(s.velocity));
    f.write_attribute(g, "velocity_units", std::string("m/s"));
    f.write_attribute(g, "angular_velocity", s.angular_velocity);
    f.write_attribute(g, "angular_velocity_units", std::string("rad/s"));
    if (is_surface_wall(s.type)) {  // turned about its axis since added, unwrapped
      f.write_attribute(g, "angle", s.angle);
      f.write_attribute(g, "angle_units", std::string("rad"));
    }
  }
}

void RunOutput::index_snapshot(const std::string& group, const SimulationBase::FlatState& s) {
  if (!xdmf_) return;
  const int d = sim_.dimension();
  std::vector<WallSpec> walls;
  for (int w = 0; w < sim_.wall_count(); ++w) walls.push_back(sim_.wall(w));
  if (!wall_extent_set_) {
    // The region walls are drawn over: the particles and the cylinders, with a
    // margin; fixed once so that walls that do not move keep one shape.
    bool any = false;
    auto include = [&](const Triple& c, double r) {
      for (int k = 0; k < d; ++k) {
        double lo = c[k] - r, hi = c[k] + r;
        wall_extent_[2 * k] = any ? std::min(wall_extent_[2 * k], lo) : lo;
        wall_extent_[2 * k + 1] = any ? std::max(wall_extent_[2 * k + 1], hi) : hi;
      }
      any = true;
    };
    for (std::size_t i = 0; i < s.id.size(); ++i) {
      Triple c{0, 0, 0};
      for (int k = 0; k < d; ++k) c[k] = s.position[i * d + k];
      include(c, s.radius[i]);
    }
    for (const auto& w : walls)
      if (w.type == WallType::cylinder) include(w.center, w.radius);
    if (!any) include({0, 0, 0}, 1e-3);
    double span = 0;
    for (int k = 0; k < d; ++k)
      span = std::max(span, wall_extent_[2 * k + 1] - wall_extent_[2 * k]);
    for (int k = 0; k < d; ++k) {
      wall_extent_[2 * k] -= 0.1 * span;
      wall_extent_[2 * k + 1] += 0.1 * span;
    }
    wall_extent_set_ = true;
  }
  XdmfSnapshot x;
  x.group = group;
  x.time = sim_.time();
  x.step = sim_.step_count();
  x.count = s.id.size();
  x.dimension = d;
  x.walls = wall_shapes(walls, d, wall_extent_);
  add_mesh_shapes(x.walls, sim_.mesh_views());
  xdmf_->add(std::move(x));
}

void RunOutput::write_series_row(bool first_row) {
  if (!file_) return;
  write_header();
  // One row a step: a run of no steps wrote the start's row at its end.
  if (sim_.step_count() == last_series_step_) return;
  GlobalStats g = sim_.stats();
  const std::vector<double> row{g.time,
                                static_cast<double>(g.step),
                                g.kinetic_translational,
                                g.kinetic_rotational,
                                static_cast<double>(g.contacts_particle),
                                static_cast<double>(g.contacts_wall),
                                g.max_overlap_ratio,
                                g.momentum[0],
                                g.momentum[1],
                                g.momentum[2],
                                g.angular_momentum_z};
  // The row before the first step comes before the step's checks: a scene given
  // a speed of 1e300 m/s (a kinetic energy of inf) gets their error, which names
  // the particle, rather than the file's refusal of the row.
  if ((g.step == 0 || first_row) &&
      !std::all_of(row.begin(), row.end(), [](double v) { return std::isfinite(v); }))
    return;
  file_->series_append("/series", row);
  last_series_step_ = g.step;
}

void RunOutput::end_of_run() {
  if (!file_ || finished_) return;
  if (sim_.step_count() != last_series_step_) write_series_row();
  note_effects();
}

void RunOutput::declare_series(const std::string& name, const std::vector<std::string>& columns) {
  declare_series(name, columns, {});
}

void RunOutput::declare_series(const std::string& name, const std::vector<std::string>& columns,
                               const std::vector<std::string>& units) {
  // A scene's own series are plain words; diagnostics write under "diagnostics/<label>".
  static const char* reserved[] = {"series",   "snapshots", "scene",  "materials",
                                   "contacts", "walls",     "results"};
  const std::string first = name.substr(0, name.find('/'));
  bool ok =
      !name.empty() && name[0] != '/' && name.back() != '/' && name.find("//") == std::string::npos;
  for (const char* r : reserved) ok = ok && first != r;
  if (first != "diagnostics") ok = ok && name.find('/') == std::string::npos;
  ok = ok && name != "diagnostics";  // the diagnostics' group, not a series
  if (!ok)
    throw InputError(fmt::format(
        "series name '{}' must be a plain word (or 'diagnostics/<label>') other than series, "
        "snapshots, scene, materials, contacts, walls, results and diagnostics",
        name));
  if (!units.empty() && units.size() != columns.size())
    throw InputError(fmt::format("series '{}': {} units given for {} columns", name, units.size(),
                                 columns.size()));
  if (file_) file_->series_declare("/" + name, columns, units);
}

void RunOutput::write_attribute(const std::string& group, const std::string& name, double value) {
  if (file_) file_->write_attribute("/" + group, name, value);
}
void RunOutput::write_attribute(const std::string& group, const std::string& name,
                                const std::string& value) {
  if (!file_) return;
  file_->write_attribute("/" + group, name, value);
  // A diagnostic's "units" (one per column, comma-separated) go on each column as well.
  if (name == "units") file_->set_series_units("/" + group, split_units(value));
}
void RunOutput::write_attribute(const std::string& group, const std::string& name,
                                const std::vector<double>& value) {
  if (file_) file_->write_attribute("/" + group, name, value);
}

void RunOutput::append_series(const std::string& name, const std::vector<double>& row) {
  if (file_) file_->series_append("/" + name, row);
}

void RunOutput::write_result(const std::string& name, double value) {
  if (!file_) return;
  file_->write_attribute("/results", name, value);
  file_->flush();
}

void RunOutput::write_failure(const std::string& message) {
  if (!file_) return;
  try {
    write_failed_state(message);
  } catch (...) {
    // The state could not be written (the disk full, say): the reason may still fit.
    file_->record_failure(message);
    throw;
  }
}

void RunOutput::write_failed_state(const std::string& message) {
  write_header();
  if (sim_.holds_share()) {
    // A spread run failing in a step: this rank holds its share of the scene and its
    // neighbours' ghosts, which a snapshot would pass off as the scene. The reason only.
    file_->write_attribute("/", "failure", message);
    last_snapshot_step_ = sim_.step_count();
    failure_step_ = sim_.step_count();
    file_->flush();
    return;
  }
  // Keep what can be kept: the particles whose state is still finite, and the reason.
  SimulationBase::FlatState s = sim_.flat_state();
  const int d = sim_.dimension(), sc = d == 2 ? 1 : 3;
  SimulationBase::FlatState kept;
  for (std::size_t i = 0; i < s.id.size(); ++i) {
    bool finite = true;
    for (int k = 0; k < d; ++k)
      finite =
          finite && std::isfinite(s.position[i * d + k]) && std::isfinite(s.velocity[i * d + k]);
    for (int k = 0; k < sc; ++k) finite = finite && std::isfinite(s.spin[i * sc + k]);
    if (!finite) continue;
    kept.id.push_back(s.id[i]);
    kept.radius.push_back(s.radius[i]);
    kept.material.push_back(s.material[i]);
    kept.fixed.push_back(s.fixed[i]);
    for (int k = 0; k < d; ++k) {
      kept.position.push_back(s.position[i * d + k]);
      kept.velocity.push_back(s.velocity[i * d + k]);
    }
    for (int k = 0; k < sc; ++k) kept.spin.push_back(s.spin[i * sc + k]);
  }
  std::vector<std::string> names;
  for (const auto& m : sim_.materials()) names.push_back(m.name);
  std::string group = file_->write_snapshot(view(kept, names));
  file_->write_attribute(group, "failure", message);
  index_snapshot(group, kept);
  file_->write_attribute("/", "failure", message);
  // The file stays open: a scene that catches the error (pcall, the REPL) goes
  // on recording into it; the end writes no second snapshot of this step.
  last_snapshot_step_ = sim_.step_count();
  failure_step_ = sim_.step_count();
  file_->flush();
  if (xdmf_) xdmf_->flush();  // the failed state in the index at once
}

}  // namespace granule::io
