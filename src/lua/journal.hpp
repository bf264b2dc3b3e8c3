// The journal: what a scene saw of the engine, so that a restarted scene can
// live through its past again without computing it.
//
// A scene is a Lua program whose only inputs, besides its source and its -D
// parameters, are the values the engine hands it: the results of sim:stats(),
// sim:particle(id), sim:run{...}, the clock. While a scene runs, every call
// into the engine is journaled with its results (or its error), and every
// Lua callback the engine makes during a run (sim:every hooks, stop_when) is
// journaled where it fired. A checkpoint stores the journal beside the state.
//
// `granule run --restart` runs the script from the top again with the journal
// in replay: each call must be the call the journal holds next (else the
// scene took another path, and the restart is refused); calls that build the
// scene (materials, walls, hooks, output) execute for real, so that the
// engine's structure is rebuilt; calls that read or change the state return
// their journaled results without executing (the state will come from the
// checkpoint); a finished sim:run fires its journaled callbacks in order and
// returns its journaled result. So the script's locals, the values its
// callbacks accumulated and the lines it printed are exactly those of the run
// that wrote the checkpoint. When the journal is used up, the checkpoint is
// applied (state, diagnostics, output) and the scene continues for real,
// journaling again.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <unordered_map>
#include <vector>

struct lua_State;

namespace granule::lua {

class Journal {
 public:
  // How a journaled call behaves in replay.
  enum class Kind {
    build,       // executes for real; its results are the real ones
    observe,     // does not execute; returns the journaled results
    run,         // a run: replays its callbacks, then returns the journaled result
    checkpoint,  // sim:save_checkpoint: journaled before it executes
  };

  bool replaying() const { return replaying_; }
  const std::vector<std::uint8_t>& bytes() const { return bytes_; }
  std::size_t entries() const { return entries_; }
  // Whether the call being replayed took its results from the journal (false once the
  // journal was used up before they came): its results must then be journaled.
  bool took_results() const { return took_results_; }
  void forget_took_results() { took_results_ = false; }
  // True once each time the journal grows past the next size worth a warning
  // (256 MiB, then each doubling; GRANULE_JOURNAL_WARN_BYTES sets the first):
  // it is kept in memory, and a script that reads the engine often grows it for
  // as long as it runs.
  bool passed_size_mark() {
    if (bytes_.size() < size_mark_) return false;
    while (size_mark_ <= bytes_.size()) size_mark_ *= 2;
    return true;
  }

  // The journal's format: 2 keeps each call's argument digest (1, without, is replayed
  // by the name of each call alone).
  static constexpr int format = 2;
  // Tables nested deeper than this are neither kept nor digested.
  static constexpr int max_depth = 64;
  // The format of these bytes: a journal continued from a format-1 checkpoint goes on
  // in format 1, since its checkpoints hold the old entries and the new together.
  int format_in_use() const { return format_in_use_; }

  // Starts replaying `recorded`, a journal of format `recorded_format`; `apply` is
  // called once, at the moment the journal is used up (then recording resumes,
  // appending to the same journal, in this format).
  void start_replay(std::vector<std::uint8_t> recorded, int recorded_format,
                    std::function<void()> apply);

  // A digest of the values at first..first+count-1 (tables by their contents, keys in
  // pairs() order; functions and userdata by their type alone): what a call was given.
  static std::uint64_t digest(lua_State* L, int first, int count);

  // ---- recording ----
  void record_call(const char* name, std::uint64_t arguments);
  void record_results(lua_State* L, int first, int count);  // the values at first..first+count-1
  void record_no_results();                                 // a build call: results not kept
  void record_error(lua_State* L, int index);
  void record_callback(std::int64_t hook_id);  // a hook fired (-1: the run's stop_when)

  // ---- replaying ----
  // The next entry must be a call of `name`, given the same arguments where
  // `check_arguments`; throws std::runtime_error naming both if not.
  void expect_call(const char* name, std::uint64_t arguments, bool check_arguments);
  enum class Next { results, error, callback, end };
  // What comes next inside a call being replayed (end: the journal is used up).
  // After a callback was replayed (`after_callback`), a call there means the
  // callback made fewer calls than in the run that wrote the journal: the scene
  // took another path, said so; anywhere else the journal is damaged.
  Next peek(bool after_callback = false);
  // Pushes the journaled results; returns their count.
  int push_results(lua_State* L);
  // A build call's entry, read; the journal's end (the checkpoint's state loaded,
  // when this was its last entry) waits for end_of_build_call(), after the call
  // has run again on the scene being rebuilt.
  void skip_results();
  void end_of_build_call() { check_end(); }
  void push_error(lua_State* L);  // the journaled error value
  std::int64_t take_callback();   // a hook's id (-1: stop_when)

 private:
  void put_byte(std::uint8_t b) { bytes_.push_back(b); }
  void put_u64(std::uint64_t v);  // LEB128: small numbers in one byte
  void put_string(const char* s, std::size_t n);
  // A short string once in full, then as its number (names and keys repeat endlessly).
  void put_interned(const char* s, std::size_t n);
  void put_value(lua_State* L, int index, int depth);
  std::uint8_t get_byte();
  std::uint64_t get_u64();
  std::string get_string();
  std::string get_interned(std::uint8_t tag);
  void push_value(lua_State* L, int depth);
  void forget_after(std::size_t bytes, std::size_t strings);  // undoes a half-kept entry
  void check_end();  // calls apply_ when the journal is used up
  [[noreturn]] void damaged(const char* what) const;

  std::vector<std::uint8_t> bytes_;
  std::size_t size_mark_ = first_size_mark();
  static std::size_t first_size_mark();
  std::size_t cursor_ = 0;
  std::size_t entries_ = 0;
  std::size_t calls_replayed_ = 0;
  bool replaying_ = false;
  int format_in_use_ = format;  // of bytes_: the recorded journal's, once replaying
  bool took_results_ = false;
  std::function<void()> apply_;
  std::unordered_map<std::string, std::uint64_t> interned_;  // recording: string -> number
  std::vector<std::string> strings_;                         // replaying: number -> string
};

// Wraps the function on the stack top (a method named `name`) so that its calls are
// journaled as `kind`; leaves the wrapper in its place.
void push_journaled(lua_State* L, const char* name, Journal::Kind kind);
// How the method `name` of a simulation is journaled (build, observe, run, checkpoint).
Journal::Kind journal_kind(const std::string& method);
// Journals the scene's clocks (os.time, os.clock, os.date, wall_time) and os.tmpname, and seeds
// math.random with a fixed seed, so that a scene's run depends on nothing unjournaled.
void journal_clocks(lua_State* L);

}  // namespace granule::lua
