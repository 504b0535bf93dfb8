#include "rov_tether/winch.hpp"

#include <algorithm>
#include <cmath>

namespace rov_tether
{

double SpeedWinch::lengthChange(const WinchInput& in)
{
  const double speed_change = in.params.winch_speed * in.dt;
  return std::isnan(in.target_length)
             ? speed_change
             : std::clamp(in.target_length - in.deployed, -std::abs(speed_change), std::abs(speed_change));
}

double PassiveWinch::lengthChange(const WinchInput& in)
{
  // The strain is read after the step's motion and before the constraints pull the segment back (a
  // post-projection reading is biased to zero). Pay-out goes on, up to max_winch_speed, while the segment
  // stays stretched at all (so a steady pull does not hold the cable at the threshold) and less than the
  // reel-in limit is out (so a vehicle circling at constant distance does not unreel the whole cable).
  const Cable& cable = in.cable;
  const std::size_t f = cable.first;
  const double length = (cable.position(f + 1) - cable.position(f)).norm();
  const double strain = length / cable.rest[f] - 1.0;
  const double excess =
      in.vehicle_attached ? in.deployed - (1.0 + in.params.reel_in_slack) * (in.vehicle - in.spool).norm() : -1.0;
  paying_out_ = strain > in.params.payout_threshold || (paying_out_ && strain > 0.0 && excess < 0.0);
  if (paying_out_)
  {
    return length - cable.rest[f];
  }
  if (excess > 0.0)
  {
    return -excess;  // reel in the slack beyond the limit
  }
  return 0.0;
}

WinchModes::WinchModes()
    : modes_{std::make_unique<PassiveWinch>(), std::make_unique<LockedWinch>(), std::make_unique<SpeedWinch>()}
{
}

Winch& WinchModes::operator[](WinchMode mode)
{
  switch (mode)
  {
    case WinchMode::kPassive:
      return *modes_[0];
    case WinchMode::kLocked:
      return *modes_[1];
    default:
      return *modes_[2];
  }
}

void WinchModes::reset()
{
  for (auto& mode : modes_)
  {
    mode->reset();
  }
}

}  // namespace rov_tether
