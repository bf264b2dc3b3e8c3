// Under mpirun every rank runs the scene script, so every rank's writers would
// write the same files. Rank 0 writes them where the script says; each other
// rank writes into a scratch folder of its own, removed when it exits. The
// writers' code stays the same on every rank (the same calls, the same
// errors), and no two processes ever write one file.
#pragma once

#include <string>

namespace granule::io {

// From now on this process writes its files into `folder` (created; removed by
// remove_scratch()). An empty folder: the files go where they are named.
void write_files_into(const std::string& folder);
void remove_scratch();

// Removes the folders under `parent` named `prefix` + "<rank>-<pid>" whose
// process is gone from this machine: the scratch of a rank that was killed
// before it could remove its own (mpirun's SIGKILL after another rank's abort).
void remove_stale_scratch(const std::string& parent, const std::string& prefix);

// Where this process writes the file named `path`: `path` itself, or its
// scratch copy; with `keep_content`, a file that exists is copied there first
// (a file opened to be continued).
std::string writable_path(const std::string& path, bool keep_content = false);

// A fresh temporary file's name (the file made empty, as os.tmpname makes it):
// in the scratch folder when there is one, so that what a rank's scene makes
// there goes with the folder; else "" (the caller makes its own).
std::string scratch_temporary();

// Where this process reads the file named `path`: its scratch copy when this
// process wrote one (a scene that writes a file and then reads it, such as a
// mesh it generates), else `path` itself.
std::string readable_path(const std::string& path);

}  // namespace granule::io
