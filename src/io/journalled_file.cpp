// The journalled HDF5 file driver (journalled_file.hpp): POSIX I/O through
// HDF5's virtual file layer, with the undo journal of a mark.
#include "io/journalled_file.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <random>
#include <stdexcept>
#include <vector>

namespace granule::io {

namespace {

constexpr char kMagic[16] = {'g', 'r', 'a', 'n', 'u', 'l', 'e', '-',
                             'j', 'o', 'u', 'r', 'n', 'a', 'l', '1'};
constexpr std::size_t kHeaderBytes = sizeof kMagic + 16;
constexpr std::uint64_t kPiece = 1 << 20;  // the most bytes a record holds, or a read takes

// The largest address a file may have (an off_t's).
constexpr haddr_t kMaxAddress = (haddr_t(1) << (8 * sizeof(off_t) - 1)) - 1;

bool write_all(int fd, const void* data, std::size_t size, off_t at = -1) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t n = at < 0 ? ::write(fd, p, size) : ::pwrite(fd, p, size, at);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = EIO;
      return false;
    }
    p += n;
    size -= static_cast<std::size_t>(n);
    if (at >= 0) at += n;
  }
  return true;
}

// Reads up to `size` bytes; fewer only at the end of the file.
bool read_all(int fd, void* data, std::size_t size, off_t at, std::size_t& got) {
  char* p = static_cast<char*>(data);
  got = 0;
  while (got < size) {
    const ssize_t n = ::pread(fd, p + got, size - got, at + static_cast<off_t>(got));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return false;
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  return true;
}

void put_u64(unsigned char* p, std::uint64_t v) {
  for (int k = 0; k < 8; ++k) p[k] = static_cast<unsigned char>(v >> (8 * k));
}
std::uint64_t get_u64(const unsigned char* p) {
  std::uint64_t v = 0;
  for (int k = 0; k < 8; ++k) v |= std::uint64_t(p[k]) << (8 * k);
  return v;
}

// The testing aid (journalled_file.hpp): which change under a journal kills the
// process, and how. Odd N: half of the file's write is done; even N: half of the
// journal record that change needs (or of the file's write when it needs none).
struct KillPoint {
  long at = 0, seen = 0;
  bool tear_record = false;
  KillPoint() {
    const char* text = std::getenv("GRANULE_KILL_AT_JOURNALLED_WRITE");
    at = text ? std::strtol(text, nullptr, 10) : 0;
  }
  // Counts a change about to be made; true when it is the one to die in.
  bool due() {
    if (at <= 0 || ++seen != at) return false;
    tear_record = at % 2 == 0;
    return true;
  }
};
KillPoint& kill_point() {
  static KillPoint k;
  return k;
}

// The file access list's setting: a journal started as the file opens (its id), before
// HDF5 writes anything to it; 0: none until mark_journal.
struct DriverInfo {
  std::uint64_t journal_from_open = 0;
};

// One open file. `pub` first: HDF5 hands back the H5FD_t it was given.
struct State {
  int fd = -1;
  std::string path;
  haddr_t eoa = 0, eof = 0;
  dev_t device = 0;
  ino_t inode = 0;
  // The journal of the current mark (fd -1: no mark yet).
  int journal = -1;
  std::uint64_t mark_end = 0;
  std::map<std::uint64_t, std::uint64_t> saved;  // start -> end, disjoint, of [0, mark_end)
  bool failed = false;                           // a journal write failed: no more writes
  std::uint64_t reserved_to = 0;                 // disk set aside up to here (reserve_space)
};
struct File {
  H5FD_t pub;
  State* state;
};
State& state_of(H5FD_t* f) {
  return *reinterpret_cast<File*>(f)->state;
}
const State& state_of(const H5FD_t* f) {
  return *reinterpret_cast<const File*>(f)->state;
}

// `error`: errno, read by the caller before anything else can change it.
void push_error(hid_t minor, const std::string& what, int error) {
  // Worded as HDF5's sec2 driver words it, so that h5_handle.cpp finds the system's message.
  H5Epush2(H5E_DEFAULT, __FILE__, "journalled_file", __LINE__, H5E_ERR_CLS, H5E_VFL, minor, "%s",
           fmt::format("{}: error message = '{}', errno = {}", what, std::strerror(error), error)
               .c_str());
}

// Saves the bytes [from, to) of the file (clipped to the mark) not yet saved this mark.
bool save(State& s, std::uint64_t from, std::uint64_t to) {
  if (s.journal < 0 || s.failed) return !s.failed;
  to = std::min<std::uint64_t>(to, s.mark_end);
  std::uint64_t at = from;
  std::vector<unsigned char> record;
  while (at < to) {
    // The saved interval that holds `at`, or the next one.
    auto next = s.saved.upper_bound(at);
    if (next != s.saved.begin()) {
      auto held = std::prev(next);
      if (held->second > at) {
        at = held->second;
        continue;
      }
    }
    const std::uint64_t end =
        std::min(at + kPiece, next == s.saved.end() ? to : std::min(to, next->first));
    const std::size_t size = static_cast<std::size_t>(end - at);
    record.assign(16 + size, 0);
    put_u64(record.data(), at);
    put_u64(record.data() + 8, size);
    std::size_t got = 0;
    // Bytes past the physical end read as zeros, as HDF5 reads them.
    const bool read = read_all(s.fd, record.data() + 16, size, static_cast<off_t>(at), got);
    if (read && kill_point().tear_record) {
      write_all(s.journal, record.data(), 16 + size / 2);
      ::raise(SIGKILL);
    }
    if (!read || !write_all(s.journal, record.data(), record.size())) {
      const int error = errno;
      s.failed = true;
      push_error(H5E_WRITEERROR, fmt::format("journal write failed: {}", journal_path(s.path)),
                 error);
      return false;
    }
    // Merge with the intervals it touches.
    std::uint64_t lo = at, hi = end;
    auto it = s.saved.lower_bound(lo);
    if (it != s.saved.begin() && std::prev(it)->second == lo) {
      --it;
      lo = it->first;
      it = s.saved.erase(it);
    }
    if (it != s.saved.end() && it->first == hi) {
      hi = it->second;
      s.saved.erase(it);
    }
    s.saved[lo] = hi;
    at = end;
  }
  return true;
}

// One writer a file: an open file description lock (fcntl F_OFD_SETLK, whole
// file), which a second writer, in another process or this one, cannot take,
// and which goes with the descriptor (and with a killed process). HDF5's own
// lock (flock) is off for our files, so that readers such as h5py can open a
// running simulation's output; the two kinds of lock do not meet. False only
// when another holds it (EAGAIN, EACCES): a file system without such locks (some
// network ones) writes unlocked, as HDF5 does with its own lock off.
bool lock_for_writing(int fd) {
  struct flock lock {};
  lock.l_type = F_WRLCK;
  lock.l_whence = SEEK_SET;
  lock.l_start = 0;
  lock.l_len = 0;
  return ::fcntl(fd, F_OFD_SETLK, &lock) == 0 || (errno != EAGAIN && errno != EACCES);
}

// A fresh journal for `s` as it is now: written whole beside the file, then renamed
// over the last one, so that a journal on the disk is always a whole one.
void start_journal(State& s, std::uint64_t file_id) {
  const std::string path = journal_path(s.path), tmp = path + ".tmp";
  auto fail = [&](const std::string& what, int error) {
    throw std::runtime_error(fmt::format("cannot {} the journal {}: error message = '{}'", what,
                                         tmp, std::strerror(error)));
  };
  // The file's bytes on the disk before the journal that undoes later writes counts.
  if (::fdatasync(s.fd) != 0) fail("sync the file before", errno);
  unsigned char header[kHeaderBytes];
  std::memcpy(header, kMagic, sizeof kMagic);
  put_u64(header + sizeof kMagic, file_id);
  put_u64(header + sizeof kMagic + 8, s.eof);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail("create", errno);
  if (!write_all(fd, header, sizeof header) || ::fdatasync(fd) != 0 ||
      ::rename(tmp.c_str(), path.c_str()) != 0) {
    const int error = errno;
    ::close(fd);
    ::unlink(tmp.c_str());
    fail("write", error);
  }
  if (s.journal >= 0) ::close(s.journal);
  s.journal = fd;
  s.mark_end = s.eof;
  s.saved.clear();
  s.failed = false;
}

H5FD_t* driver_open(const char* name, unsigned flags, hid_t fapl, haddr_t maxaddr) {
  if (!name || !*name || maxaddr == 0 || maxaddr > kMaxAddress) return nullptr;
  int o = (flags & H5F_ACC_RDWR) ? O_RDWR : O_RDONLY;
  if (flags & H5F_ACC_CREAT) o |= O_CREAT;
  if (flags & H5F_ACC_EXCL) o |= O_EXCL;
  // (Truncated only once it is ours: a file another process writes is left whole.)
  const int fd = ::open(name, o | O_CLOEXEC, 0666);
  if (fd < 0) {
    const int error = errno;
    push_error(H5E_CANTOPENFILE, fmt::format("unable to open file: name = '{}'", name), error);
    return nullptr;
  }
  if ((flags & H5F_ACC_RDWR) &&
      (!lock_for_writing(fd) || ((flags & H5F_ACC_TRUNC) && ::ftruncate(fd, 0) != 0))) {
    const int error = errno;
    push_error(H5E_CANTOPENFILE,
               error == EAGAIN || error == EACCES
                   ? fmt::format("'{}' is open for writing elsewhere (another process?)", name)
                   : fmt::format("unable to lock or truncate file: name = '{}'", name),
               error);
    ::close(fd);
    return nullptr;
  }
  struct stat st {};
  if (fstat(fd, &st) != 0) {
    const int error = errno;
    push_error(H5E_CANTOPENFILE, fmt::format("unable to fstat file: name = '{}'", name), error);
    ::close(fd);
    return nullptr;
  }
  auto* f = static_cast<File*>(std::calloc(1, sizeof(File)));
  if (!f) {
    ::close(fd);
    return nullptr;
  }
  f->state = new State();
  f->state->fd = fd;
  f->state->path = name;
  f->state->eof = static_cast<haddr_t>(st.st_size);
  f->state->device = st.st_dev;
  f->state->inode = st.st_ino;
  const auto* info = static_cast<const DriverInfo*>(H5Pget_driver_info(fapl));
  if (info && info->journal_from_open != 0) {
    try {
      start_journal(*f->state, info->journal_from_open);
    } catch (const std::exception& e) {
      H5Epush2(H5E_DEFAULT, __FILE__, "journalled_file", __LINE__, H5E_ERR_CLS, H5E_VFL,
               H5E_CANTOPENFILE, "%s", e.what());
      ::close(fd);
      delete f->state;
      std::free(f);
      return nullptr;
    }
  }
  return &f->pub;
}

herr_t driver_close(H5FD_t* file) {
  State& s = state_of(file);
  int status = 0;
  if (s.journal >= 0) ::close(s.journal);
  // The room set aside and not written goes back to the disk (a file's length is kept).
  if (s.reserved_to > 0) (void)::ftruncate(s.fd, static_cast<off_t>(s.eof));
  if (::close(s.fd) != 0) {
    const int error = errno;
    push_error(H5E_CANTCLOSEFILE, "unable to close file", error);
    status = -1;
  }
  delete &s;
  std::free(reinterpret_cast<File*>(file));
  return status;
}

int driver_cmp(const H5FD_t* a, const H5FD_t* b) {
  const State &x = state_of(a), &y = state_of(b);
  if (x.device != y.device) return x.device < y.device ? -1 : 1;
  if (x.inode != y.inode) return x.inode < y.inode ? -1 : 1;
  return 0;
}

herr_t driver_query(const H5FD_t*, unsigned long* flags) {
  // sec2's features, but its handle is not a POSIX descriptor (mark_journal finds the State).
  if (flags)
    *flags = H5FD_FEAT_AGGREGATE_METADATA | H5FD_FEAT_ACCUMULATE_METADATA | H5FD_FEAT_DATA_SIEVE |
             H5FD_FEAT_AGGREGATE_SMALLDATA | H5FD_FEAT_DEFAULT_VFD_COMPATIBLE;
  return 0;
}

haddr_t driver_get_eoa(const H5FD_t* file, H5FD_mem_t) {
  return state_of(file).eoa;
}
herr_t driver_set_eoa(H5FD_t* file, H5FD_mem_t, haddr_t addr) {
  state_of(file).eoa = addr;
  return 0;
}
haddr_t driver_get_eof(const H5FD_t* file, H5FD_mem_t) {
  return state_of(file).eof;
}
herr_t driver_get_handle(H5FD_t* file, hid_t, void** handle) {
  if (!handle) return -1;
  *handle = &state_of(file);
  return 0;
}

herr_t driver_read(H5FD_t* file, H5FD_mem_t, hid_t, haddr_t addr, size_t size, void* buffer) {
  State& s = state_of(file);
  if (addr == HADDR_UNDEF || addr + size > s.eoa) {
    push_error(H5E_READERROR, fmt::format("addr overflow, addr = {}, size = {}", addr, size), 0);
    return -1;
  }
  std::size_t got = 0;
  if (!read_all(s.fd, buffer, size, static_cast<off_t>(addr), got)) {
    const int error = errno;
    push_error(H5E_READERROR, "file read failed", error);
    return -1;
  }
  std::memset(static_cast<char*>(buffer) + got, 0, size - got);  // past the end: zeros
  return 0;
}

herr_t driver_write(H5FD_t* file, H5FD_mem_t, hid_t, haddr_t addr, size_t size,
                    const void* buffer) {
  State& s = state_of(file);
  if (addr == HADDR_UNDEF || addr + size > s.eoa) {
    push_error(H5E_WRITEERROR, fmt::format("addr overflow, addr = {}, size = {}", addr, size), 0);
    return -1;
  }
  const bool die = s.journal >= 0 && kill_point().due();
  if (!save(s, addr, addr + size)) return -1;
  if (die) {
    write_all(s.fd, buffer, size / 2, static_cast<off_t>(addr));
    ::raise(SIGKILL);
  }
  if (!write_all(s.fd, buffer, size, static_cast<off_t>(addr))) {
    const int error = errno;
    push_error(H5E_WRITEERROR, "file write failed", error);
    return -1;
  }
  s.eof = std::max<haddr_t>(s.eof, addr + size);
  return 0;
}

herr_t driver_truncate(H5FD_t* file, hid_t, hbool_t) {
  State& s = state_of(file);
  if (s.eoa == s.eof) return 0;
  const bool die = s.journal >= 0 && kill_point().due();
  if (s.eoa < s.eof && !save(s, s.eoa, s.eof)) return -1;
  if (die) ::raise(SIGKILL);  // (a truncation is whole or not done)
  if (::ftruncate(s.fd, static_cast<off_t>(s.eoa)) != 0) {
    const int error = errno;
    push_error(H5E_SEEKERROR, "unable to extend file properly", error);
    return -1;
  }
  // A cut frees what was set aside past the new end; a growth keeps it (freed at close).
  if (s.eoa < s.eof) s.reserved_to = std::min<std::uint64_t>(s.reserved_to, s.eoa);
  s.eof = s.eoa;
  return 0;
}

// Locks: none (the outputs are opened with HDF5's file locking off; see h5_output.cpp).
herr_t driver_lock(H5FD_t*, hbool_t) {
  return 0;
}
herr_t driver_unlock(H5FD_t*) {
  return 0;
}

H5FD_class_t make_class() {
  H5FD_class_t c{};
  c.name = "granule_journalled";
  c.maxaddr = kMaxAddress;
  c.fc_degree = H5F_CLOSE_WEAK;
  c.fapl_size = sizeof(DriverInfo);  // copied and freed by HDF5 as plain bytes
  c.open = driver_open;
  c.close = driver_close;
  c.cmp = driver_cmp;
  c.query = driver_query;
  c.get_eoa = driver_get_eoa;
  c.set_eoa = driver_set_eoa;
  c.get_eof = driver_get_eof;
  c.get_handle = driver_get_handle;
  c.read = driver_read;
  c.write = driver_write;
  c.truncate = driver_truncate;
  c.lock = driver_lock;
  c.unlock = driver_unlock;
  const H5FD_mem_t map[] = H5FD_FLMAP_DICHOTOMY;
  std::copy(std::begin(map), std::end(map), std::begin(c.fl_map));
  return c;
}

hid_t driver_id() {
  static const H5FD_class_t cls = make_class();
  static hid_t id = H5FDregister(&cls);
  if (id < 0 || H5Iis_valid(id) <= 0) id = H5FDregister(&cls);  // HDF5 closed and reopened
  if (id < 0) throw std::runtime_error("cannot register the journalled HDF5 file driver");
  return id;
}

}  // namespace

