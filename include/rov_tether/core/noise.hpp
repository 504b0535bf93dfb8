#pragma once

#include <cstdint>

#include "rov_tether/core/cable.hpp"
#include "rov_tether/core/random.hpp"

namespace rov_tether
{

/**
 * The paper's random micro-current displacements: a uniform displacement per axis added to each free
 * particle, seeded, so the same seed gives the same run. The particles of the first two free segments get
 * none (the paper's rule against spontaneous release at the spool).
 */
class MicroCurrentNoise
{
 public:
  /// Particles after the spool outlet that get no displacement.
  static constexpr std::size_t kQuietParticles = 2;

  void reseed(std::int64_t seed) { rng_.reseed(static_cast<std::uint64_t>(seed)); }
  /// Adds a displacement uniform in [-amplitude, amplitude] per axis to particles [first + 1 +
  /// kQuietParticles, end) [m].
  void apply(Cable& cable, std::size_t end, double amplitude)
  {
    if (amplitude <= 0.0)
    {
      return;
    }
    for (std::size_t i = cable.first + 1 + kQuietParticles; i < end; ++i)
    {
      cable.x[i] += amplitude * rng_.symmetric();
      cable.y[i] += amplitude * rng_.symmetric();
      cable.z[i] += amplitude * rng_.symmetric();
    }
  }

 private:
  Xoshiro256Plus rng_;
};

}  // namespace rov_tether
