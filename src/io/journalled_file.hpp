// HDF5 files that can be put back as they stood at a mark (a checkpoint).
//
// HDF5 updates a file's metadata in place (group indexes, dataset extents, the
// superblock last), so a process killed while writing can leave links to
// objects past the file's recorded end: a file nothing can continue. Files
// opened through this driver (POSIX reads and writes, as HDF5's sec2) keep,
// once a mark is set, a journal beside them, `<file>.journal`, of the bytes
// below the mark's end of file that a write or a truncation is about to
// change, each byte saved once a mark. restore_journal() writes them back and
// cuts the file to its length at the mark: the file as it stood, whatever
// moment the process died. Only bytes changed in place are saved (metadata and
// the last chunk of a growing series), so the journal stays small.
//
// Journal layout: the magic "granule-journal1", the file's 8-byte id, the
// 8-byte length at the mark; then records {8-byte offset, 8-byte size, bytes}.
// A record is written whole before the bytes it saves change, so a record cut
// short by a kill saved bytes that never changed and is ignored. A kill is
// covered, a power cut only where the system kept the order of the writes.
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <string>

namespace granule::io {

// Makes `fapl` open files through the driver: no journal until mark_journal, or,
// with `journal_from_open` (the file's id), a journal whose mark is the file as it
// was opened, before HDF5 writes anything. Every open of a file that may be open
// already in this process goes through it: HDF5 knows two opens for one file only
// when both have one driver.
void use_journalled_driver(hid_t fapl, std::uint64_t journal_from_open = 0);

// A new file's id, for its journal (random, positive as an int64, never 0).
std::uint64_t new_file_id();

// The journal's name for a file.
std::string journal_path(const std::string& file_path);

// For a file opened through the driver, just flushed (H5Fflush): a fresh
// journal whose mark is the file as it is now. Throws naming the file when the
// journal cannot be written.
void mark_journal(hid_t file, std::uint64_t file_id);

// For a file opened through the driver: disk set aside from its end of file to
// `bytes` past its end of allocation (fallocate, keeping the file's size), where
// HDF5's next writes land, and as much again in its journal when it has one (the
// bytes a write overwrites are saved there first), so that a write HDF5 starts
// cannot find the disk full half-way (which leaves its metadata out of step with
// the file). Returns 0 where reserved, the errno (ENOSPC, EDQUOT, EFBIG) where the
// disk lacks the room or the file would pass the process's size limit (ulimit -f:
// EFBIG), and -1 where the file system cannot reserve (or the file is
// another driver's): then only a check of the free space is left.
int reserve_space(hid_t file, std::uint64_t bytes);

// This process's file size limit (ulimit -f) in bytes; 0 where there is none.
std::uint64_t file_size_limit();

// After the file was closed cleanly: its journal is not needed.
void remove_journal(const std::string& file_path);

// Puts `target` back as the journal of `original` recorded it at its mark
// (target is original, or a copy of it). Returns false, changing nothing, when
// there is no journal (the file was closed cleanly); throws naming the files when
// the journal is another file's (another id), or it or the target cannot be read
// or written.
bool restore_journal(const std::string& original, const std::string& target, std::uint64_t file_id);

// A testing aid: with GRANULE_KILL_AT_JOURNALLED_WRITE=N in the environment,
// the process kills itself (SIGKILL) in the N-th write or truncation made under
// a journal, as a kill mid-write would: for odd N half of the file's bytes
// written, for even N half of the journal record that saves them.

}  // namespace granule::io
