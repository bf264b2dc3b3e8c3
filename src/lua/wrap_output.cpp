// The simulation's HDF5 output from Lua: sim:output opens it, snapshot, series,
// append and result write into it, close finishes it (io/run_output.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <memory>

#include "core/errors.hpp"
#include "io/run_output.hpp"
#include "io/same_file.hpp"
#include "lua/journal.hpp"
#include "lua/lua_util.hpp"
#include "lua/scene.hpp"
#include "lua/wrap_simulation.hpp"

namespace granule::lua {

namespace {
io::RunOutput& output_of(LuaSim& s) {
  if (!s.output) throw std::runtime_error("no output file: call sim:output { ... } first");
  return *s.output;
}
// A file the scene has finished: named as complete, not partial, if the scene then fails.
void mark_finished(SceneContext* ctx, const std::string& path) {
  if (ctx && !(ctx->journal && ctx->journal->replaying())) ctx->outputs_finished.insert(path);
}

}  // namespace

// ---- output ----
int l_output(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    SceneContext* ctx = context(L);
    TableReader t(L, 2, "output");
    io::RunOutputSettings o;
    std::string fallback = ctx->output_path;
    if (fallback.empty())
      fallback = ctx->scene_path.empty()
                     ? "granule.h5"
                     : std::filesystem::path(ctx->scene_path).stem().string() + ".h5";
    // -o on the command line wins over the scene's own choice: the first output
    // is -o's file, a later one that names its own (the scene's second file)
    // -o's stem joined to its own, so that every case of a sweep writes files of
    // its own; a later one that names none is -o's again, refused below as the
    // scene's default name would be.
    o.path = ctx->output_path.empty() ? t.string("file", fallback) : ctx->output_path;
    if (!ctx->output_path.empty() && ctx->outputs_under_o > 0 && t.has("file")) {
      const std::filesystem::path named(ctx->output_path);
      const std::string own = std::filesystem::path(t.string("file")).stem().string();
      o.path =
          (named.parent_path() / (named.stem().string() + "_" + own + named.extension().string()))
              .string();
    }
    // A restarted run writes beside the original's output, never over it (unless -o says so).
    if (!ctx->restart_path.empty() && ctx->output_path.empty()) {
      std::filesystem::path p(o.path);
      o.path =
          (p.parent_path() / (p.stem().string() + "_restarted" + p.extension().string())).string();
    }
    // -o wins, but the scene's own 'file' must still be a file name.
    if (!ctx->output_path.empty() && t.has("file")) (void)t.string("file");
    // One file, one role: opened again it would be emptied of what it holds.
    if (s.running)
      throw InputError(
          "output: not from inside a run's callback (the run's snapshots and series go to the "
          "output it began with); open it before sim:run");
    if (io::same_file(o.path, ctx->scene_path))
      throw InputError(
          fmt::format("output: {} is the scene file; give the output another name", o.path));
    if (io::same_file(o.path, ctx->restart_path))
      throw InputError(fmt::format(
          "output: {} is the checkpoint this run continues; give the output another name", o.path));
    if (io::same_file(o.path, s.checkpoint.path))
      throw InputError(fmt::format(
          "output: {} is also where this simulation's checkpoints go; a checkpoint would replace "
          "the results it holds: give the output or the checkpoint another name",
          o.path));
    for (const std::string& opened : s.output_paths)
      if (io::same_file(o.path, opened))
        throw InputError(fmt::format(
            "output: {} was already opened by this simulation; opening it again would erase "
            "what it holds: call sim:output once per file (its settings hold for every later "
            "run)",
            o.path));
    o.snapshot_every = t.number("snapshot_every", 0);
    o.series_every = t.number("series_every", 0);
    o.xdmf = t.boolean("xdmf", true);
    o.forces = t.boolean("forces", false);
    o.contacts = t.boolean("contacts", false);
    t.finish();
    // The XDMF names its data "file.h5:/path": a reader splits that at its first ':'.
    if (o.xdmf && std::filesystem::path(o.path).filename().string().find(':') != std::string::npos)
      s.sim->warn(fmt::format(
          "output {}: the file's name holds a ':', where XDMF readers (ParaView) split a data "
          "reference, so the .xmf beside it will not open; name the file without ':' (or give "
          "xdmf = false)",
          o.path));
    o.scene_path = ctx->scene_path;
    o.scene_source = ctx->scene_source;
    o.parameters = ctx->parameter_values;
    o.numeric_parameters = ctx->numeric_parameters;
    o.integer_parameters = ctx->integer_parameters;
    for (const auto& d : ctx->parameter_docs) o.parameter_units[d.name] = d.unit;
    // Replaying a restarted scene's past: the output is made (its hooks in their places)
    // but writes nothing; the checkpoint's output is continued when the journal ends.
    o.muted = ctx->journal && ctx->journal->replaying();
    if (s.output) mark_finished(ctx, s.output->path());
    s.output.reset();
    s.output = std::make_unique<io::RunOutput>(*s.sim, o);
    if (ctx) ctx->outputs_finished.erase(o.path);
    ++s.output_calls;
    if (!ctx->output_path.empty()) ++ctx->outputs_under_o;  // opened: the next is a second file
    s.output_paths.push_back(o.path);
    if (!o.muted) ctx->outputs_written.push_back(o.path);
    lua_pushstring(L, o.path.c_str());
    return 1;
  });
}

