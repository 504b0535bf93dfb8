#include "rov_tether/core/current_field.hpp"

#include <cmath>

#include "rov_tether/core/random.hpp"

namespace rov_tether
{
namespace
{
constexpr double kPi = 3.14159265358979323846;
}  // namespace

void CurrentField::configure(const TetherParams& params)
{
  mean_ = Position(params.current[0], params.current[1], params.current[2]);
  variation_ = params.current_variation;
  Xoshiro256Plus waves(static_cast<std::uint64_t>(params.seed) ^ 0x9e3779b97f4a7c15ULL);
  auto unit = [&waves]
  {
    Position v(waves.symmetric(), waves.symmetric(), waves.symmetric());
    return v.norm() > 1e-6 ? Position(v.normalized()) : Position(Position::UnitX());
  };
  for (auto& mode : modes_)
  {
    mode.direction = unit();
    const double wavelength = 60.0 + 40.0 * waves.symmetric();
    const double period = 180.0 + 120.0 * waves.symmetric();
    mode.wave_vector = unit() * (2.0 * kPi / wavelength);
    mode.omega = 2.0 * kPi / period;
    mode.phase = kPi * waves.symmetric();
  }
}

Position CurrentField::at(const Position& point, double t) const
{
  Position u = mean_;
  if (variation_ > 0.0)
  {
    // Each sine has RMS 1/sqrt(2): the sum of K modes scaled by sqrt(2/K) has RMS current_variation.
    const double scale = variation_ * std::sqrt(2.0 / kModes);
    for (const auto& mode : modes_)
    {
      u += scale * std::sin(mode.wave_vector.dot(point) + mode.omega * t + mode.phase) * mode.direction;
    }
  }
  return u;
}

}  // namespace rov_tether
