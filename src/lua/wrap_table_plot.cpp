// A look at a simulation from the prompt: sim:table prints particles as a table,
// sim:plot draws a series of the output as a PNG (through tools/plot_series.py).
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/names.hpp"
#include "io/rank_files.hpp"
#include "io/run_output.hpp"
#include "lua/lua_util.hpp"
#include "lua/run_progress.hpp"
#include "lua/shown.hpp"
#include "lua/wrap_simulation.hpp"

extern char** environ;

namespace granule::lua {

namespace {

// The value of one field of particle `id`, and its column heading.
const char* const table_fields[] = {"id", "x",  "y",  "z",  "vx", "vy",     "vz",       "wx",
                                    "wy", "wz", "fx", "fy", "fz", "radius", "material", "mass"};

double field_value(const SimulationBase& sim, std::int64_t id, const std::string& f) {
  const int d = sim.dimension();
  auto part = [&](const Triple& v, int k) { return k < d ? v[k] : 0.0; };
  if (f == "id") return static_cast<double>(id);
  if (f == "x" || f == "y" || f == "z") return part(sim.position(id), f[0] - 'x');
  if (f == "vx" || f == "vy" || f == "vz") return part(sim.velocity(id), f[1] - 'x');
  if (f == "fx" || f == "fy" || f == "fz") return part(sim.force(id), f[1] - 'x');
  if (f == "wx" || f == "wy" || f == "wz") return sim.spin(id)[f[1] - 'x'];
  if (f == "radius") return sim.radius(id);
  if (f == "mass") return sim.mass(id);
  return static_cast<double>(sim.material_of(id));  // "material"
}

}  // namespace

// sim:table { ids = { ... }, fields = { ... } } -> text (also printed)
int l_table(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    const SimulationBase& sim = *s.sim;
    TableReader t(L, 2, "table");
    std::vector<std::int64_t> ids;
    if (t.push_table("ids")) {
      const auto n = static_cast<lua_Integer>(lua_rawlen(L, -1));
      for (lua_Integer k = 1; k <= n; ++k) {
        lua_rawgeti(L, -1, k);
        ids.push_back(particle_id(L, lua_gettop(L), sim));
        lua_pop(L, 1);
      }
      lua_pop(L, 1);
    } else {
      for (std::int64_t id : sim.particle_ids()) {
        if (ids.size() == 20) break;  // the first 20, as the prompt shows long lists
        ids.push_back(id);
      }
    }
    std::vector<std::string> fields;
    if (t.push_table("fields")) {
      fields = read_string_list(L, lua_gettop(L), "table: fields");
      lua_pop(L, 1);
    } else {
      fields = sim.dimension() == 2
                   ? std::vector<std::string>{"id", "x", "y", "vx", "vy", "wz", "radius"}
                   : std::vector<std::string>{"id", "x", "y", "z", "vx", "vy", "vz", "radius"};
    }
    t.finish();
    std::vector<std::string> known(std::begin(table_fields), std::end(table_fields));
    for (const auto& f : fields)
      if (std::find(known.begin(), known.end(), f) == known.end()) {
        const std::string hint = nearest_name(f, known);
        throw std::runtime_error(
            fmt::format("table: no field '{}'{}; fields: {}", f,
                        hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint),
                        fmt::join(known, ", ")));
      }
    std::string text;
    for (const auto& f : fields) text += fmt::format("{:>13}", f);
    text += "\n";
    for (std::int64_t id : ids) {
      for (const auto& f : fields) {
        const double v = field_value(sim, id, f);
        text += (f == "id" || f == "material") ? fmt::format("{:>13}", static_cast<long long>(v))
                                               : fmt::format("{:>13.6g}", v);
      }
      text += "\n";
    }
    clear_progress_line();
    std::cout << text << std::flush;
    lua_pushlstring(L, text.data(), text.size());
    mark_shown(L);
    return 1;
  });
}

// sim:plot(name [, { file = }]) -> png path
int l_plot(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    const std::string name = read_string(L, 2, "plot: series name");
    std::string file;
    if (!lua_isnoneornil(L, 3)) {
      if (!lua_istable(L, 3)) throw std::runtime_error("plot: the second argument is { file = }");
      lua_pushnil(L);
      while (lua_next(L, 3) != 0) {
        const bool is_file =
            lua_type(L, -2) == LUA_TSTRING && std::string(lua_tostring(L, -2)) == "file";
        if (!is_file || lua_type(L, -1) != LUA_TSTRING) {
          lua_pop(L, 2);
          throw std::runtime_error(
              "plot: the second argument is { file = 'name.png' }, nothing else");
        }
        file = lua_tostring(L, -1);
        lua_pop(L, 1);
      }
      if (file.empty()) throw std::runtime_error("plot: file must not be empty");
    }
    if (!s.output) throw std::runtime_error("plot: no output file: call sim:output { ... } first");
    io::H5Output& h5 = s.output->file();
    // "group/column" for a scene's own series, else a column of /series; a name that is
    // no column but begins some ("kinetic_energy") plots each of them.
    std::string group = "/series", column = name;
    if (auto slash = name.rfind('/'); slash != std::string::npos) {
      group = "/" + name.substr(0, slash);
      column = name.substr(slash + 1);
    }
    const auto columns = h5.series_columns(group);
    if (columns.empty())
      throw std::runtime_error(fmt::format("plot: the output has no series '{}'", group));
    std::vector<std::string> chosen;
    for (const auto& c : columns)
      if (c != "time" && (c == column || c.rfind(column + "_", 0) == 0)) chosen.push_back(c);
    if (chosen.empty()) {
      const std::string hint = nearest_name(column, columns);
      throw std::runtime_error(
          fmt::format("plot: series {} has no column '{}'{}; it has {}", group, column,
                      hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint),
                      fmt::join(columns, ", ")));
    }
    s.output->flush();  // the rows so far on disk, for the plotting script to read
    const std::filesystem::path out(s.output->path());
    if (file.empty()) {
      std::string stem = column;
      for (auto& ch : stem)
        if (ch == '/') ch = '_';
      file = (out.parent_path() / (out.stem().string() + "_" + stem + ".png")).string();
    }
    // A rank other than 0 draws into its scratch folder, from its own copy of the
    // output (the path the output names is rank 0's file).
    file = io::writable_path(file);
    const std::string source = io::readable_path(out.string());
    const std::filesystem::path tools =
        std::filesystem::path(library_dir()).parent_path() / "tools";
    const char* python_env = std::getenv("GRANULE_PYTHON");
    const std::string python = python_env && *python_env ? python_env : "/usr/bin/python3";
    std::vector<std::string> args{
        python,      (tools / "plot_series.py").string(),       source, "--group", group,
        "--columns", fmt::format("{}", fmt::join(chosen, ",")), "-o",   file};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    // No shell: file names with spaces or quotes reach the script as they are.
    pid_t pid = 0;
    if (posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0)
      throw std::runtime_error(
          fmt::format("plot: cannot run {} (GRANULE_PYTHON names another)", python));
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
      throw std::runtime_error(fmt::format("plot: {} failed for {} (its message is above)",
                                           (tools / "plot_series.py").string(), source));
    clear_progress_line();
    std::cout << "plot: " << fmt::format("{}", fmt::join(chosen, ", ")) << " in " << file << "\n"
              << std::flush;
    lua_pushstring(L, file.c_str());
    mark_shown(L);
    return 1;
  });
}

}  // namespace granule::lua
