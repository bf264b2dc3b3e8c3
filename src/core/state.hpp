// A simulation's complete state as named plain arrays: what a checkpoint holds.
// The engine fills and reads it (simulation_state.cpp) without knowing the file
// format; src/io/checkpoint.cpp writes it to HDF5 and back. Arrays are stored
// exactly (doubles as doubles, histories as raw bytes), so a run continued from
// a checkpoint is bit-identical to one that never stopped.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace granule {

struct StateBlob {
  std::map<std::string, std::vector<double>> doubles;
  std::map<std::string, std::vector<std::int64_t>> integers;
  std::map<std::string, std::vector<std::uint8_t>> bytes;
  std::map<std::string, std::string> texts;

  // Lookups that throw a clear error when a checkpoint lacks an entry.
  const std::vector<double>& d(const std::string& key) const;
  const std::vector<std::int64_t>& i(const std::string& key) const;
  const std::vector<std::uint8_t>& b(const std::string& key) const;
  const std::string& t(const std::string& key) const;
  std::vector<std::string> lines(const std::string& key) const;  // t(key), line by line
  bool has(const std::string& key) const {
    return doubles.count(key) || integers.count(key) || bytes.count(key) || texts.count(key);
  }
};

}  // namespace granule
