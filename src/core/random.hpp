// A seeded generator whose stream is the same on every platform and standard
// library (std::uniform_real_distribution is not), so a seed reproduces a fill.
#pragma once

#include <cstdint>
#include <random>

namespace granule {

class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  // Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  std::uint64_t next() { return engine_(); }

 private:
  std::mt19937_64 engine_;
};

}  // namespace granule
