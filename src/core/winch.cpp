#include "rov_tether/core/winch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rov_tether
{
namespace
{

/// The speed `wanted` reached from `speed` at most `acceleration` x dt away [m/s].
double accelerate(double speed, double wanted, double acceleration, double dt)
{
  const double step = acceleration * dt;
  return speed + std::clamp(wanted - speed, -step, step);
}

/// Stretch of the spool segment now: its length beyond its rest length [m].
double spoolStretch(const Cable& cable)
{
  const std::size_t f = cable.first;
  return (cable.position(f + 1) - cable.position(f)).norm() - cable.rest[f];
}

}  // namespace

bool BrakeWinch::drum(const WinchInput& in, SpoolDrum* drum)
{
  if (!in.drum_in_solver)
  {
    return false;
  }
  const TetherParams& p = in.params;
  drum->brake = p.brake_tension * in.dt * in.dt;
  drum->floor = -1.0;  // never reels in
  drum->inertia = p.winch_inertia;
  drum->coast = std::max(in.speed, 0.0) * in.dt;
  drum->min_payout = 0.0;
  drum->max_payout = std::max(0.0, std::min(p.max_winch_speed * in.dt, p.cable_length - in.deployed));
  drum->stall = std::numeric_limits<double>::infinity();  // it never reels in
  drum->payout = 0.0;
  return true;
}

bool ConstantTensionWinch::drum(const WinchInput& in, SpoolDrum* drum)
{
  if (!in.drum_in_solver)
  {
    return false;
  }
  const TetherParams& p = in.params;
  const double h2 = in.dt * in.dt;
  const double change = p.max_winch_acceleration * in.dt;
  drum->brake = (p.target_tension + p.tension_deadband) * h2;
  drum->floor = (p.target_tension - p.tension_deadband) * h2;  // not positive: it never reels in
  drum->inertia = 0.0;
  drum->coast = 0.0;
  const double fastest_out = std::min(p.max_winch_speed, in.drive_speed + change) * in.dt;
  const double fastest_in = std::max(-p.max_winch_speed, in.drive_speed - change) * in.dt;
  drum->max_payout = std::min(fastest_out, p.cable_length - in.deployed);
  drum->min_payout = std::min(std::max(fastest_in, p.min_deployed_length - in.deployed), drum->max_payout);
  drum->stall = p.winchPull() * h2;  // the motor gives way at its pull, whatever the acceleration limit
  drum->slip = std::max(0.0, std::min(p.max_winch_speed * in.dt, p.cable_length - in.deployed));
  drum->payout = 0.0;
  return true;
}

bool SpeedWinch::drum(const WinchInput& in, SpoolDrum* drum)
{
  if (!in.drum_in_solver)
  {
    return false;
  }
  const double change = lengthChange(in);
  if (!(change < 0.0))
  {
    return false;  // paying out or standing: no force stops it, the change is made before the solve
  }
  // Reeling in: at the commanded speed while the spool tension stays below the motor's stall pull; there the
  // motor gives way (the drum stops, pulled harder it pays out), met within the step so no lag lets the pull
  // overshoot.
  drum->brake = 0.0;
  drum->floor = -1.0;
  drum->inertia = 0.0;
  drum->coast = 0.0;
  drum->min_payout = change;
  drum->max_payout = change;
  drum->stall = in.params.winchPull() * in.dt * in.dt;
  drum->slip = std::max(0.0, std::min(in.params.max_winch_speed * in.dt, in.params.cable_length - in.deployed));
  drum->payout = 0.0;
  return true;
}

double BrakeWinch::lengthChange(const WinchInput& in)
{
  // Without the drum in the solve: the last step's tension decides.
  const TetherParams& p = in.params;
  if (p.winch_inertia > 0.0)
  {
    const double speed =
        std::max(0.0, std::max(in.speed, 0.0) + in.dt * (in.spool_tension - p.brake_tension) / p.winch_inertia);
    return speed * in.dt;
  }
  // Massless: pay out the stretch beyond what the brake holds elastically, brake_tension L / EA.
  const double held = p.brake_tension * in.cable.rest[in.cable.first] / p.axial_stiffness;
  return in.spool_tension > p.brake_tension ? std::max(0.0, spoolStretch(in.cable) - held) : 0.0;
}

double ConstantTensionWinch::lengthChange(const WinchInput& in)
{
  const TetherParams& p = in.params;
  const double error = in.spool_tension - p.target_tension;
  const double band = p.tension_deadband;
  const double ramp = std::max(p.target_tension, 1e-3);
  double wanted = 0.0;
  if (std::abs(error) > band)
  {
    wanted = std::copysign(p.max_winch_speed * std::min(1.0, (std::abs(error) - band) / ramp), error);
  }
  return accelerate(in.drive_speed, wanted, p.max_winch_acceleration, in.dt) * in.dt;
}

double SpeedWinch::shortestDistance(const WinchInput& in)
{
  // Within rounding of the limit (the rest lengths' sum) it is there: asked for no 1e-16 m reel-ins.
  const double distance = in.params.min_deployed_length - in.deployed;
  return distance < -1e-9 ? distance : 0.0;
}

double SpeedWinch::commandedSpeed(const WinchInput& in)
{
  const TetherParams& p = in.params;
  if (std::isnan(in.target_length) && !(p.winch_speed < 0.0))
  {
    return p.winch_speed;
  }
  // Towards the target, or a reel-in without one towards min_deployed_length (the shortest the drum reels in to,
  // which it would otherwise hit at full speed and then be asked past at every step): no faster than lets it stop
  // there at max_winch_acceleration. At min_deployed_length that is 0.
  const double distance = std::isnan(in.target_length) ? shortestDistance(in) : in.target_length - in.deployed;
  // The speed from which steps of dt, each slower by a dt, stop within the distance d: v^2 / 2a + v dt / 2 = d (the
  // continuous sqrt(2 a d) ran a dt behind and arrived at up to ten times a dt: a jerk at the end).
  const double a = p.max_winch_acceleration;
  const double half_step = 0.5 * a * in.dt;
  const double stopping = std::sqrt(half_step * half_step + 2.0 * a * std::abs(distance)) - half_step;
  return std::copysign(std::min(std::abs(p.winch_speed), stopping), distance);
}

double SpeedWinch::lengthChange(const WinchInput& in)
{
  const TetherParams& p = in.params;
  const double change = accelerate(in.drive_speed, commandedSpeed(in), p.max_winch_acceleration, in.dt) * in.dt;
  if (std::isnan(in.target_length))
  {
    // A reel-in not past min_deployed_length, whatever winch_speed asks now: a drive still reeling in after a
    // switch to 0 or a pay-out slows down at max_winch_acceleration, which may not stop it in time (a drive still
    // paying out slows down as it would).
    return change < 0.0 ? std::max(change, shortestDistance(in)) : change;
  }
  const double distance = in.target_length - in.deployed;  // and not past the target
  return std::abs(change) > std::abs(distance) ? distance : change;
}

double StrainWinch::lengthChange(const WinchInput& in)
{
  // The strain is read after the step's motion and before the constraints pull the segment back (a
  // post-projection reading is biased to zero). Pay-out goes on, up to max_winch_speed, while the segment
  // stays stretched at all (so a steady pull does not hold the cable at the threshold) and less than the
  // reel-in limit is out (so a vehicle circling at constant distance does not unreel the whole cable).
  const Cable& cable = in.cable;
  const std::size_t f = cable.first;
  const double stretch = spoolStretch(cable);
  const double strain = stretch / cable.rest[f];
  const double excess =
      in.vehicle_attached ? in.deployed - (1.0 + in.params.reel_in_slack) * (in.vehicle - in.spool).norm() : -1.0;
  paying_out_ = strain > in.params.payout_threshold || (paying_out_ && strain > 0.0 && excess < 0.0);
  if (paying_out_)
  {
    return stretch;
  }
  if (excess > 0.0)
  {
    return -excess;  // reel in the slack beyond the limit
  }
  return 0.0;
}

WinchModes::WinchModes()
    : modes_{std::make_unique<BrakeWinch>(), std::make_unique<ConstantTensionWinch>(), std::make_unique<SpeedWinch>(),
             std::make_unique<LockedWinch>(), std::make_unique<StrainWinch>()}
{
}

Winch& WinchModes::operator[](WinchMode mode)
{
  switch (mode)
  {
    case WinchMode::kBrake:
      return *modes_[0];
    case WinchMode::kConstantTension:
      return *modes_[1];
    case WinchMode::kSpeed:
      return *modes_[2];
    case WinchMode::kLocked:
      return *modes_[3];
    default:
      return *modes_[4];
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
