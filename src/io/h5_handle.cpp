// The HDF5 error walker shared by the readers and writers (h5_handle.hpp).
#include "io/h5_handle.hpp"

namespace granule::io {

namespace {

// The library's own description of the error just raised (innermost first), since our
// messages replace HDF5's automatic stack printing.
herr_t collect_error(unsigned n, const H5E_error2_t* err, void* data) {
  auto* text = static_cast<std::string*>(data);
  if (n == 0 && err && err->desc) *text = err->desc;
  return 0;
}

}  // namespace

std::string hdf5_error_text() {
  std::string text;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, collect_error, &text);
  // A failed write's description carries the call's whole record (time, descriptor,
  // buffer address, over two lines); its first words and the system's message suffice.
  const std::string marker = "error message = '";
  const auto m = text.find(marker);
  if (m != std::string::npos) {
    const auto end = text.find('\'', m + marker.size());
    text = text.substr(0, text.find(':')) + ": " +
           text.substr(m + marker.size(), end == std::string::npos ? end : end - m - marker.size());
  }
  return text;
}

}  // namespace granule::io