int l_snapshot(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    auto& out = output_of(s);
    if (lua_isnoneornil(L, 2)) {
      out.write_snapshot();
      return 0;
    }
    // sim:snapshot { forces =, contacts = }: this snapshot only; the output's own by default.
    TableReader t(L, 2, "snapshot");
    const bool forces = t.boolean("forces", out.settings().forces);
    const bool contacts = t.boolean("contacts", out.settings().contacts);
    t.finish();
    out.write_snapshot(forces, contacts);
    return 0;
  });
}

int l_series(lua_State* L) {
  return protect(L, [](lua_State* L) {
    auto& out = output_of(self(L));
    std::string name = read_string(L, 2, "series name");
    auto columns = read_string_list(L, 3, "series columns");
    std::vector<std::string> units;
    if (!lua_isnoneornil(L, 4)) units = read_string_list(L, 4, "series units");
    out.declare_series(name, columns, units);
    return 0;
  });
}

int l_append(lua_State* L) {
  return protect(L, [](lua_State* L) {
    auto& out = output_of(self(L));
    std::string name = read_string(L, 2, "series name");
    if (!lua_istable(L, 3)) throw std::runtime_error("append: expected a list of numbers");
    std::vector<double> row;
    const auto n = static_cast<lua_Integer>(lua_rawlen(L, 3));
    for (lua_Integer k = 1; k <= n; ++k) {
      lua_rawgeti(L, 3, k);
      row.push_back(read_number(L, -1, fmt::format("append '{}' value {}", name, k)));
      lua_pop(L, 1);
    }
    out.append_series(name, row);
    return 0;
  });
}

int l_result(lua_State* L) {
  return protect(L, [](lua_State* L) {
    auto& out = output_of(self(L));
    TableReader t(L, 2, "result");
    const std::vector<std::string> names = t.keys();
    std::size_t entries = 0;
    lua_pushnil(L);
    while (lua_next(L, 2) != 0) ++entries, lua_pop(L, 1);
    if (entries != names.size())
      throw InputError(
          "result: every value needs a name (sim:result { name = value }); one without would "
          "be lost");
    for (const auto& key : names) {  // each a column of /results and of a sweep's summary
      const bool control = std::any_of(key.begin(), key.end(),
                                       [](unsigned char c) { return c < 0x20 || c == 0x7f; });
      // A comma would split the name in the lists that join result names (a
      // sweep's partial_results attribute, its CSV header).
      if (key.empty() || key == "." || key == ".." ||
          key.find_first_of("/,") != std::string::npos || control)
        throw InputError(fmt::format(
            "result: the name '{}' cannot name a column of /results (empty, '.', '..', or holding "
            "a '/', a ',' or a control character)",
            key));
    }
    for (const auto& key : names) out.write_result(key, t.number(key.c_str()));
    return 0;
  });
}

int l_close(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    // In the REPL what the user does at the prompt after the scene goes to the same
    // file: it is finished when the session ends (the simulation is collected).
    if (SceneContext* ctx = context(L); ctx && ctx->repl) {
      if (s.output) s.output->flush();
      return 0;
    }
    if (s.running)
      throw InputError(
          "close: not from inside a run's callback (the run's snapshots and series go on into "
          "the output until it ends); close it after sim:run");
    if (s.output) {
      s.output->finish();
      mark_finished(context(L), s.output->path());
    }
    s.output.reset();
    return 0;
  });
}

}  // namespace granule::lua
