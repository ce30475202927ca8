// Random: seeded uniform numbers that are the same on every platform, for jitter and Poisson sampling.
#pragma once

#include <cstdint>
#include <random>

namespace romp::geometry {

// std::mt19937_64's integer sequence is fixed by the standard; std::uniform_real_distribution's
// conversion to doubles is not (libstdc++, libc++ and MSVC differ). So the conversions are here.
class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}

  // Uniform in [0, 1): the top 53 bits of one draw, scaled by 2⁻⁵³ (exact).
  double uniform() { return double(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double low, double high) { return low + (high - low) * uniform(); }
  // Uniform in [0, n) for n > 0; the modulo bias is below n / 2⁶⁴.
  std::uint64_t below(std::uint64_t n) { return engine_() % n; }

 private:
  std::mt19937_64 engine_;
};

}  // namespace romp::geometry
