#include "lua/journal.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <cstring>
#include <iostream>
#include <iterator>
#include <lua.hpp>
#include <stdexcept>

#include "lua/lua_util.hpp"
#include "lua/scene.hpp"

namespace granule::lua {

namespace {

// Entry tags. A call is 'C' name, then (after any callbacks it made) 'R' values,
// 'B' (a build call, results not kept) or 'X' error; a callback is 'H' hook id + 1.
constexpr std::uint8_t tag_call = 'C', tag_results = 'R', tag_build = 'B', tag_error = 'X',
                       tag_callback = 'H';
// Value tags.
constexpr std::uint8_t v_nil = 'n', v_true = 't', v_false = 'f', v_integer = 'i', v_float = 'd',
                       v_string = 's', v_new_string = 'S', v_string_ref = 'r', v_table = '{',
                       v_table_end = '}';
constexpr std::size_t interned_length = 64;  // longer strings are kept in full each time

}  // namespace

void Journal::start_replay(std::vector<std::uint8_t> recorded, int recorded_format,
                           std::function<void()> apply) {
  if (recorded_format < 1 || recorded_format > format)
    throw std::runtime_error(fmt::format(
        "restart: the checkpoint's journal has format {}, which this granule does not know "
        "(it reads 1 to {}); continue it with the granule that wrote it",
        recorded_format, format));
  bytes_ = std::move(recorded);
  // The first run warned of the sizes it passed: the next warning is the next mark.
  while (size_mark_ <= bytes_.size()) size_mark_ *= 2;
  format_in_use_ = recorded_format;
  calls_replayed_ = 0;
  cursor_ = 0;
  apply_ = std::move(apply);
  replaying_ = true;
  check_end();
}

void Journal::put_u64(std::uint64_t v) {
  while (v >= 0x80) {
    bytes_.push_back(static_cast<std::uint8_t>(v | 0x80));
    v >>= 7;
  }
  bytes_.push_back(static_cast<std::uint8_t>(v));
}

void Journal::put_interned(const char* s, std::size_t n) {
  if (n > interned_length) {
    put_byte(v_string);
    put_string(s, n);
    return;
  }
  std::string key(s, n);
  auto it = interned_.find(key);
  if (it != interned_.end()) {
    put_byte(v_string_ref);
    put_u64(it->second);
    return;
  }
  const std::uint64_t number = interned_.size();
  interned_.emplace(std::move(key), number);
  put_byte(v_new_string);
  put_string(s, n);
}

void Journal::put_string(const char* s, std::size_t n) {
  put_u64(n);
  bytes_.insert(bytes_.end(), s, s + n);
}

void Journal::put_value(lua_State* L, int index, int depth) {
  index = lua_absindex(L, index);
  switch (lua_type(L, index)) {
    case LUA_TNIL:
      put_byte(v_nil);
      return;
    case LUA_TBOOLEAN:
      put_byte(lua_toboolean(L, index) ? v_true : v_false);
      return;
    case LUA_TNUMBER:
      if (lua_isinteger(L, index)) {
        // Zig-zag, so that small negative numbers stay short too.
        const auto i = static_cast<std::uint64_t>(lua_tointeger(L, index));
        put_byte(v_integer);
        put_u64((i << 1) ^ (0 - (i >> 63)));
      } else {
        // The bits, so that a replayed value is the recorded one exactly.
        double d = lua_tonumber(L, index);
        std::uint8_t raw[8];
        std::memcpy(raw, &d, sizeof raw);
        put_byte(v_float);
        bytes_.insert(bytes_.end(), raw, raw + 8);
      }
      return;
    case LUA_TSTRING: {
      std::size_t n = 0;
      const char* s = lua_tolstring(L, index, &n);
      put_interned(s, n);
      return;
    }
    case LUA_TTABLE: {
      if (depth >= Journal::max_depth)
        throw std::runtime_error("journal: a result nests tables deeper than 64 levels");
      put_byte(v_table);
      lua_pushnil(L);
      while (lua_next(L, index) != 0) {
        put_value(L, -2, depth + 1);
        put_value(L, -1, depth + 1);
        lua_pop(L, 1);
      }
      put_byte(v_table_end);
      return;
    }
    default:
      throw std::runtime_error(fmt::format(
          "journal: cannot keep a {} value (a call that returns one must be a build call)",
          lua_typename(L, lua_type(L, index))));
  }
}

std::size_t Journal::first_size_mark() {
  const char* set = std::getenv("GRANULE_JOURNAL_WARN_BYTES");
  if (set) {
    char* end = nullptr;
    const unsigned long long bytes = std::strtoull(set, &end, 10);
    if (end != set && *end == 0 && bytes > 0) return static_cast<std::size_t>(bytes);
  }
  return std::size_t{256} << 20;
}

void Journal::record_call(const char* name, std::uint64_t arguments) {
  took_results_ = false;  // this call's results are new: they are journaled
  put_byte(tag_call);
  put_interned(name, std::strlen(name));
  if (format_in_use_ >= 2)
    for (int k = 0; k < 8; ++k) put_byte(static_cast<std::uint8_t>(arguments >> (8 * k)));
  ++entries_;
}

void Journal::forget_after(std::size_t bytes, std::size_t strings) {
  bytes_.resize(bytes);
  for (auto it = interned_.begin(); it != interned_.end();)
    it = it->second >= strings ? interned_.erase(it) : std::next(it);
}

void Journal::record_results(lua_State* L, int first, int count) {
  const std::size_t mark = bytes_.size(), strings = interned_.size();
  try {
    put_byte(tag_results);
    put_u64(static_cast<std::uint64_t>(count));
    for (int k = 0; k < count; ++k) put_value(L, first + k, 0);
  } catch (...) {
    forget_after(mark, strings);
    throw;
  }
}

void Journal::record_no_results() {
  put_byte(tag_build);
}

void Journal::record_error(lua_State* L, int index) {
  put_byte(tag_error);
  const int t = lua_type(L, index);
  if (t == LUA_TSTRING || t == LUA_TTABLE || t == LUA_TNUMBER || t == LUA_TBOOLEAN ||
      t == LUA_TNIL) {
    const std::size_t mark = bytes_.size(), strings = interned_.size();
    try {
      put_value(L, index, 0);
      return;
    } catch (...) {
      forget_after(mark, strings);
    }
  }
  // Its __tostring could raise, a longjmp out of this C++ frame: that value gets the
  // address form luaL_tolstring gives one without a metatable.
  const char* text = nullptr;  // pushed; popped below
  if (luaL_getmetafield(L, index, "__tostring") != LUA_TNIL) {
    lua_pop(L, 1);
    text = lua_pushfstring(L, "%s: %p", luaL_typename(L, index), lua_topointer(L, index));
  } else {
    text = luaL_tolstring(L, index, nullptr);
  }
  put_interned(text, std::strlen(text));
  lua_pop(L, 1);
}

void Journal::record_callback(std::int64_t hook_id) {
  put_byte(tag_callback);
  put_u64(static_cast<std::uint64_t>(hook_id + 1));
  ++entries_;
}

[[noreturn]] void Journal::damaged(const char* what) const {
  throw std::runtime_error(
      fmt::format("restart: the checkpoint's journal is damaged ({} at byte {} of {})", what,
                  cursor_, bytes_.size()));
}

std::uint8_t Journal::get_byte() {
  if (cursor_ >= bytes_.size()) damaged("it ends inside an entry");
  return bytes_[cursor_++];
}

std::uint64_t Journal::get_u64() {
  std::uint64_t v = 0;
  for (int shift = 0; shift < 64; shift += 7) {
    if (cursor_ >= bytes_.size()) damaged("it ends inside a number");
    const std::uint8_t b = bytes_[cursor_++];
    v |= std::uint64_t(b & 0x7f) << shift;
    if (!(b & 0x80)) return v;
  }
  damaged("a number is too long");
}

std::string Journal::get_interned(std::uint8_t tag) {
  if (tag == v_string) return get_string();
  if (tag == v_new_string) {
    strings_.push_back(get_string());
    return strings_.back();
  }
  if (tag == v_string_ref) {
    const std::uint64_t number = get_u64();
    if (number >= strings_.size()) damaged("a string refers past the strings seen");
    return strings_[number];
  }
  damaged("a string was expected");
}

std::string Journal::get_string() {
  const std::uint64_t n = get_u64();
  if (n > bytes_.size() - cursor_) damaged("a string runs past its end");
  std::string s(reinterpret_cast<const char*>(bytes_.data() + cursor_), n);
  cursor_ += n;
  return s;
}

void Journal::push_value(lua_State* L, int depth) {
  if (depth >= Journal::max_depth) damaged("tables nest too deep");
  luaL_checkstack(L, 4, "journal");
  switch (get_byte()) {
    case v_nil:
      lua_pushnil(L);
      return;
    case v_true:
      lua_pushboolean(L, 1);
      return;
    case v_false:
      lua_pushboolean(L, 0);
      return;
    case v_integer: {
      const std::uint64_t z = get_u64();
      lua_pushinteger(L, static_cast<lua_Integer>((z >> 1) ^ (0 - (z & 1))));
      return;
    }
    case v_float: {
      if (bytes_.size() - cursor_ < 8) damaged("it ends inside a number");
      double d = 0;
      std::memcpy(&d, bytes_.data() + cursor_, sizeof d);
      cursor_ += 8;
      lua_pushnumber(L, d);
      return;
    }
    case v_string:
    case v_new_string:
    case v_string_ref: {
      std::string s = get_interned(bytes_[cursor_ - 1]);
      lua_pushlstring(L, s.data(), s.size());
      return;
    }
    case v_table: {
      lua_newtable(L);
      while (true) {
        if (cursor_ >= bytes_.size()) damaged("a table has no end");
        if (bytes_[cursor_] == v_table_end) {
          ++cursor_;
          return;
        }
        push_value(L, depth + 1);
        push_value(L, depth + 1);
        if (lua_isnil(L, -2)) damaged("a table key is nil");
        lua_rawset(L, -3);
      }
    }
    default:
      damaged("an unknown value");
  }
}

void Journal::check_end() {
  if (replaying_ && cursor_ == bytes_.size()) {
    replaying_ = false;
    took_results_ = false;
    interned_.clear();  // recording goes on numbering the strings the journal holds
    for (std::size_t k = 0; k < strings_.size(); ++k) interned_.emplace(strings_[k], k);
    if (apply_) {
      auto apply = std::move(apply_);
      apply_ = nullptr;
      apply();
    }
  }
}

namespace {
// The scene and its -D values were checked against the checkpoint before the
// replay began: what is left to differ is what the journal does not keep.
constexpr const char* another_path_why =
    "the scene's choices depend on something the journal does not keep: values read through "
    "sim:arrays() or sim:contact_arrays(), which read NaN while a restart replays (take them "
    "from sim:particle, sim:stats or sim:contacts to decide), a file the scene reads that "
    "changed, an environment variable, or the order of `next` over a table";
// The replay parted from the journal where `what` says.
[[noreturn]] void another_path(const std::string& what) {
  throw std::runtime_error(fmt::format(
      "restart: the scene took another path than the run that wrote the checkpoint: {} ({})", what,
      another_path_why));
}
}  // namespace

void Journal::expect_call(const char* name, std::uint64_t arguments, bool check_arguments) {
  if (cursor_ >= bytes_.size()) damaged("it ended");
  const std::size_t at = cursor_;
  const std::uint8_t tag = get_byte();
  if (tag == tag_callback) {
    cursor_ = at;
    another_path(fmt::format("it called {} where that run's sim:run fired a callback", name));
  }
  if (tag == tag_results || tag == tag_error) {
    // The results of a call that has begun: only a run's, whose callback this is.
    cursor_ = at;
    another_path(fmt::format("it called {} where that run's callback had returned", name));
  }
  if (tag != tag_call) damaged("a call was expected");
  const std::string recorded = get_interned(get_byte());
  took_results_ = false;
  if (recorded != name)
    another_path(fmt::format("it called {} where that run called {}", name, recorded));
  ++calls_replayed_;
  ++entries_;  // the journal's entries, the first run's counted as they are replayed
  if (format_in_use_ >= 2) {
    std::uint64_t recorded_arguments = 0;
    for (int k = 0; k < 8; ++k)
      recorded_arguments |= static_cast<std::uint64_t>(get_byte()) << (8 * k);
    if (check_arguments && recorded_arguments != arguments)
      another_path(fmt::format("its call {}, {}, was given other values than in that run",
                               calls_replayed_, name));
  }
  check_end();
}

Journal::Next Journal::peek(bool after_callback) {
  if (!replaying_) return Next::end;
  if (cursor_ >= bytes_.size()) damaged("it ended");
  switch (bytes_[cursor_]) {
    case tag_results:
    case tag_build:
      return Next::results;
    case tag_error:
      return Next::error;
    case tag_callback:
      return Next::callback;
    case tag_call:
      if (after_callback) {
        ++cursor_;
        another_path(fmt::format("a callback returned where in that run it went on to call {}",
                                 get_interned(get_byte())));
      }
      damaged("a call where a call's results were expected");
    default:
      damaged("an unknown entry");
  }
}

int Journal::push_results(lua_State* L) {
  const std::uint8_t tag = get_byte();
  int n = 0;
  if (tag == tag_results) {
    const std::uint64_t count = get_u64();
    if (count > 255) damaged("too many results");
    n = static_cast<int>(count);
    for (int k = 0; k < n; ++k) push_value(L, 0);
  } else if (tag != tag_build) {
    damaged("results were expected");
  }
  check_end();
  took_results_ = true;
  return n;
}

void Journal::skip_results() {
  const std::uint8_t tag = get_byte();
  if (tag == tag_results) {
    // Results of a build call are not replayed; a build call journals none, so this
    // only skips a count of zero.
    if (get_u64() != 0) damaged("a build call with results");
  } else if (tag != tag_build) {
    damaged("results were expected");
  }
  took_results_ = true;
}

void Journal::push_error(lua_State* L) {
  if (get_byte() != tag_error) damaged("an error was expected");
  push_value(L, 0);
  check_end();
  took_results_ = true;
}

std::int64_t Journal::take_callback() {
  if (get_byte() != tag_callback) damaged("a callback was expected");
  const std::int64_t id = static_cast<std::int64_t>(get_u64()) - 1;
  ++entries_;
  check_end();
  return id;
}

// ---- the wrapper ----

namespace {

struct CallName {
  const char* name;
  Journal::Kind kind;
};

// Runs f(); a C++ exception leaves its message on the stack (prefixed with the
// script's line if `where`) and true: the caller raises it once the C++ frames are
// gone (a Lua error is a longjmp).
template <typename F>
bool failed_with_message(lua_State* L, F&& f, bool where = false) {
  bool failed = false;
  {
    std::string message;
    try {
      f();
    } catch (const std::exception& e) {
      message = e.what();
      failed = true;
    }
    if (failed) {
      if (where) push_script_where(L);
      lua_pushstring(L, message.c_str());
      if (where) lua_concat(L, 2);
    }
  }
  return failed;
}

// upvalue 1: the wrapped function; upvalue 2: light userdata, the CallName.
int journaled_call(lua_State* L) {
  const auto* call = static_cast<const CallName*>(lua_touserdata(L, lua_upvalueindex(2)));
  SceneContext* ctx = context(L);
  Journal* j = ctx ? ctx->journal.get() : nullptr;
  const int nargs = lua_gettop(L);
  // A scene a signal stopped makes no more engine calls, even one that caught the stop
  // (pcall): it would go on computing what its checkpoint no longer holds, and end with
  // status 0 when a scheduler asked it to stop. (The clocks stay readable; the REPL goes
  // on after a stop by design.)
  if (ctx && ctx->interrupted && !ctx->repl && std::strncmp(call->name, "os.", 3) != 0 &&
      std::strcmp(call->name, "wall_time") != 0) {
    push_script_where(L);
    lua_pushfstring(L, "%s: the scene was stopped (%s); it makes no more engine calls", call->name,
                    ctx->interrupt_message.c_str());
    lua_concat(L, 2);
    return lua_error(L);
  }
  // Calls the wrapped function below the arguments, protected, so that an error can be
  // journaled before it goes on; journals the outcome when `record` and the journal is
  // recording (and the results were not the journal's own).
  auto call_inner = [&](bool record) -> int {
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    const int status = lua_pcall(L, nargs, LUA_MULTRET, 0);
    if (record && j && !j->replaying() && !j->took_results() && failed_with_message(L, [&] {
          if (status != LUA_OK)
            j->record_error(L, -1);
          else if (call->kind == Journal::Kind::build)
            j->record_no_results();
          else
            j->record_results(L, 1, lua_gettop(L));
        }))
      return lua_error(L);
    if (status != LUA_OK) return lua_error(L);
    return lua_gettop(L);
  };
  if (!j) return call_inner(false);
  if (!ctx->restart_failure.empty()) {
    lua_pushstring(L, ctx->restart_failure.c_str());
    return lua_error(L);
  }
  if (ctx->begin_replay) {  // --restart: the replay starts before the first journaled call
    if (failed_with_message(L, [&] {
          auto begin = std::move(ctx->begin_replay);
          ctx->begin_replay = nullptr;
          try {
            begin();
          } catch (const std::exception& e) {
            ctx->restart_failure = e.what();  // the restart's error, not this call's
            throw;
          }
        }))
      return lua_error(L);
  }
  if (!j->replaying()) {
    if (failed_with_message(L, [&] { j->record_call(call->name, Journal::digest(L, 1, nargs)); }))
      return lua_error(L);
    if (j->passed_size_mark() && !ctx->quiet)
      std::cerr << fmt::format(
          "warning: the restart journal (what the script has read from the engine, {} calls, "
          "kept in memory so that a checkpoint can replay the script) holds {:.3g} MB and grows "
          "with every read: a script that reads many particles every few steps should read "
          "them through sim:arrays() or sim:contact_arrays(), which journal nothing, or in a "
          "C++ diagnostic (docs/architecture.md)\n",
          j->entries(), j->bytes().size() / 1e6);
    return call_inner(true);
  }
  if (failed_with_message(
          L,
          [&] {
            // Once the replay has read views (NaN there, and warned), the values the
            // scene computes from them differ from the first run's by design.
            j->expect_call(call->name, Journal::digest(L, 1, nargs), !ctx->views_read_in_replay);
          },
          true))
    return lua_error(L);
  // The journal ended with this call's start: it executes for real, and is journaled.
  if (!j->replaying()) return call_inner(true);

  Journal::Next next = Journal::Next::results;
  int results = 0;
  if (failed_with_message(L, [&] {
        next = j->peek();
        if (call->kind == Journal::Kind::run) {
          next = Journal::Next::callback;  // the run replays its own callbacks (l_run)
        } else if (next == Journal::Next::error) {
          j->push_error(L);
        } else if (next == Journal::Next::results) {
          if (call->kind == Journal::Kind::build)
            j->skip_results();
          else
            results = j->push_results(L);
        } else {
          throw std::runtime_error(fmt::format(
              "restart: the checkpoint's journal holds a callback inside {}", call->name));
        }
      }))
    return lua_error(L);
  switch (call->kind) {
    case Journal::Kind::run:
      // The run itself replays the callbacks it fired and returns its journaled result,
      // or, when the journal ends inside it, continues it for real (journaled again).
      return call_inner(true);
    case Journal::Kind::build: {
      if (next == Journal::Next::error) return lua_error(L);
      // Made again on the scene being rebuilt, and only then, if this call ends the
      // journal, the checkpoint's state loaded: the run that wrote it had made the
      // call before its checkpoint (made after the load, a sim:set_contact would ask
      // for a preparation that run never had, a sim:every a second hook).
      const int n = call_inner(true);
      if (failed_with_message(L, [&] { j->end_of_build_call(); })) return lua_error(L);
      return n;
    }
    case Journal::Kind::observe:
    case Journal::Kind::checkpoint:
      // Its results were the journal's; a run it was called in (from a callback)
      // and that goes on after the journal's end journals its own.
      j->forget_took_results();
      if (next == Journal::Next::error) return lua_error(L);
      return results;
  }
  return 0;
}

}  // namespace

void push_journaled(lua_State* L, const char* name, Journal::Kind kind) {
  // One CallName per wrapped function, alive as long as the program (names are literals or
  // interned below).
  static std::vector<std::unique_ptr<CallName>> names;
  static std::vector<std::unique_ptr<std::string>> texts;
  texts.push_back(std::make_unique<std::string>(name));
  names.push_back(std::make_unique<CallName>(CallName{texts.back()->c_str(), kind}));
  lua_pushlightuserdata(L, names.back().get());
  lua_pushcclosure(L, journaled_call, 2);
}

Journal::Kind journal_kind(const std::string& method) {
  // Calls that build the scene's structure execute again in replay: the engine must
  // hold the same materials, laws, walls, hooks, diagnostics and output when the
  // checkpoint's state is loaded into it. Everything else reads or changes the state
  // (which the checkpoint brings) or writes output (which the continued file holds).
  static const char* build[] = {"simulation", "material", "contact", "set_contact", "wall_plane",
                                "wall_cylinder", "wall_mesh", "wall_polyline", "wall_disk",
                                "wall_cone", "set_wall", "gravity", "set_damping", "central_field",
                                "remove_central_field", "set_central_strength", "schedule",
                                "remove_schedule", "every", "remove_hook", "set", "output",
                                "checkpoint", "diagnostic", "remove_diagnostic",
                                // views of the engine's arrays: made again, read live
                                // (wrap_views.cpp says what they read while replaying)
                                "arrays", "contact_arrays"};
  if (method == "run") return Journal::Kind::run;
  if (method == "save_checkpoint") return Journal::Kind::checkpoint;
  for (const char* b : build)
    if (method == b) return Journal::Kind::build;
  return Journal::Kind::observe;
}

void journal_clocks(lua_State* L) {
  // The clocks are inputs like the engine's results; a restarted scene sees the times
  // the first run saw.
  lua_getglobal(L, "os");
  // os.tmpname too: a new name in every process, which a call's arguments then hold
  // (granule.mesh_shapes writes its meshes there).
  for (const char* name : {"time", "clock", "date", "tmpname"}) {
    lua_getfield(L, -1, name);
    push_journaled(L, (std::string("os.") + name).c_str(), Journal::Kind::observe);
    lua_setfield(L, -2, name);
  }
  lua_pop(L, 1);
  lua_getglobal(L, "wall_time");
  if (lua_isfunction(L, -1)) {
    push_journaled(L, "wall_time", Journal::Kind::observe);
    lua_setglobal(L, "wall_time");
  } else {
    lua_pop(L, 1);
  }
  // math.random from a fixed seed: a scene draws the same numbers every run (and so
  // again after a restart); math.randomseed(os.time()) varies them, journaled.
  lua_getglobal(L, "math");
  lua_getfield(L, -1, "randomseed");
  lua_pushinteger(L, 20011);
  lua_call(L, 1, 0);
  lua_pop(L, 1);
}

}  // namespace granule::lua
