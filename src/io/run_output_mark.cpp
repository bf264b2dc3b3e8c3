// RunOutput's checkpoint mark: how far the file has got (save_mark), and a muted
// output continued from it (resume): the file copied, cut back and written on.
#include <fmt/format.h>

#include <algorithm>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "io/effect_fields.hpp"
#include "io/rank_files.hpp"
#include "io/run_output.hpp"

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

// The effects noted so far (note_effects), for a checkpoint: "flag\tname" for
// each flag on, "list\tname\titem" for each list item.
std::string RunOutput::effects_text() const {
  std::vector<std::string> lines;
  for (const auto& [name, flag] : effect_flags())
    if (effects_seen_.*flag) lines.push_back(fmt::format("flag\t{}", name));
  for (const auto& [name, list] : effect_lists())
    for (const auto& item : effects_seen_.*list)
      lines.push_back(fmt::format("list\t{}\t{}", name, item));
  return join_lines(lines);
}

void RunOutput::restore_effects(const std::string& text) {
  effects_seen_ = ActiveEffects{};
  for (const auto& line : lines_of(text)) {
    const auto f = split_tabs(line);
    bool known = false;
    if (f.size() == 2 && f[0] == "flag")
      for (const auto& [name, flag] : effect_flags())
        if (f[1] == name) effects_seen_.*flag = known = true;
    if (f.size() == 3 && f[0] == "list")
      for (const auto& [name, list] : effect_lists())
        if (f[1] == name) {
          (effects_seen_.*list).push_back(f[2]);
          known = true;
        }
    if (!known) damaged_mark("output.effects");
  }
}

void RunOutput::save_mark(StateBlob& state) {
  if (!file_) return;
  // The file as it is now is what a restart from this checkpoint continues, whenever
  // this process dies: a write after this is undone from the file's journal first.
  state.integers["output.file_id"] = {static_cast<std::int64_t>(file_->mark())};
  // Absolute: a restart may run in another folder.
  std::error_code ec;
  const auto absolute = std::filesystem::absolute(settings_.path, ec);
  state.texts["output.path"] = ec ? settings_.path : absolute.string();
  std::vector<std::string> series;
  for (const auto& [group, rows] : file_->series_rows())
    series.push_back(fmt::format("{}\t{}", group, rows));
  state.texts["output.series"] = join_lines(series);
  state.texts["output.results"] = join_lines(file_->attribute_names("/results"));
  state.texts["output.top_level"] = join_lines(file_->top_level_names());
  state.texts["output.root_attributes"] = join_lines(file_->attribute_names("/"));
  state.integers["output.progress"] = {static_cast<std::int64_t>(file_->snapshot_count()),
                                       header_written_ ? 1 : 0,
                                       walls_written_,
                                       last_snapshot_step_,
                                       wall_extent_set_ ? 1 : 0,
                                       last_snapshot_digest_,
                                       last_series_step_,
                                       failure_step_,
                                       opening_due_ ? 1 : 0};
  state.doubles["output.wall_extent"] = {wall_extent_.begin(), wall_extent_.end()};
  if (xdmf_) xdmf_->flush();  // the index on disk as the checkpoint records it
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

void RunOutput::resume(const StateBlob& state, const std::function<bool(bool)>& copies_made) {
  if (!settings_.muted) throw std::logic_error("RunOutput::resume: the output is not muted");
  const std::string original = state.t("output.path");
  std::map<std::string, std::int64_t> series;
  for (const auto& line : lines_of(state.t("output.series"))) {
    auto f = split_tabs(line);
    if (f.size() != 2) damaged_mark("output.series");
    series[f[0]] = to_count(f[1], "output.series");
  }
  H5Output::Kept kept;
  kept.attribute_group = "/results";
  kept.attributes = lines_of(state.t("output.results"));
  kept.top_level = lines_of(state.t("output.top_level"));
  kept.root_attributes = lines_of(state.t("output.root_attributes"));
  const auto& progress = state.i("output.progress");
  const auto& extent = state.d("output.wall_extent");
  // (Five to seven entries in checkpoints written before the last snapshot's
  // digest, the last series row's step, the failure's step and the opening's
  // record were kept.)
  if (progress.size() < 5 || progress.size() > 9) damaged_mark("output.progress");
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
  // Written on after the checkpoint (by a run that may have died mid-write): put back as
  // it stood at the checkpoint, or at a later one, which reopen() cuts back to this.
  // (Checkpoints written before files were journalled have no id.)
  std::uint64_t file_id = 0;
  if (state.integers.count("output.file_id")) {
    const auto& id = state.i("output.file_id");
    if (id.size() != 1 || id[0] <= 0) damaged_mark("output.file_id");
    file_id = static_cast<std::uint64_t>(id[0]);
  }
  auto put_back = [&](const std::string& target) {
    if (file_id == 0) return;
    try {
      H5Output::restore(original, target, file_id);
    } catch (const std::exception& e) {
      throw std::runtime_error(fmt::format("restart: {}", e.what()));
    }
  };
  // (Under mpirun a rank other than 0 copies it into its scratch folder: io/rank_files.hpp.)
  const std::string here = writable_path(settings_.path);
  const bool in_place = std::filesystem::equivalent(original, here, ec);
  std::exception_ptr copy_failed;
  if (!in_place) {
    try {
      H5Output::forget_journal(here);  // of a file that was there
      std::filesystem::copy_file(original, here, std::filesystem::copy_options::overwrite_existing,
                                 ec);
      if (ec)
        throw std::runtime_error(fmt::format("restart: cannot copy {} to {}: {}", original,
                                             settings_.path, ec.message()));
      put_back(here);
    } catch (...) {
      copy_failed = std::current_exception();
    }
  }
  const bool all_copied = !copies_made || copies_made(copy_failed == nullptr);
  if (copy_failed) std::rethrow_exception(copy_failed);
  if (!all_copied)
    throw std::runtime_error(
        fmt::format("restart: another rank could not copy {} (its message says why)", original));
  if (in_place) put_back(original);
  try {
    file_ = H5Output::reopen(settings_.path, static_cast<std::size_t>(progress[0]), series, kept,
                             file_id);
  } catch (const OutputOfAnotherRun& e) {
    // A copy refused is no file of this run's: not left behind.
    if (!in_place) std::filesystem::remove(here, ec);
    throw std::runtime_error(fmt::format(
        "restart: {}; {} was written anew by another run since the checkpoint (a restart "
        "continues the first run's file: put that file back there)",
        e.what(), original));
  }
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
  failure_step_ = progress.size() > 7 ? progress[7] : -1;
  opening_due_ = progress.size() > 8 && progress[8] != 0;
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
