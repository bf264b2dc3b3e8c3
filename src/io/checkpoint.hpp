// Checkpoint files: a StateBlob (core/state.hpp) plus text attributes in an
// HDF5 file of its own. Written to "<path>.tmp" and renamed into place, so a
// crash while writing never leaves a half-written checkpoint where the last
// good one was.
//   /checkpoint                attrs format="granule-checkpoint-1", written, plus the caller's
//   /checkpoint/doubles/<key>  float64 arrays    /checkpoint/integers/<key> int64 arrays
//   /checkpoint/bytes/<key>    uint8 arrays      /checkpoint/texts/<key>    strings
// Keys may contain '.', never '/'.
#pragma once

#include <map>
#include <string>

#include "core/state.hpp"

namespace granule::io {

void write_checkpoint(const std::string& path, const StateBlob& state,
                      const std::map<std::string, std::string>& attributes = {});
StateBlob read_checkpoint(const std::string& path,
                          std::map<std::string, std::string>* attributes = nullptr);
// One text entry of a checkpoint, without reading the rest (throws naming the
// file when it is not a checkpoint or lacks the entry).
std::string read_checkpoint_text(const std::string& path, const std::string& key);

// The same layout as a group of an existing HDF5 file, e.g. a closed run output that
// keeps part of a state beside its snapshots (a prepared agglomerate's contact
// histories). add_state_group refuses a group that exists; read_state_group one
// that is missing or of another layout; both name the file.
void add_state_group(const std::string& path, const std::string& group, const StateBlob& state);
bool has_state_group(const std::string& path, const std::string& group);
StateBlob read_state_group(const std::string& path, const std::string& group);

}  // namespace granule::io
