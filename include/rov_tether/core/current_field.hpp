#pragma once

#include <cstdint>

#include "rov_tether/core/cable.hpp"
#include "rov_tether/core/tether_params.hpp"

namespace rov_tether
{

/**
 * The water's velocity: the uniform `current` plus its slow, spatially correlated variation
 * (`current_variation`, RMS): a few plane waves of 20-100 m wavelength and 1-5 min period drawn from the
 * seed. Real currents have no high-frequency content (the paper), so neither has this field.
 */
class CurrentField
{
 public:
  /// Takes the current and its variation from `params`, and draws the waves from params.seed (their own
  /// generator, so the noise sequence does not depend on them).
  void configure(const TetherParams& params);
  /// Water velocity at `point` and time t [m/s].
  Position at(const Position& point, double t) const;
  /// True when the water moves the same everywhere and always (no variation).
  bool uniform() const { return variation_ <= 0.0; }
  /// The uniform part [m/s].
  const Position& mean() const { return mean_; }

 private:
  /// One plane wave: amplitude direction, wave vector [1/m], angular frequency [1/s] and phase.
  struct Mode
  {
    Position direction;
    Position wave_vector;
    double omega;
    double phase;
  };
  static constexpr std::size_t kModes = 4;
  Position mean_ = Position::Zero();
  double variation_ = 0.0;
  Mode modes_[kModes];
};

}  // namespace rov_tether
