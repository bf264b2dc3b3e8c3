#include "app/repl.hpp"

#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <lua.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/interrupt.hpp"
#include "core/names.hpp"
#include "lua/completion.hpp"
#include "lua/run_progress.hpp"
#include "lua/shown.hpp"

#ifdef GRANULE_HAVE_READLINE
#include <readline/history.h>
#include <readline/readline.h>
#endif

namespace granule::app {

namespace {

#ifdef GRANULE_HAVE_READLINE
lua_State* completion_state = nullptr;

// History survives the session in ~/.granule_history (the last 1000 lines),
// appended line by line so that even a killed session keeps it.
std::string history_file() {
  const char* home = std::getenv("HOME");
  return home && *home ? std::string(home) + "/.granule_history" : "";
}

char* completion_generator(const char* text, int state) {
  static std::vector<std::string> matches;
  static std::size_t next = 0;
  if (state == 0) {
    matches = lua::complete(completion_state, text);
    next = 0;
  }
  if (next < matches.size()) return strdup(matches[next++].c_str());
  return nullptr;
}

char** attempted_completion(const char* text, int, int) {
  rl_attempted_completion_over = 1;  // names from Lua only, never file names
  return rl_completion_matches(text, completion_generator);
}

void setup_readline(lua_State* L) {
  completion_state = L;
  rl_readline_name = "granule";
  // '.' and ':' are part of the word, so that granule.vec.n and sim:ru complete.
  rl_basic_word_break_characters = const_cast<char*>(" \t\n\"\\'`@$><=;|&{}()[],+-*/%^~#");
  rl_completion_append_character = '\0';
  rl_attempted_completion_function = attempted_completion;
  std::string file = history_file();
  if (!file.empty()) {
    // append_history needs the file to exist; a missing or unreadable one is not an error.
    if (FILE* f = std::fopen(file.c_str(), "a")) std::fclose(f);
    history_truncate_file(file.c_str(), 1000);
    read_history(file.c_str());
  }
}

// Ctrl-C at the prompt drops the line being typed and shows a fresh prompt, as
// a shell does; the session goes on (Ctrl-C stops runs, not the REPL). The
// handler only notes the signal: readline, its read interrupted, calls the
// event hook, which clears the line outside the handler.
volatile std::sig_atomic_t prompt_interrupted = 0;

void note_prompt_interrupt(int) {
  prompt_interrupted = 1;
}

int clear_line_after_interrupt() {
  if (!prompt_interrupted) return 0;
  prompt_interrupted = 0;
  rl_replace_line("", 0);
  rl_crlf();
  rl_on_new_line();
  rl_redisplay();
  return 0;
}
#endif

}  // namespace

bool read_terminal_line(const char* prompt, std::string& line) {
#ifdef GRANULE_HAVE_READLINE
  if (isatty(0)) {
    rl_catch_signals = 0;
    rl_signal_event_hook = clear_line_after_interrupt;
    struct sigaction on {
    }, before{};
    on.sa_handler = note_prompt_interrupt;
    sigemptyset(&on.sa_mask);
    on.sa_flags = 0;  // no SA_RESTART: readline's read sees EINTR and calls the hook
    sigaction(SIGINT, &on, &before);
    char* s = readline(prompt);
    sigaction(SIGINT, &before, nullptr);
    if (!s) return false;
    line = s;
    if (*s) {
      add_history(s);
      std::string file = history_file();
      if (!file.empty()) append_history(1, file.c_str());
    }
    free(s);
    return true;
  }
#endif
  if (isatty(0)) std::cout << prompt << std::flush;
  return static_cast<bool>(std::getline(std::cin, line));
}

ReplInput terminal_input() {
  return {read_terminal_line, isatty(0) != 0, {}};
}

namespace {

// The message of the error object on the stack top.
std::string error_text(lua_State* L) {
  const char* msg = lua_tostring(L, -1);
  return msg ? msg : std::string("(error object is a ") + luaL_typename(L, -1) + " value)";
}

// How the prompt shows a value: plain tables (a particle, stats, a list of ids)
// two levels deep with sorted keys and 6 significant digits, so that results can
// be read; anything else as tostring() shows it (its __tostring included).
const char* show_source = R"lua(
local function show(v, depth)
  if math.type(v) == "float" then return string.format("%.6g", v) end
  if type(v) == "string" and depth > 1 then return string.format("%q", v) end
  if type(v) ~= "table" or getmetatable(v) ~= nil then return tostring(v) end
  if depth > 2 then return "{...}" end
  local parts, n = {}, #v
  for i = 1, math.min(n, 20) do parts[#parts + 1] = show(v[i], depth + 1) end
  if n > 20 then parts[#parts + 1] = "... (" .. n .. " entries)" end
  local keys = {}
  for k in pairs(v) do
    if not (math.type(k) == "integer" and k >= 1 and k <= n) then keys[#keys + 1] = k end
  end
  table.sort(keys, function(a, b) return tostring(a) < tostring(b) end)
  for i, k in ipairs(keys) do
    if i > 40 then parts[#parts + 1] = "..." break end
    local name = type(k) == "string" and k:match("^[%a_][%w_]*$") and k or "[" .. show(k, 3) .. "]"
    parts[#parts + 1] = name .. " = " .. show(v[k], depth + 1)
  end
  return #parts == 0 and "{}" or "{ " .. table.concat(parts, ", ") .. " }"
end
return show
)lua";

// Prints the values on the stack, tab-separated, through `show` (upvalue 1).
// Called through lua_pcall: a __tostring metamethod may raise an error, which
// must not escape; no C++ object lives in this frame.
int print_values(lua_State* L) {
  int n = lua_gettop(L);
  for (int k = 1; k <= n; ++k) {
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_pushvalue(L, k);
    lua_pushinteger(L, 1);
    lua_call(L, 2, 1);
    std::size_t len = 0;
    const char* s = lua_tolstring(L, -1, &len);
    if (k > 1) std::fputc('\t', stdout);
    if (s) std::fwrite(s, 1, len, stdout);
    lua_pop(L, 1);
  }
  if (n > 0) std::fputc('\n', stdout);
  std::fflush(stdout);
  return 0;
}

// After a scene has run: its simulation is a local of the scene, so give the
// last one a global name the user can type.
void bind_sim(lua_State* L, bool tell) {
  lua_getglobal(L, "sim");
  bool taken = !lua_isnil(L, -1);
  lua_pop(L, 1);
  if (taken) return;
  lua_getglobal(L, "simulations");
  if (lua_pcall(L, 0, 1, 0) != LUA_OK || !lua_istable(L, -1)) {
    lua_pop(L, 1);
    return;
  }
  lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, -1));
  if (n > 0) {
    lua_rawgeti(L, -1, n);
    const char* name = luaL_tolstring(L, -1, nullptr);
    if (tell) std::cerr << "granule: the scene's simulation is `sim`: " << name << "\n";
    lua_pop(L, 1);
    lua_setglobal(L, "sim");
  }
  lua_pop(L, 1);
}

// _G's __index at the prompt: a misspelt name is an error that names it (and the
// nearest global), where plain Lua would carry on with nil. Assigning a new global
// stays allowed: the prompt has no other place to keep a value.
int undefined_global(lua_State* L) {
  const char* name = lua_tostring(L, 2);
  if (!name) return 0;  // a non-string key (_G[1]) reads nil, as in plain Lua
  std::vector<std::string> known;
  lua_pushnil(L);
  while (lua_next(L, 1) != 0) {
    lua_pop(L, 1);
    if (lua_type(L, -1) == LUA_TSTRING) known.emplace_back(lua_tostring(L, -1));
  }
  const std::string hint = nearest_name(name, known);
  if (hint.empty()) return luaL_error(L, "%s is not defined", name);
  return luaL_error(L, "%s is not defined (did you mean %s?)", name, hint.c_str());
}

void report_undefined_globals(lua_State* L) {
  lua_pushglobaltable(L);
  lua_newtable(L);
  lua_pushcfunction(L, undefined_global);
  lua_setfield(L, -2, "__index");
  lua_setmetatable(L, -2);
  lua_pop(L, 1);
}

}  // namespace

// Follows lua.c: try "return <line>" first so expressions print; keep reading
// while the chunk is incomplete ("<eof>" errors); errors never end the session.
int run_repl(const std::string& scene, lua::SceneContext& ctx, const ReplInput& input) {
  ctx.repl = true;
  lua_State* L = lua::new_state(&ctx);
  lua::clear_progress_before_prints(L);
  if (input.prepare) input.prepare(L);
  const bool interactive = input.interactive;
  const auto& read_line = input.read;
  int failures = 0;
  if (luaL_loadstring(L, show_source) != LUA_OK || lua_pcall(L, 0, 1, 0) != LUA_OK)
    throw std::runtime_error("REPL: cannot load the value printer");
  lua_setfield(L, LUA_REGISTRYINDEX, "granule.repl_show");
  // The library as a global at the prompt (scenes still `require` it themselves).
  if (luaL_dostring(L, "granule = require 'granule'") != LUA_OK) {
    std::cerr << "error: " << error_text(L) << "\n";
    lua_settop(L, 0);
    ++failures;
  }
  if (!scene.empty()) {
    std::string err;
    {
      InterruptScope interrupt(L);
      err = lua::run_file(L, scene);
    }
    if (!err.empty()) {
      std::cerr << "error: " << err << "\n";
      ++failures;
    }
    bind_sim(L, ctx.rank == 0);
  }
  ctx.repl_prompt = true;  // from here the journal holds what is typed (checkpoints say so)
  report_undefined_globals(L);
#ifdef GRANULE_HAVE_READLINE
  if (interactive) setup_readline(L);
#endif
  if (interactive)
    std::cout << "granule " << GRANULE_VERSION
              << " REPL (Lua 5.4): help() lists the API, Tab completes, Ctrl-C stops a run, "
                 "Ctrl-D quits\n";
  std::string line;
  while (read_line("> ", line)) {
    std::string chunk = line;
    bool loaded = false;
    for (;;) {
      std::string as_expr = "return " + chunk;
      if (luaL_loadbuffer(L, as_expr.data(), as_expr.size(), "=stdin") == LUA_OK) {
        loaded = true;
        break;
      }
      lua_pop(L, 1);
      if (luaL_loadbuffer(L, chunk.data(), chunk.size(), "=stdin") == LUA_OK) {
        loaded = true;
        break;
      }
      std::string msg = error_text(L);
      lua_pop(L, 1);
      if (msg.size() >= 5 && msg.compare(msg.size() - 5, 5, "<eof>") == 0) {
        std::string more;
        if (!read_line(">> ", more)) {
          // The input ended inside a statement (a piped script cut short): said,
          // and counted as a failing line, not run half.
          std::cout << "error: the input ended inside an unfinished statement, which was not run: "
                    << msg << "\n";
          ++failures;
          break;
        }
        chunk += "\n" + more;
        continue;
      }
      std::cout << "error: " << msg << "\n";
      ++failures;
      break;
    }
    if (!loaded) {
      lua_settop(L, 0);
      continue;
    }
    int status;
    lua::clear_shown(L);
    {
      InterruptScope interrupt(L);
      status = lua_pcall(L, 0, LUA_MULTRET, 0);
    }
    if (status != LUA_OK) {
      std::cout << "error: " << error_text(L) << "\n";
      ++failures;
      lua_settop(L, 0);
      continue;
    }
    // sim:table and sim:plot print what they return: once is enough.
    if (lua_gettop(L) == 1 && lua::is_shown(L, 1)) lua_settop(L, 0);
    if (lua_gettop(L) > 0) {
      lua_getfield(L, LUA_REGISTRYINDEX, "granule.repl_show");
      lua_pushcclosure(L, print_values, 1);
      lua_insert(L, 1);
      if (lua_pcall(L, lua_gettop(L) - 1, 0, 0) != LUA_OK) {
        std::cout << "error: " << error_text(L) << "\n";
        ++failures;
      }
    }
    lua_settop(L, 0);
  }
  lua_close(L);
  return failures > 0 && !interactive ? 1 : 0;
}

}  // namespace granule::app
