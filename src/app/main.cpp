// granule: the command-line front end.
//   granule run scene.lua [-D name=value ...] [-o out.h5] [--quiet]
//   granule repl [scene.lua] [-D ...]
//   granule models          list contact models and their parameters
#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <iostream>
#include <lua.hpp>
#include <string>
#include <vector>

#include "contact/models.hpp"
#include "lua/lua_simulation.hpp"
#include "lua/scene.hpp"

#ifdef GRANULE_HAVE_READLINE
#include <readline/history.h>
#include <readline/readline.h>
#endif
#include <unistd.h>

#include <csignal>

namespace {

const char* usage =
    "usage:\n"
    "  granule run SCENE.lua [-D name=value ...] [-o OUT.h5] [--quiet] [--threads N]\n"
    "              [--restart CHECKPOINT.h5]\n"
    "  granule repl [SCENE.lua] [-D name=value ...]\n"
    "  granule models\n"
    "  granule --version\n";

struct Options {
  std::string command, scene;
  granule::lua::SceneContext ctx;
};

int fail_usage(const std::string& message) {
  std::cerr << "granule: " << message << "\n" << usage;
  return 2;
}

// Ctrl-C during a run: the run loop writes a checkpoint at the next chunk
// boundary and stops; a second Ctrl-C ends the program at once.
extern "C" void on_interrupt(int) {
  if (granule::lua::interrupt_requested.exchange(true)) std::_Exit(130);
}

int run_scene(Options& o) {
  std::signal(SIGINT, on_interrupt);
  lua_State* L = granule::lua::new_state(&o.ctx);
  granule::lua::make_globals_strict(L);
  std::string err = granule::lua::run_file(L, o.scene);
  lua_close(L);  // closes output files (their final snapshot) even after an error
  if (!err.empty()) {
    std::cerr << "error: " << err << "\n";
    for (const auto& f : o.ctx.outputs_written)
      std::cerr << "partial results kept in " << f << "\n";
    return granule::lua::interrupt_requested.load() ? 130 : 1;
  }
  return 0;
}

bool read_line(const char* prompt, std::string& line) {
#ifdef GRANULE_HAVE_READLINE
  if (isatty(0)) {
    char* s = readline(prompt);
    if (!s) return false;
    line = s;
    if (*s) add_history(s);
    free(s);
    return true;
  }
#endif
  if (isatty(0)) std::cout << prompt << std::flush;
  return static_cast<bool>(std::getline(std::cin, line));
}

// Follows lua.c: try "return <line>" first so expressions print; keep reading
// while the chunk is incomplete ("<eof>" errors); errors never end the session.
int repl(Options& o) {
  lua_State* L = granule::lua::new_state(&o.ctx);
  if (!o.scene.empty()) {
    std::string err = granule::lua::run_file(L, o.scene);
    if (!err.empty()) std::cerr << "error: " << err << "\n";
  }
  if (isatty(0)) std::cout << "granule " << GRANULE_VERSION << " REPL (Lua 5.4); Ctrl-D to quit\n";
  std::string line;
  while (read_line("> ", line)) {
    std::string chunk = line;
    for (;;) {
      std::string as_expr = "return " + chunk;
      if (luaL_loadbuffer(L, as_expr.data(), as_expr.size(), "=stdin") == LUA_OK) break;
      lua_pop(L, 1);
      if (luaL_loadbuffer(L, chunk.data(), chunk.size(), "=stdin") == LUA_OK) break;
      std::string msg = lua_tostring(L, -1);
      lua_pop(L, 1);
      if (msg.size() >= 5 && msg.compare(msg.size() - 5, 5, "<eof>") == 0) {
        std::string more;
        if (!read_line(">> ", more)) break;
        chunk += "\n" + more;
        continue;
      }
      std::cout << "error: " << msg << "\n";
      chunk.clear();
      break;
    }
    if (chunk.empty() || lua_gettop(L) == 0) continue;
    int base = lua_gettop(L);
    if (lua_pcall(L, 0, LUA_MULTRET, 0) != LUA_OK) {
      std::cout << "error: " << (lua_tostring(L, -1) ? lua_tostring(L, -1) : "?") << "\n";
      lua_settop(L, 0);
      continue;
    }
    int n = lua_gettop(L) - base + 1;
    for (int k = 0; k < n; ++k) {
      std::cout << (k ? "\t" : "") << luaL_tolstring(L, base + k, nullptr);
      lua_pop(L, 1);
    }
    if (n > 0) std::cout << "\n";
    lua_settop(L, 0);
  }
  lua_close(L);
  return 0;
}

int list_models() {
  for (const auto& m : granule::contact_model_catalogue()) {
    std::cout << m.name << ": " << m.doc << "\n";
    for (const auto& p : m.parameters) {
      std::string def =
          std::isnan(p.default_value) ? "required" : fmt::format("default {}", p.default_value);
      std::cout << fmt::format("    {:<26} [{}] {}; {}\n", p.name, p.unit, def, p.doc);
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty()) return fail_usage("no command given");
  Options o;
  o.command = args[0];
  if (o.command == "--version") {
    std::cout << "granule " << GRANULE_VERSION << "\n";
    return 0;
  }
  if (o.command == "--help" || o.command == "-h" || o.command == "help") {
    std::cout << usage;
    return 0;
  }
  if (o.command == "models") return list_models();
  if (o.command != "run" && o.command != "repl")
    return fail_usage("unknown command '" + o.command + "'");
  for (std::size_t k = 1; k < args.size(); ++k) {
    const std::string& a = args[k];
    if (a == "-D" || a == "-o") {
      if (k + 1 >= args.size()) return fail_usage(a + " needs a value");
      const std::string& v = args[++k];
      if (a == "-o") {
        o.ctx.output_path = v;
      } else {
        auto eq = v.find('=');
        if (eq == std::string::npos || eq == 0)
          return fail_usage("-D expects name=value, got '" + v + "'");
        o.ctx.overrides[v.substr(0, eq)] = v.substr(eq + 1);
      }
    } else if (a.rfind("-D", 0) == 0 && a.size() > 2) {
      std::string v = a.substr(2);
      auto eq = v.find('=');
      if (eq == std::string::npos || eq == 0)
        return fail_usage("-D expects name=value, got '" + v + "'");
      o.ctx.overrides[v.substr(0, eq)] = v.substr(eq + 1);
    } else if (a == "--quiet" || a == "-q") {
      o.ctx.quiet = true;
    } else if (a == "--restart") {
      if (k + 1 >= args.size()) return fail_usage("--restart needs a checkpoint file");
      o.ctx.restart_path = args[++k];
    } else if (a == "--threads") {
      if (k + 1 >= args.size()) return fail_usage("--threads needs a value");
      const std::string& v = args[++k];
      char* end = nullptr;
      long n = std::strtol(v.c_str(), &end, 10);
      if (v.empty() || *end != 0 || n < 1 || n > 4096)
        return fail_usage("--threads expects a whole number >= 1, got '" + v + "'");
      o.ctx.threads = static_cast<int>(n);
    } else if (!a.empty() && a[0] == '-') {
      return fail_usage("unknown option '" + a + "'");
    } else if (o.scene.empty()) {
      o.scene = a;
    } else {
      return fail_usage("more than one scene file given ('" + o.scene + "', '" + a + "')");
    }
  }
  o.ctx.scene_path = o.scene;
  if (o.command == "run") {
    if (o.scene.empty()) return fail_usage("run needs a scene file");
    return run_scene(o);
  }
  return repl(o);
}
