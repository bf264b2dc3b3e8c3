// Plain values appended to and read from a byte string, bit for bit: the
// particle records that travel between ranks and the contact histories packed
// with them (structs of doubles, ints and fixed-size Eigen vectors, copied as
// memory, as the checkpoints copy them).
#pragma once

#include <cstring>
#include <stdexcept>
#include <string>

namespace granule::bytes {

template <typename T>
void put(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

// The value at `at`, which moves past it; std::runtime_error "<what> is cut
// short" when fewer bytes remain.
template <typename T>
T take(const std::string& in, std::size_t& at, const char* what) {
  if (at + sizeof(T) > in.size()) throw std::runtime_error(std::string(what) + " is cut short");
  T value;
  std::memcpy(static_cast<void*>(&value), in.data() + at, sizeof(T));
  at += sizeof(T);
  return value;
}

}  // namespace granule::bytes