void use_journalled_driver(hid_t fapl, std::uint64_t journal_from_open) {
  const DriverInfo info{journal_from_open};
  if (H5Pset_driver(fapl, driver_id(), &info) < 0)
    throw std::runtime_error("cannot select the journalled HDF5 file driver");
}

std::uint64_t new_file_id() {
  std::random_device device;
  std::uint64_t id = (std::uint64_t(device()) << 32) ^ device() ^
                     std::uint64_t(std::chrono::steady_clock::now().time_since_epoch().count());
  id &= (std::uint64_t(1) << 62) - 1;
  return id == 0 ? 1 : id;
}

std::string journal_path(const std::string& file_path) {
  return file_path + ".journal";
}

namespace {
// Only a file of this driver has a State behind its handle (else null).
State* state_of_file(hid_t file) {
  hid_t driver = -1;
  if (const hid_t fapl = H5Fget_access_plist(file); fapl >= 0) {
    driver = H5Pget_driver(fapl);
    H5Pclose(fapl);
  }
  void* handle = nullptr;
  if (driver < 0 || driver != driver_id() ||
      H5Fget_vfd_handle(file, H5P_FILE_ACCESS_DEFAULT, &handle) < 0 || !handle)
    return nullptr;
  return static_cast<State*>(handle);
}
}  // namespace

