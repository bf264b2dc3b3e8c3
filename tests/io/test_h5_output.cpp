// HDF5 output and input: exact round trips, series buffering, refusals of bad
// data, and that a flushed file is readable before its writer is closed.
#include <hdf5.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "io/h5_input.hpp"
#include "io/h5_output.hpp"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using granule::io::H5Output;
using granule::io::SnapshotView;

namespace {

// A unique file name in the temporary directory, removed when the test ends.
struct TempFile {
  std::string path;
  explicit TempFile(const std::string& tag) {
    static std::atomic<int> counter{0};
    std::random_device rd;
    path = (fs::temp_directory_path() / ("granule_io_" + tag + "_" + std::to_string(rd()) + "_" +
                                         std::to_string(counter++) + ".h5"))
               .string();
  }
  ~TempFile() {
    std::error_code ec;
    fs::remove(path, ec);
  }
};

// Owned particle arrays, and a view of them as the engine would pass.
struct Particles {
  int dimension = 3, spin_components = 3;
  std::vector<std::int64_t> id;
  std::vector<double> radius, position, velocity, spin;
  std::vector<std::int32_t> material;
  std::vector<std::uint8_t> fixed;
  std::vector<std::string> names;

  Particles(int dim, std::size_t n) : dimension(dim), spin_components(dim == 2 ? 1 : 3) {
    std::mt19937_64 rng(1234 + dim);
    std::uniform_real_distribution<double> u(-1, 1);
    for (std::size_t i = 0; i < n; ++i) {
      id.push_back(static_cast<std::int64_t>(i) * 1000003 + (std::int64_t{1} << 40));
      radius.push_back(1e-6 * (1 + std::abs(u(rng))));
      for (int k = 0; k < dim; ++k) {
        position.push_back(u(rng) * 1e-3);
        velocity.push_back(u(rng) * 3);
      }
      for (int k = 0; k < spin_components; ++k) spin.push_back(u(rng) * 1e4);
      material.push_back(static_cast<std::int32_t>(i % 2));
      fixed.push_back(i % 5 == 0 ? 1 : 0);
    }
    // Values whose bits a lossy path would change.
    if (n >= 3) {
      position[0] = -0.0;
      velocity[1] = std::numeric_limits<double>::denorm_min();
      spin[2] = std::numeric_limits<double>::max();
      radius[2] = 0.1;  // not exactly representable
    }
    names = {"glass", "α-alumina"};  // UTF-8 must survive
  }

  SnapshotView view(std::int64_t step, double time) const {
    SnapshotView v;
    v.step = step;
    v.time = time;
    v.dimension = dimension;
    v.spin_components = spin_components;
    v.count = id.size();
    v.id = id.data();
    v.radius = radius.data();
    v.position = position.data();
    v.velocity = velocity.data();
    v.spin = spin.data();
    v.material = material.data();
    v.fixed = fixed.data();
    v.material_names = names;
    return v;
  }
};

// Bitwise equality: 0.0 == -0.0 would pass a lossy round trip.
bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

void require_round_trip(const Particles& p, const granule::io::SnapshotData& s, std::int64_t step,
                        double time) {
  CHECK(s.step == step);
  CHECK(s.time == time);
  CHECK(s.dimension == p.dimension);
  CHECK(s.spin_components == p.spin_components);
  CHECK(s.id == p.id);
  CHECK(same_bits(s.radius, p.radius));
  CHECK(same_bits(s.position, p.position));
  CHECK(same_bits(s.velocity, p.velocity));
  CHECK(same_bits(s.spin, p.spin));
  CHECK(s.material == p.material);
  CHECK(s.fixed == p.fixed);
  CHECK(s.material_names == p.names);
}

// Reads a scalar string attribute with the raw C API, to check what h5py will see.
std::string root_string_attribute(const std::string& path, const char* name) {
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(f >= 0);
  hid_t a = H5Aopen_by_name(f, "/", name, H5P_DEFAULT, H5P_DEFAULT);
  REQUIRE(a >= 0);
  hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);  // HDF5 will not convert UTF-8 text to ASCII
  char* value = nullptr;
  REQUIRE(H5Aread(a, t, &value) >= 0);
  std::string out = value ? value : "";
  H5free_memory(value);
  H5Tclose(t);
  H5Aclose(a);
  H5Fclose(f);
  return out;
}

}  // namespace

