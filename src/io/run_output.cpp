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

void RunOutput::finish() {
  if (finished_ || !file_) return;
  finished_ = true;
  write_header();
  write_new_walls();
  sim_.flush_diagnostics();  // partly filled windows, while the file is open
  if (sim_.step_count() != last_snapshot_step_ && sim_.particle_count() > 0) write_snapshot();
  file_->flush();
}

void RunOutput::flush() {
  if (finished_ || !file_) return;
  write_header();
  write_new_walls();
  file_->flush();
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
  index_snapshot(file_->write_snapshot(v), s);
  last_snapshot_step_ = sim_.step_count();
  last_snapshot_digest_ = digest;
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

void RunOutput::write_series_row() {
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
  if (g.step == 0 &&
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
  if (!ok)
    throw InputError(fmt::format(
        "series name '{}' must be a plain word (or 'diagnostics/<label>') other than series, "
        "snapshots, scene, materials, contacts, walls and results",
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
  write_header();
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
  last_snapshot_step_ = sim_.step_count();
  finished_ = true;  // do not append a normal final snapshot after a failure
  file_->flush();
}

}  // namespace granule::io

namespace granule::io {

namespace {
std::string join_lines(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  return out;
}
std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    out.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return out;
}
std::vector<std::string> split_tabs(const std::string& line) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    std::size_t end = line.find('\t', start);
    out.push_back(line.substr(start, end == std::string::npos ? std::string::npos : end - start));
    if (end == std::string::npos) return out;
    start = end + 1;
  }
}
[[noreturn]] void damaged_mark(const std::string& what) {
  throw InputError(fmt::format("checkpoint: the output mark is damaged ({})", what));
}
std::int64_t to_count(const std::string& text, const std::string& what) {
  std::size_t used = 0;
  long long v = -1;
  try {
    v = std::stoll(text, &used);
  } catch (...) {
    damaged_mark(what);
  }
  if (used != text.size() || v < 0) damaged_mark(what);
  return v;
}
}  // namespace

void RunOutput::save_mark(StateBlob& state) {
  if (!file_) return;
  file_->flush();
  // Absolute: a restart may run in another folder.
  std::error_code ec;
  const auto absolute = std::filesystem::absolute(settings_.path, ec);
  state.texts["output.path"] = ec ? settings_.path : absolute.string();
  std::vector<std::string> series;
  for (const auto& [group, rows] : file_->series_rows())
    series.push_back(fmt::format("{}\t{}", group, rows));
  state.texts["output.series"] = join_lines(series);
  state.texts["output.results"] = join_lines(file_->attribute_names("/results"));
  state.integers["output.progress"] = {static_cast<std::int64_t>(file_->snapshot_count()),
                                       header_written_ ? 1 : 0,
                                       walls_written_,
                                       last_snapshot_step_,
                                       wall_extent_set_ ? 1 : 0,
                                       last_snapshot_digest_,
                                       last_series_step_};
  state.doubles["output.wall_extent"] = {wall_extent_.begin(), wall_extent_.end()};
  // The materials and laws written: their count, then the laws' groups.
  std::vector<std::string> laws{std::to_string(materials_written_)};
  laws.insert(laws.end(), laws_written_.begin(), laws_written_.end());
  state.texts["output.laws"] = join_lines(laws);
  state.texts["output.effects"] = effects_text();
  // The XDMF index: each snapshot's line, then its walls' lines; numbers in flat arrays.
  std::vector<std::string> lines;
  std::vector<double> times, points;
  std::vector<std::int64_t> connectivity;
  if (xdmf_)
    for (const auto& x : xdmf_->snapshots()) {
      lines.push_back(
          fmt::format("{}\t{}\t{}\t{}\t{}", x.group, x.step, x.count, x.dimension, x.walls.size()));
      times.push_back(x.time);
      for (const auto& w : x.walls) {
        lines.push_back(fmt::format("{}\t{}\t{}\t{}\t{}", w.name, w.topology, w.nodes_per_element,
                                    w.points.size(), w.connectivity.size()));
        points.insert(points.end(), w.points.begin(), w.points.end());
        connectivity.insert(connectivity.end(), w.connectivity.begin(), w.connectivity.end());
      }
    }
  state.texts["output.xdmf"] = join_lines(lines);
  state.doubles["output.xdmf.time"] = times;
  state.doubles["output.xdmf.points"] = points;
  state.integers["output.xdmf.connectivity"] = connectivity;
}

void RunOutput::resume(const StateBlob& state) {
  if (!settings_.muted) throw std::logic_error("RunOutput::resume: the output is not muted");
  const std::string original = state.t("output.path");
  std::map<std::string, std::int64_t> series;
  for (const auto& line : lines_of(state.t("output.series"))) {
    auto f = split_tabs(line);
    if (f.size() != 2) damaged_mark("output.series");
    series[f[0]] = to_count(f[1], "output.series");
  }
  const auto results = lines_of(state.t("output.results"));
  const auto& progress = state.i("output.progress");
  const auto& extent = state.d("output.wall_extent");
  // (Five or six entries in checkpoints written before the last snapshot's digest
  // and the last series row's step were kept.)
  if (progress.size() < 5 || progress.size() > 7) damaged_mark("output.progress");
  if (extent.size() != 6) damaged_mark("output.wall_extent");
  // The XDMF index as it stood.
  std::vector<XdmfSnapshot> index;
  {
    const auto lines = lines_of(state.t("output.xdmf"));
    const auto& times = state.d("output.xdmf.time");
    const auto& points = state.d("output.xdmf.points");
    const auto& conn = state.i("output.xdmf.connectivity");
    std::size_t line = 0, p = 0, c = 0;
    while (line < lines.size()) {
      auto f = split_tabs(lines[line++]);
      if (f.size() != 5 || index.size() >= times.size()) damaged_mark("output.xdmf");
      XdmfSnapshot x;
      x.group = f[0];
      x.step = to_count(f[1], "output.xdmf");
      x.count = static_cast<std::size_t>(to_count(f[2], "output.xdmf"));
      x.dimension = static_cast<int>(to_count(f[3], "output.xdmf"));
      x.time = times[index.size()];
      const std::int64_t walls = to_count(f[4], "output.xdmf");
      for (std::int64_t w = 0; w < walls; ++w) {
        if (line >= lines.size()) damaged_mark("output.xdmf");
        auto g = split_tabs(lines[line++]);
        if (g.size() != 5) damaged_mark("output.xdmf");
        XdmfShape shape;
        shape.name = g[0];
        shape.topology = g[1];
        shape.nodes_per_element = static_cast<int>(to_count(g[2], "output.xdmf"));
        const auto np = static_cast<std::size_t>(to_count(g[3], "output.xdmf"));
        const auto nc = static_cast<std::size_t>(to_count(g[4], "output.xdmf"));
        if (points.size() - p < np || conn.size() - c < nc) damaged_mark("output.xdmf");
        shape.points.assign(points.begin() + static_cast<std::ptrdiff_t>(p),
                            points.begin() + static_cast<std::ptrdiff_t>(p + np));
        for (std::size_t k = 0; k < nc; ++k)
          shape.connectivity.push_back(static_cast<int>(conn[c + k]));
        p += np;
        c += nc;
        x.walls.push_back(std::move(shape));
      }
      index.push_back(std::move(x));
    }
  }
  // The first run's file, copied where this run writes (unless they are one file).
  std::error_code ec;
  if (!std::filesystem::exists(original, ec))
    throw InputError(fmt::format(
        "restart: the output {} of the run that wrote the checkpoint is missing; a restart "
        "continues that file",
        original));
  // (Under mpirun a rank other than 0 copies it into its scratch folder: io/rank_files.hpp.)
  const std::string here = writable_path(settings_.path);
  if (!std::filesystem::equivalent(original, here, ec)) {
    std::filesystem::copy_file(original, here, std::filesystem::copy_options::overwrite_existing,
                               ec);
    if (ec)
      throw std::runtime_error(
          fmt::format("restart: cannot copy {} to {}: {}", original, settings_.path, ec.message()));
  }
  file_ = H5Output::reopen(settings_.path, static_cast<std::size_t>(progress[0]), series,
                           "/results", results);
  if (settings_.xdmf) {
    xdmf_ = std::make_unique<XdmfIndex>(settings_.path);
    xdmf_->restore(std::move(index));
  }
  header_written_ = progress[1] != 0;
  walls_written_ = static_cast<int>(progress[2]);
  last_snapshot_step_ = progress[3];
  wall_extent_set_ = progress[4] != 0;
  last_snapshot_digest_ = progress.size() > 5 ? progress[5] : 0;
  last_series_step_ = progress.size() > 6 ? progress[6] : -1;
  // (Checkpoints written before the effects were noted: they are noted from here on.)
  if (state.has("output.effects")) restore_effects(state.t("output.effects"));
  // A checkpoint written before the laws' record: what the scene holds now counts
  // as written (as it was then).
  laws_written_.clear();
  if (state.has("output.laws")) {
    const std::vector<std::string> lines = lines_of(state.t("output.laws"));
    if (lines.empty()) damaged_mark("output.laws");
    std::size_t used = 0;
    unsigned long long count = 0;
    try {
      count = std::stoull(lines[0], &used);
    } catch (const std::exception&) {
      damaged_mark("output.laws");
    }
    if (used != lines[0].size() || count > sim_.materials().size()) damaged_mark("output.laws");
    materials_written_ = static_cast<std::size_t>(count);
    laws_written_.insert(lines.begin() + 1, lines.end());
  } else {
    materials_written_ = sim_.materials().size();
    const auto& mats = sim_.materials();
    const PairTable& table = sim_.pair_table();
    for (int a = 0; a < table.material_count(); ++a)
      for (int b = a; b < table.material_count(); ++b)
        if (table.at(a, b).model >= 0)
          laws_written_.insert(fmt::format("/contacts/{}-{}", mats[a].name, mats[b].name));
  }
  std::copy(extent.begin(), extent.end(), wall_extent_.begin());
  settings_.muted = false;
}

}  // namespace granule::io
