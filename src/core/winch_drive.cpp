#include "rov_tether/core/winch_drive.hpp"

#include <algorithm>
#include <cmath>

namespace rov_tether
{

SpoolDrum* WinchDrive::beforeSolve(const Scene& scene, double dt)
{
  const Cable& cable = scene.cable;
  const TetherParams& params = scene.params;
  held_at_pull_ = false;
  commanded_speed_ = 0.0;
  if (cable.first + 1 >= cable.size())
  {
    speed_ = drive_speed_ = 0.0;
    return nullptr;
  }
  // The spool segment's tension at the end of the last step, what a tension-driven winch reads.
  const double h = scene.last_step > 0.0 ? scene.last_step : dt;
  const double spool_tension = scene.solver.multipliers().stretch[cable.first] / (h * h);
  const WinchInput input{cable,
                         params,
                         scene.spool.deployedLength(cable),
                         dt,
                         target_length_,
                         scene.vehicle_attached,
                         scene.spool.outlet(),
                         scene.vehicle,
                         spool_tension,
                         speed_,
                         drive_speed_,
                         scene.solver.takesDrum()};
  Winch& winch = winches_[params.winch_mode];
  commanded_speed_ = params.winch_mode == WinchMode::kSpeed ? SpeedWinch::commandedSpeed(input) : 0.0;
  if (winch.drum(input, &drum_))
  {
    // A speed winch's drum is given only to reel in, by exactly its min_payout = max_payout; the stall pull alone
    // holds it back (spool_drum.hpp), which afterSolve reads from the pay-out the solve gives.
    reel_in_asked_ = params.winch_mode == WinchMode::kSpeed ? std::min(drum_.min_payout, 0.0) : 0.0;
    return &drum_;  // the solver decides the pay-out (afterSolve)
  }
  reel_in_asked_ = 0.0;
  double change = winch.lengthChange(input);
  if (change < 0.0 && spool_tension >= params.winchPull())
  {
    change = 0.0;  // no reel-in pulls harder than the motor's stall pull: it stops there
    held_at_pull_ = true;
  }
  payOut(scene, change, dt);
  return nullptr;
}

void WinchDrive::afterSolve(const Scene& scene, bool drum_in_solve, double h)
{
  if (drum_in_solve)
  {
    // Reeled in less than asked (by more than rounding): the stall pull held the drum.
    held_at_pull_ = reel_in_asked_ < 0.0 && drum_.payout > reel_in_asked_ * (1.0 - 1e-9);
    payOut(scene, drum_.payout, h, true);  // the pay-out the drum's law gave within the solve
    // The drive turned within its limits. A pull past the motor's stall pull stops a reel-in (the drive stops with
    // its motor, as far as standing) and pulled harder back-drives the drum out: a slip the drive does not take on.
    // A massless drum has no speed of its own: once the pull lets go, it turns at its drive's speed again (not at
    // the slip's, slowing at max_winch_acceleration, which paid metres out into slack cable:
    // Winch.ABackDrivenDrumTakesItsDrivesSpeedOnceThePullLetsGo).
    const double lowest = std::min(drum_.min_payout, drum_.max_payout) / h;
    const double highest = std::max(drum_.min_payout, drum_.max_payout) / h;
    drive_speed_ = std::isfinite(drum_.payout) ? std::clamp(speed_, lowest, std::max(highest, std::min(speed_, 0.0)))
                                               : speed_;  // a diverged solve's drum: standing, as payOut left it
  }
  outrun_time_ = atItsLimit(scene, h) ? outrun_time_ + h : 0.0;
  noteStall(scene, h);
  const TetherParams& params = scene.params;
  at_shortest_ = params.winch_mode == WinchMode::kSpeed && std::isnan(target_length_) && params.winch_speed < 0.0 &&
                 speed_ == 0.0 && scene.spool.deployedLength(scene.cable) <= params.min_deployed_length + 1e-9;
}

void WinchDrive::payOut(const Scene& scene, double change, double dt, bool drum_law)
{
  const TetherParams& params = scene.params;
  const double deployed = scene.spool.deployedLength(scene.cable);
  const double max_change = params.max_winch_speed * dt;
  if (!std::isfinite(change))
  {
    change = 0.0;  // a diverged solve's drum: the tether's checks re-lay the cable next, the spool stays as it was
  }
  change = std::clamp(change, -max_change, max_change);
  change = std::clamp(change, std::min(0.0, params.min_deployed_length - deployed),
                      std::max(0.0, params.cable_length - deployed));
  speed_ = drive_speed_ = change / dt;
  if (change != 0.0)
  {
    // A rod's first segment under the drum's law (no force while slack) keeps a slack release's slack.
    const bool rod_on_drum = drum_law && params.solver == SolverType::kDirect && params.elasticBending();
    scene.spool.payOut(scene.cable, scene.solver.multipliers(), change, params.lineMass(), scene.vehicle_attached,
                       rod_on_drum);
  }
}

void WinchDrive::restartDrive()
{
  drive_speed_ = speed_ * drive_speed_ <= 0.0 ? 0.0 : std::abs(speed_) < std::abs(drive_speed_) ? speed_ : drive_speed_;
}

void WinchDrive::reset()
{
  winches_.reset();
  speed_ = drive_speed_ = 0.0;
  outrun_time_ = 0.0;
  stall_time_ = 0.0;
  held_at_pull_ = false;
  at_shortest_ = false;
}

void WinchDrive::noteStall(const Scene& scene, double h)
{
  const TetherParams& params = scene.params;
  if (params.winch_mode != WinchMode::kSpeed || !(commanded_speed_ < 0.0) ||
      speed_ <= commanded_speed_ * (1.0 - 1e-9) ||
      scene.spool.deployedLength(scene.cable) <= params.min_deployed_length + 1e-9)
  {
    stall_time_ = 0.0;  // not asked to reel in, reeling in at its speed, or stopped by min_deployed_length
  }
  else if (held_at_pull_)
  {
    // Only the sub-steps the pull held count; those it spends getting back to speed after one (a solver that
    // stops the drum on the last step's tension restarts it, and is held again) neither count nor clear them.
    stall_time_ += h;
  }
}

bool WinchDrive::atItsLimit(const Scene& scene, double h) const
{
  const Cable& cable = scene.cable;
  const TetherParams& params = scene.params;
  if (cable.size() < cable.first + 2 || !(speed_ >= params.max_winch_speed * (1.0 - 1e-9)))
  {
    return false;
  }
  // The tension at which the mode gives way: the brake, the auto-tension target, the strain rule's threshold
  // as a tension (its stretch payout_threshold x L under EA).
  const double gives_way =
      params.winch_mode == WinchMode::kBrake             ? params.brake_tension
      : params.winch_mode == WinchMode::kConstantTension ? params.target_tension
      : params.winch_mode == WinchMode::kStrain
          ? params.payout_threshold *
                (cable.loading.empty() ? params.axial_stiffness : cable.loading.axial_stiffness[cable.first])
          : -1.0;
  const double tension = scene.solver.multipliers().stretch[cable.first] / (h * h);
  return gives_way >= 0.0 && tension > gives_way;
}

}  // namespace rov_tether
