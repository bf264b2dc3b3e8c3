// What every HDF5 reader and writer in src/io shares: a handle that owns one
// hid_t, the library's own description of the error just raised, the switch
// that keeps HDF5's stack dump off the terminal, and the files' time stamps.
// Internal to src/io.
#pragma once

#include <hdf5.h>

#include <ctime>
#include <string>
#include <utility>

// H5Pset_file_locking exists from 1.10.7 in the 1.10 series and from 1.12.1 after that.
#if (H5_VERS_MAJOR == 1 && H5_VERS_MINOR == 10 && H5_VERS_RELEASE >= 7) || H5_VERSION_GE(1, 12, 1)
#define GRANULE_HAVE_FILE_LOCKING_PLIST 1
#endif

namespace granule::io {

// Owns one hid_t and closes it with the matching H5*close; move-only, so no handle is
// closed twice or leaked when an exception unwinds.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer close) : id_(id), close_(close) {}
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, H5I_INVALID_HID)), close_(o.close_) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, H5I_INVALID_HID);
      close_ = o.close_;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }
  hid_t get() const { return id_; }
  bool ok() const { return id_ >= 0; }
  void release() { id_ = H5I_INVALID_HID; }  // forgets the id without closing it
  void reset() {
    if (id_ >= 0 && close_) close_(id_);
    id_ = H5I_INVALID_HID;
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
  Closer close_ = nullptr;
};

// The description of the HDF5 error just raised (innermost first; "" if none), made short:
// a failed write says "file write failed: No space left on device". Call it before any
// other HDF5 function, which would clear the error. (Also declared in h5_output.hpp, for
// code that does not include HDF5's header.)
std::string hdf5_error_text();

// hdf5_error_text(), or "HDF5 error" when the library recorded none.
inline std::string h5_error_detail() {
  const std::string text = hdf5_error_text();
  return text.empty() ? "HDF5 error" : text;
}

inline void silence_hdf5() {
  // Users should see our messages, which name the file and object, not HDF5's stack dump.
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

// Now in UTC as ISO 8601 ("2026-01-31T12:00:00Z"), the time stamps our files carry.
inline std::string iso_time_now() {
  std::time_t t = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&t, &utc);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return buf;
}

}  // namespace granule::io
