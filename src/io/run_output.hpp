// Attaches HDF5 output to a running simulation: the scene's provenance
// (source text, parameters, what is simulated), a time series of global
// quantities, particle snapshots at set intervals, scene-declared series, and
// the state at a failure. Snapshots reach the disk as they are written, series
// rows at least once a second of a run (flush_if_due, between its chunks), so
// a crash or a kill loses at most the last second's rows.
#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "core/state.hpp"
#include "engine/simulation_base.hpp"
#include "hooks/diagnostic.hpp"
#include "io/h5_output.hpp"
#include "io/xdmf.hpp"

namespace granule::io {

struct RunOutputSettings {
  std::string path;
  double snapshot_every = 0;  // s of simulated time; 0 = first and last only
  double series_every = 0;    // s; 0 = every 100 steps
  bool xdmf = true;           // keep <file>.xmf beside the HDF5 file for ParaView
  std::string scene_path;
  std::string scene_source;
  std::vector<std::pair<std::string, std::string>> parameters;  // name -> value as text
  std::map<std::string, double> numeric_parameters;
  std::map<std::string, std::int64_t> integer_parameters;  // written as integers
  std::map<std::string, std::string> parameter_units;  // name -> unit as parameters{} declared it
  // Made but writing nothing until resume(): a restarted scene replaying its past.
  bool muted = false;
  // Every snapshot with the last step's force and torque per particle, and the contact
  // network (pairs, forces, normals; needs the simulation's record_contacts).
  bool forces = false;
  bool contacts = false;
};

class RunOutput final : public OutputSink {
 public:
  RunOutput(SimulationBase& sim, RunOutputSettings settings);
  ~RunOutput();  // writes the final snapshot if the run advanced since the last one; never throws
  RunOutput(const RunOutput&) = delete;
  RunOutput& operator=(const RunOutput&) = delete;

  void write_snapshot();  // with the settings' forces and contacts
  void write_snapshot(bool forces, bool contacts);
  // first_row: the file's first (as at step 0), left out where not finite.
  void write_series_row(bool first_row = false);
  // The end of a run (sim:run returned, not interrupted): a /series row of the
  // final state, unless the cadence has just written one.
  void end_of_run();
  // An output opened after the scene had stepped: the first /series row and
  // snapshot, of the state the run about to start begins from (once; sim:run
  // calls it, and finish() where no run followed).
  void record_opening();
  // What the runs written so far simulated, into /scene/effects (run_output_header.cpp).
  void note_effects();
  void write_result(const std::string& name, double value);  // /results attributes
  void write_failure(const std::string& message);            // finite particles + message
  // The scene ended on an error of its own (a callback's, its Lua's): the reason as
  // the file's `failure`, unless a step's failure at this step is already the cause.
  void note_scene_error(const std::string& message) noexcept;
  void finish();        // final snapshot + flush
  void flush();         // everything written so far on disk; the file stays open for more
  void flush_if_due();  // flush(), if a second of wall time has passed since the last
  const std::string& path() const { return settings_.path; }
  const RunOutputSettings& settings() const { return settings_; }

  // Checkpoints: how far the file has got (flushed first), under "output.*" keys; and,
  // for a muted output, the file of the run that wrote the checkpoint copied to this
  // output's path and cut back to that mark, then written on as if never stopped.
  // `copies_made`: under mpirun, whether every rank made its copy (all ranks call
  // resume, and pass it): the ranks that write scratch copies copy the first run's
  // file (and put their copies back) before rank 0 puts the file itself back and
  // cuts it.
  void save_mark(StateBlob& state);
  void resume(const StateBlob& state, const std::function<bool(bool)>& copies_made = {});

  // OutputSink: where the scene's diagnostics write.
  void declare_series(const std::string& group, const std::vector<std::string>& columns) override;
  // A scene's series with the unit of each column (empty: from io/output_units.hpp).
  void declare_series(const std::string& group, const std::vector<std::string>& columns,
                      const std::vector<std::string>& units);
  void append_series(const std::string& group, const std::vector<double>& row) override;
  void write_attribute(const std::string& group, const std::string& name, double value) override;
  void write_attribute(const std::string& group, const std::string& name,
                       const std::string& value) override;
  void write_attribute(const std::string& group, const std::string& name,
                       const std::vector<double>& value) override;
  std::string xdmf_path() const { return xdmf_ ? xdmf_->path() : ""; }
  H5Output& file() { return *file_; }

 private:
  void write_failed_state(const std::string& message);  // write_failure's body
  void write_header();
  void write_new_walls();
  void write_new_laws();             // run_output_header.cpp
  std::string effects_text() const;  // for the checkpoint mark
  void restore_effects(const std::string& text);
  SnapshotView view(const SimulationBase::FlatState& s, std::vector<std::string> names) const;
  void write_wall_states(const std::string& snapshot);
  void index_snapshot(const std::string& group, const SimulationBase::FlatState& s);
  SimulationBase& sim_;
  RunOutputSettings settings_;
  std::unique_ptr<H5Output> file_;
  std::unique_ptr<XdmfIndex> xdmf_;
  std::array<double, 6> wall_extent_{};  // where walls are drawn in the XDMF, fixed at the first
  bool wall_extent_set_ = false;
  std::vector<int> hook_ids_;
  std::int64_t last_snapshot_step_ = -1;
  std::int64_t last_series_step_ = -1;      // the step of /series' last row
  std::int64_t last_snapshot_digest_ = -1;  // of the last snapshot's particles (state_digest)
  std::int64_t last_snapshot_state_ = -1;   // the same without its flags: the state alone
  bool finished_ = false;
  std::chrono::steady_clock::time_point last_flush_ = std::chrono::steady_clock::now();
  // The step a run into this file failed at (-1: none): the diagnostics'
  // windows open then, holding that step's samples, are not written at the end
  // unless the scene went on (a REPL session, a pcall) and stepped since.
  std::int64_t failure_step_ = -1;
  // Opened after the scene had stepped: its first series row and snapshot, of the
  // state the next run starts from, are still to be written (record_opening).
  bool opening_due_ = false;
  bool header_written_ = false;
  int walls_written_ = 0;               // walls 0 .. walls_written_ - 1 are in /walls
  std::size_t materials_written_ = 0;   // materials 0 .. materials_written_ - 1 are in /materials
  std::set<std::string> laws_written_;  // the /contacts groups written
  ActiveEffects effects_seen_;          // note_effects()
};

}  // namespace granule::io