TEST_CASE("io: 3D snapshot round-trips exactly", "[io]") {
  TempFile tmp("snap3d");
  Particles p(3, 257);
  {
    H5Output out(tmp.path);
    CHECK(out.path() == tmp.path);
    CHECK(out.write_snapshot(p.view(41, 1.25e-7)) == "/snapshots/000000");
    CHECK(out.snapshot_count() == 1);
  }
  CHECK(granule::io::count_snapshots(tmp.path) == 1);
  require_round_trip(p, granule::io::read_snapshot(tmp.path), 41, 1.25e-7);
  CHECK(root_string_attribute(tmp.path, "format") == "granule-1");
  CHECK(root_string_attribute(tmp.path, "created").size() == 20);  // 2024-01-31T12:00:00Z
}

TEST_CASE("io: 2D snapshots round-trip exactly and are indexed in order", "[io]") {
  TempFile tmp("snap2d");
  Particles first(2, 100), second(2, 37);
  second.position[5] = 42.0;
  {
    H5Output out(tmp.path);
    CHECK(out.write_snapshot(first.view(0, 0.0)) == "/snapshots/000000");
    CHECK(out.write_snapshot(second.view(500, 1e-3)) == "/snapshots/000001");
    Particles none(2, 0);  // a failure snapshot may keep no particle at all
    CHECK(out.write_snapshot(none.view(501, 1.1e-3)) == "/snapshots/000002");
  }
  CHECK(granule::io::count_snapshots(tmp.path) == 3);
  require_round_trip(first, granule::io::read_snapshot(tmp.path, 0), 0, 0.0);
  require_round_trip(second, granule::io::read_snapshot(tmp.path, 1), 500, 1e-3);
  require_round_trip(second, granule::io::read_snapshot(tmp.path, -2), 500, 1e-3);
  auto empty = granule::io::read_snapshot(tmp.path);
  CHECK(empty.step == 501);
  CHECK(empty.id.empty());
  CHECK(empty.dimension == 2);
  CHECK(empty.spin_components == 1);
  REQUIRE_THROWS_WITH(granule::io::read_snapshot(tmp.path, 3),
                      Contains(tmp.path) && Contains("snapshot 3"));
  REQUIRE_THROWS_WITH(granule::io::read_snapshot(tmp.path, -4), Contains("snapshot -4"));
}

TEST_CASE("io: a series of 3000 rows reads back whole", "[io]") {
  TempFile tmp("series");
  const std::size_t rows = 3000;
  // The values written, kept: computed again for the check, the compiler may
  // round them differently (a fused multiply-add in one place, not the other).
  std::vector<double> written_energy(rows), written_count(rows);
  for (std::size_t r = 0; r < rows; ++r) {
    written_energy[r] = std::sin(0.001 * r + 1) * 10.0;
    written_count[r] = std::sin(0.001 * r + 2) * 100.0;
  }
  {
    H5Output out(tmp.path);
    out.series_declare("/series", {"time", "energy", "count"}, {"s", "J", "-"});
    out.series_declare("/series", {"time", "energy", "count"});  // same columns: no-op
    for (std::size_t r = 0; r < rows; ++r)
      out.series_append("/series", {1e-6 * r, written_energy[r], written_count[r]});
    // No flush: destruction must write the rows still buffered.
  }
  auto time = granule::io::read_series_column(tmp.path, "/series", "time");
  auto energy = granule::io::read_series_column(tmp.path, "/series", "energy");
  auto count = granule::io::read_series_column(tmp.path, "series/", "count");
  REQUIRE(time.size() == rows);
  REQUIRE(energy.size() == rows);
  REQUIRE(count.size() == rows);
  for (std::size_t r = 0; r < rows; ++r) {
    REQUIRE(time[r] == 1e-6 * r);
    REQUIRE(energy[r] == written_energy[r]);
    REQUIRE(count[r] == written_count[r]);
  }
  REQUIRE_THROWS_WITH(granule::io::read_series_column(tmp.path, "/series", "power"),
                      Contains("/series/power") && Contains(tmp.path) && Contains("energy"));
}