void mark_journal(hid_t file, std::uint64_t file_id) {
  State* s = state_of_file(file);
  if (!s)
    throw std::logic_error("mark_journal: the file was not opened through the journalled driver");
  start_journal(*s, file_id);
}

std::uint64_t file_size_limit() {
  struct rlimit limit {};
  if (::getrlimit(RLIMIT_FSIZE, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return 0;
  return static_cast<std::uint64_t>(limit.rlim_cur);
}

int reserve_space(hid_t file, std::uint64_t bytes) {
  State* const found = state_of_file(file);
  if (!found) return -1;
  State& s = *found;
  // From the end of file: space HDF5 allocated but has not written yet is a hole too.
  const std::uint64_t from = s.eof, to = std::max<std::uint64_t>(s.eoa, s.eof) + bytes;
  auto reserve = [](int fd, std::uint64_t at, std::uint64_t size) {
    // fallocate is not held to the process's file size limit (ulimit -f); the
    // writes are, so a write past it would fail half-way (or raise SIGXFSZ).
    if (const std::uint64_t limit = file_size_limit(); limit > 0 && at + size > limit) return EFBIG;
    if (::fallocate(fd, FALLOC_FL_KEEP_SIZE, static_cast<off_t>(at), static_cast<off_t>(size)) == 0)
      return 0;
    return errno == ENOSPC || errno == EDQUOT || errno == EFBIG ? errno : -1;
  };
  if (to > s.reserved_to) {
    const int result = reserve(s.fd, from, to - from);
    if (result != 0) return result;
    s.reserved_to = to;
  }
  if (s.journal >= 0) {
    struct stat journal_stat {};
    const std::uint64_t want = std::min<std::uint64_t>(bytes, s.mark_end);
    if (::fstat(s.journal, &journal_stat) == 0 && want > 0) {
      const int result = reserve(s.journal, static_cast<std::uint64_t>(journal_stat.st_size), want);
      if (result > 0) return result;
    }
  }
  return 0;
}

void remove_journal(const std::string& file_path) {
  std::error_code ec;
  std::filesystem::remove(journal_path(file_path), ec);
}

bool restore_journal(const std::string& original, const std::string& target,
                     std::uint64_t file_id) {
  const std::string path = journal_path(original);
  auto fail_read = [&]() {
    throw std::runtime_error(
        fmt::format("cannot read the journal {}: {}", path, std::strerror(errno)));
  };
  const int journal = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (journal < 0) {
    if (errno == ENOENT) return false;
    fail_read();
  }
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } close_journal{journal};
  unsigned char header[kHeaderBytes];
  std::size_t got = 0;
  if (!read_all(journal, header, sizeof header, 0, got)) fail_read();
  if (got < sizeof header || std::memcmp(header, kMagic, sizeof kMagic) != 0)
    throw std::runtime_error(fmt::format(
        "{} is not a Granule journal (or was cut short); the output {} cannot be put back "
        "as it stood at the checkpoint",
        path, original));
  if (get_u64(header + sizeof kMagic) != file_id)
    throw std::runtime_error(fmt::format(
        "{} is not the file the checkpoint's run wrote (its journal {} is another file's: "
        "written again since?)",
        original, path));
  const std::uint64_t length = get_u64(header + sizeof kMagic + 8);
  const int fd = ::open(target.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0)
    throw std::runtime_error(
        fmt::format("cannot open {} to put it back: {}", target, std::strerror(errno)));
  Closer close_target{fd};
  if (!lock_for_writing(fd))
    throw std::runtime_error(fmt::format(
        "{} is being written by another process (is the run that wrote the checkpoint still "
        "going?); a restart continues a file no run writes",
        target));
  auto fail_write = [&]() {
    throw std::runtime_error(
        fmt::format("cannot put {} back as it stood: {}", target, std::strerror(errno)));
  };
  off_t at = sizeof header;
  std::vector<unsigned char> bytes;
  while (true) {
    unsigned char head[16];
    if (!read_all(journal, head, sizeof head, at, got)) fail_read();
    if (got < sizeof head) break;  // the end, or a record cut short (its bytes never changed)
    const std::uint64_t offset = get_u64(head), size = get_u64(head + 8);
    if (offset + size > length || size > length)
      throw std::runtime_error(fmt::format("the journal {} is damaged", path));
    // In pieces. A record cut short saved bytes that never changed: writing back the
    // part of it that is there writes what the file holds.
    bool whole = true;
    for (std::uint64_t done = 0; done < size && whole; done += got) {
      bytes.resize(static_cast<std::size_t>(std::min<std::uint64_t>(size - done, kPiece)));
      if (!read_all(journal, bytes.data(), bytes.size(), at + 16 + static_cast<off_t>(done), got))
        fail_read();
      if (!write_all(fd, bytes.data(), got, static_cast<off_t>(offset + done))) fail_write();
      whole = got == bytes.size();
    }
    if (!whole) break;
    at += static_cast<off_t>(16 + size);
  }
  if (::ftruncate(fd, static_cast<off_t>(length)) != 0 || ::fdatasync(fd) != 0) fail_write();
  return true;
}

}  // namespace granule::io
