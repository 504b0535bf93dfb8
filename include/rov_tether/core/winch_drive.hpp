#pragma once

#include <cmath>
#include <limits>

#include "rov_tether/core/cable.hpp"
#include "rov_tether/core/constraint_solver.hpp"
#include "rov_tether/core/spool.hpp"
#include "rov_tether/core/spool_drum.hpp"
#include "rov_tether/core/tether_params.hpp"
#include "rov_tether/core/winch.hpp"

namespace rov_tether
{

/**
 * A tether's winch from one sub-step to the next: the mode's decision before the solve (a length change, or the
 * drum a direct solve takes into its step), the pay-out within the speed and length limits, the drive's own speed
 * (which a slip does not carry), and what the winch did (its speed, an outrun, a stall). Tether owns one and hands
 * it the scene of each sub-step; the modes themselves are the strategies of winch.hpp.
 */
class WinchDrive
{
 public:
  /// What the winch reads and moves in a sub-step: the tether's cable, spool and parameters, the solver's
  /// multipliers of the last solve, and the vehicle's attachment.
  struct Scene
  {
    Cable& cable;
    Spool& spool;
    const TetherParams& params;
    ConstraintSolver& solver;  ///< Its multipliers: the last solve's, and what a pay-out re-weighs.
    bool vehicle_attached;
    Position vehicle;  ///< Attachment point [m] (when attached).
    double last_step;  ///< The last sub-step's length [s] (tension = lambda / h^2), 0 before the first.
  };

  /// How long the winch must stay at its limit to be outrun, or held at its stall pull to have stalled [s].
  static constexpr double kOutrunTime = 0.2;

  /// The winch's decision before the solve of a (sub-)step of dt: pays out or reels in now, or fills the drum
  /// for a solver that takes it into the step and returns it (then afterSolve pays out what the solve gave).
  SpoolDrum* beforeSolve(const Scene& scene, double dt);
  /// After the solve of a sub-step of h: the drum's pay-out (when beforeSolve gave one) and the drive's speed,
  /// then the outrun and stall counts.
  void afterSolve(const Scene& scene, bool drum_in_solve, double h);
  /// Pays out (positive) or reels in `change` [m] within the speed and length limits; sets the winch's speed.
  void payOut(const Scene& scene, double change, double dt, bool drum_law = false);
  /// The drive starts again (a new winch mode or solver, a re-laid cable) from the drum as it turns, but not from
  /// a slip past the old drive: the one of the two speeds nearer standing, and standing if they turn opposite ways.
  void restartDrive();
  /// Forgets every mode's latched state and stands the winch still (a reset).
  void reset();

  /// In `speed` mode, the length to pay out or reel in to [m]; NaN for none (the caller checks the range).
  void setTargetLength(double length) { target_length_ = length; }
  double targetLength() const { return target_length_; }
  /// The pay-out speed over the last (sub-)step [m/s], negative reeling in.
  double speed() const { return speed_; }
  /// A `speed` winch's commanded speed in the last sub-step [m/s]; 0 in the other modes.
  double commandedSpeed() const { return commanded_speed_; }
  /// At its limit, pulled past giving way, for the last kOutrunTime (Tether::winchOutrun).
  bool outrun() const { return outrun_time_ >= kOutrunTime; }
  /// A speed winch's reel-in held at the stall pull for kOutrunTime (Tether::winchStalled).
  bool stalled() const { return stall_time_ >= kOutrunTime; }
  /// A `speed` winch without a target, its winch_speed asking to reel in, standing at min_deployed_length over the
  /// last sub-step (Tether::winchAtShortest).
  bool atShortest() const { return at_shortest_; }

 private:
  /// Whether the winch paid out at max_winch_speed over the last sub-step of length h [s] while the spool
  /// segment pulled harder than its mode gives way at.
  bool atItsLimit(const Scene& scene, double h) const;
  /// Counts the sub-step of length h [s] towards stalled() when the stall pull held a speed winch's reel-in.
  void noteStall(const Scene& scene, double h);

  WinchModes winches_;
  double target_length_ = std::numeric_limits<double>::quiet_NaN();  ///< speed-mode target [m]
  double speed_ = 0.0;            ///< Pay-out speed over the last (sub-)step [m/s], negative reeling in.
  double drive_speed_ = 0.0;      ///< The winch drive's own speed over it [m/s] (WinchInput::drive_speed).
  double outrun_time_ = 0.0;      ///< How long the winch has been at its limit, pulled past giving way [s].
  double stall_time_ = 0.0;       ///< Sub-steps a speed winch's reel-in was held at the stall pull, since at speed [s].
  double commanded_speed_ = 0.0;  ///< A speed winch's commanded speed in the sub-step [m/s]; 0 in other modes.
  double reel_in_asked_ = 0.0;    ///< The reel-in a speed winch's drum was asked for in the sub-step [m] (< 0).
  bool held_at_pull_ = false;     ///< The sub-step's reel-in was held back at the stall pull.
  bool at_shortest_ = false;      ///< atShortest().
  SpoolDrum drum_;                ///< The brake drum as the solver takes it into a step.
};

}  // namespace rov_tether