TEST_CASE("io: a series cannot be redeclared with other columns", "[io]") {
  TempFile tmp("redeclare");
  H5Output out(tmp.path);
  out.series_declare("/impact", {"time", "overlap"});
  REQUIRE_THROWS_WITH(out.series_declare("/impact", {"time", "overlap", "force"}),
                      Contains("/impact") && Contains(tmp.path));
  REQUIRE_THROWS_WITH(out.series_declare("/impact", {"overlap", "time"}), Contains("/impact"));
  REQUIRE_THROWS_WITH(out.series_append("/impact", {1.0}),
                      Contains("/impact") && Contains("2 columns"));
  REQUIRE_THROWS_WITH(out.series_append("/other", {1.0}), Contains("/other"));
  REQUIRE_THROWS(out.series_declare("/bad", {"a", "a"}));
  REQUIRE_THROWS(out.series_declare("/bad", {"a/b"}));
  REQUIRE_THROWS(out.series_declare("/bad", {"a", "b"}, {"m"}));
  out.series_append("/impact", {0.0, 1e-9});
  out.flush();
  CHECK(granule::io::read_series_column(tmp.path, "/impact", "overlap") ==
        std::vector<double>{1e-9});
}

TEST_CASE("io: non-finite values are refused and name what was wrong", "[io]") {
  TempFile tmp("nan");
  H5Output out(tmp.path);
  Particles p(3, 50);
  p.velocity[3 * 7 + 1] = std::numeric_limits<double>::quiet_NaN();
  REQUIRE_THROWS_WITH(out.write_snapshot(p.view(10, 1e-3)), Contains(std::to_string(p.id[7])) &&
                                                                Contains("velocity") &&
                                                                Contains(tmp.path));
  CHECK(out.snapshot_count() == 0);
  p.velocity[3 * 7 + 1] = 0;
  p.spin[3 * 9] = -std::numeric_limits<double>::infinity();
  REQUIRE_THROWS_WITH(out.write_snapshot(p.view(10, 1e-3)),
                      Contains(std::to_string(p.id[9])) && Contains("spin"));
  p.spin[3 * 9] = 0;
  p.position[3 * 2] = std::numeric_limits<double>::quiet_NaN();
  REQUIRE_THROWS_WITH(out.write_snapshot(p.view(10, 1e-3)),
                      Contains(std::to_string(p.id[2])) && Contains("position"));
  p.position[3 * 2] = 0;
  // Nothing of the refused snapshots was written: the next one takes index 0.
  CHECK(out.write_snapshot(p.view(10, 1e-3)) == "/snapshots/000000");

  out.series_declare("/series", {"time", "energy"});
  out.series_append("/series", {0.0, 1.0});
  REQUIRE_THROWS_WITH(out.series_append("/series", {1.0, std::nan("")}),
                      Contains("energy") && Contains(tmp.path));
  REQUIRE_THROWS_WITH(
      out.write_attribute("/scene/parameters", "rpm", std::numeric_limits<double>::infinity()),
      Contains("rpm"));
  REQUIRE_THROWS_WITH(out.write_attribute("/walls/drum", "center", std::vector<double>{0, NAN}),
                      Contains("center"));
  out.flush();
  CHECK(granule::io::read_series_column(tmp.path, "/series", "energy") == std::vector<double>{1.0});
  CHECK(granule::io::count_snapshots(tmp.path) == 1);
}

TEST_CASE("io: an unwritable or missing path throws naming it", "[io]") {
  const std::string bad = "/nonexistent_dir/x.h5";
  REQUIRE_THROWS_WITH(H5Output(bad), Contains(bad));
  REQUIRE_THROWS_WITH(granule::io::count_snapshots(bad), Contains(bad));
  REQUIRE_THROWS_WITH(granule::io::read_text(bad, "/scene/source"), Contains(bad));
}

TEST_CASE("io: text and attributes are written and replaced", "[io]") {
  TempFile tmp("text");
  const std::string source = "-- scene\nlocal rpm = 2000 -- ω in rpm\n";
  {
    H5Output out(tmp.path);
    out.write_text("/scene/source", "old");
    out.write_text("/scene/source", source);
    out.write_text("/scene/empty", "");
    out.write_attribute("/scene/parameters", "rpm", 2000.0);
    out.write_attribute("/scene/parameters", "rpm", 3000.0);
    out.write_attribute("/scene/parameters", "seed", std::int64_t{7});
    out.write_attribute("/scene/parameters", "name", std::string("demo"));
    out.write_attribute("/walls/drum", "center", std::vector<double>{0.0, 0.0});
    out.write_attribute("/", "program", std::string("granule"));
    out.series_declare("/series", {"time"}, {"s"});
    out.write_attribute("/series/time", "note", std::string("attributes on datasets work"));
    REQUIRE_THROWS_WITH(out.write_text("/scene/bad", std::string("a\0b", 3)),
                        Contains("/scene/bad"));
  }
  CHECK(granule::io::read_text(tmp.path, "/scene/source") == source);
  CHECK(granule::io::read_text(tmp.path, "/scene/empty").empty());
  CHECK(root_string_attribute(tmp.path, "program") == "granule");
  REQUIRE_THROWS_WITH(granule::io::read_text(tmp.path, "/scene/missing"),
                      Contains("/scene/missing") && Contains(tmp.path));
}

