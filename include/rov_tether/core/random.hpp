#pragma once

#include <cstdint>

namespace rov_tether
{

/**
 * xoshiro256+ (Blackman and Vigna), seeded through splitmix64: a small, fast generator whose output is
 * the same on every platform, so a seeded run is reproducible bit for bit.
 */
class Xoshiro256Plus
{
 public:
  explicit Xoshiro256Plus(std::uint64_t seed = 1) { reseed(seed); }

  void reseed(std::uint64_t seed)
  {
    for (auto& word : state_)
    {
      seed += 0x9E3779B97F4A7C15ull;
      std::uint64_t z = seed;
      z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
      z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
      word = z ^ (z >> 31);
    }
  }

  std::uint64_t next()
  {
    const std::uint64_t result = state_[0] + state_[3];
    const std::uint64_t t = state_[1] << 17;
    state_[2] ^= state_[0];
    state_[3] ^= state_[1];
    state_[1] ^= state_[2];
    state_[0] ^= state_[3];
    state_[2] ^= t;
    state_[3] = (state_[3] << 45) | (state_[3] >> 19);
    return result;
  }

  /// Uniform in [-1, 1).
  double symmetric() { return static_cast<double>(next() >> 11) * 0x1.0p-52 - 1.0; }

 private:
  std::uint64_t state_[4];
};

}  // namespace rov_tether
