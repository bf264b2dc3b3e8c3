// FNV-1a, 64 bits: a digest of bytes to tell two texts or states apart (not
// for security). Fed in pieces; the same bytes in the same order give the
// same value on every machine of one byte order.
#pragma once

#include <cstddef>
#include <cstdint>

namespace granule {

class Fnv1a {
 public:
  void add(const void* data, std::size_t bytes) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < bytes; ++k) value_ = (value_ ^ b[k]) * 1099511628211ull;
  }
  std::uint64_t value() const { return value_; }

 private:
  std::uint64_t value_ = 14695981039346656037ull;
};

}  // namespace granule