TEST_CASE("io: a flushed file is readable while its writer is still open", "[io]") {
  TempFile tmp("live"), crash_copy("crashcopy");
  Particles p(3, 20);
  H5Output out(tmp.path);
  out.write_text("/scene/source", "print('hi')");
  out.series_declare("/series", {"time", "energy"});
  for (int r = 0; r < 10; ++r) out.series_append("/series", {r * 1e-3, r * 2.0});
  out.write_snapshot(p.view(3, 3e-3));
  for (int r = 10; r < 15; ++r) out.series_append("/series", {r * 1e-3, r * 2.0});
  out.flush();

  // What a crash right now would leave on disk: the bytes of the file, read by a fresh
  // open of a different file, so nothing comes from the writer's caches.
  fs::copy_file(tmp.path, crash_copy.path, fs::copy_options::overwrite_existing);
  CHECK(granule::io::count_snapshots(crash_copy.path) == 1);
  require_round_trip(p, granule::io::read_snapshot(crash_copy.path), 3, 3e-3);
  CHECK(granule::io::read_series_column(crash_copy.path, "/series", "energy").size() == 15);
  CHECK(granule::io::read_text(crash_copy.path, "/scene/source") == "print('hi')");

  // And the live file itself, read-only, while this process holds it open for writing.
  CHECK(granule::io::count_snapshots(tmp.path) == 1);
  CHECK(granule::io::read_series_column(tmp.path, "/series", "time").size() == 15);
  require_round_trip(p, granule::io::read_snapshot(tmp.path, 0), 3, 3e-3);

  // The writer goes on working after being read.
  out.series_append("/series", {0.015, 30.0});
  out.flush();
  CHECK(granule::io::read_series_column(tmp.path, "/series", "time").size() == 16);
}

TEST_CASE("io: buffered series rows reach the disk within about half a second", "[io]") {
  TempFile tmp("batch"), crash_copy("batchcopy");
  H5Output out(tmp.path);
  out.series_declare("/series", {"time"});
  out.series_append("/series", {0.0});
  std::this_thread::sleep_for(std::chrono::milliseconds(600));
  out.series_append("/series", {1.0});  // over 0.5 s since the last write: both go to disk
  out.series_append("/series", {2.0});  // normally still buffered
  fs::copy_file(tmp.path, crash_copy.path, fs::copy_options::overwrite_existing);
  auto on_disk = granule::io::read_series_column(crash_copy.path, "/series", "time");
  // Only a stall of 0.5 s between the last two appends would have written the third row.
  REQUIRE(on_disk.size() >= 2);
  CHECK(on_disk[0] == 0.0);
  CHECK(on_disk[1] == 1.0);
}

TEST_CASE("io: no HDF5 handle outlives its writer or a failed call", "[io]") {
  TempFile tmp("handles");
  {
    H5Output out(tmp.path);
    Particles p(2, 10);
    out.write_snapshot(p.view(1, 1e-6));
    p.spin[4] = std::nan("");
    CHECK_THROWS(out.write_snapshot(p.view(2, 2e-6)));
    out.series_declare("/series", {"time"});
    out.series_append("/series", {1.0});
    CHECK_THROWS(out.series_declare("/series/time/deeper", {"x"}));
    CHECK_THROWS(out.write_text("/series", "a group is not replaced by text"));
    CHECK_THROWS(out.write_attribute("/series/time/x", "a", 1.0));
    out.flush();
    CHECK_THROWS(granule::io::read_snapshot(tmp.path, 7));
    CHECK_THROWS(granule::io::read_text(tmp.path, "/series"));
    CHECK(granule::io::read_snapshot(tmp.path).step == 1);
  }
  CHECK(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL) == 0);
}
