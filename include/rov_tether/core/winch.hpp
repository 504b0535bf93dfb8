#pragma once

#include <array>
#include <memory>

#include "rov_tether/core/cable.hpp"
#include "rov_tether/core/spool_drum.hpp"
#include "rov_tether/core/tether_params.hpp"

namespace rov_tether
{

/// What a winch rule sees when it decides one step's length change.
struct WinchInput
{
  const Cable& cable;
  const TetherParams& params;
  double deployed;       ///< Cable off the spool [m].
  double dt;             ///< Step [s].
  double target_length;  ///< speed mode's target [m], NaN for none.
  bool vehicle_attached;
  Position spool;        ///< Outlet [m].
  Position vehicle;      ///< Attachment point [m] (when attached).
  double spool_tension;  ///< Tension of the spool segment at the end of the last step [N].
  double speed;          ///< The winch's pay-out speed over the last step [m/s], negative reeling in.
  /// Its drive's own speed over the last step [m/s]: `speed`, except where a pull past the motor's stall pull
  /// back-drove the drum out past its drive, a slip the drive does not take on (a stall that stops a reel-in
  /// stops the drive with it). The acceleration limit (max_winch_acceleration) ramps this: a massless drum turns
  /// at its drive's speed again as soon as the pull lets go.
  double drive_speed;
  bool drum_in_solver;  ///< The solver meets a SpoolDrum's law within its step (direct).
};

/**
 * A winch mode: how much cable to pay out (positive) or reel in over a step, before the tether applies the
 * speed and length limits (max_winch_speed, min_deployed_length, cable_length). One small strategy per
 * mode; a new mode is one more class and one more entry in WinchModes.
 */
class Winch
{
 public:
  virtual ~Winch() = default;
  /// The length change decided before the step's solve [m].
  virtual double lengthChange(const WinchInput& in) = 0;
  /// Fills `drum` for a solver that takes it into the step, which then decides the pay-out itself (after
  /// its solve the tether pays out drum->payout); false when this mode works before the solve instead.
  virtual bool drum(const WinchInput& /*in*/, SpoolDrum* /*drum*/) { return false; }
  /// Forgets any latched state (a reset).
  virtual void reset() {}
};

/**
 * `brake`: the drum is held by a brake that slips at brake_tension [N]. While the spool-end tension
 * exceeds it, cable pays out, the drum's equivalent mass winch_inertia [kg] accelerating by (T - brake) / m
 * (a massless drum pays out exactly as fast as keeps the tension at the brake); otherwise the drum slows down
 * and stops. It never reels in. With direct the law is met within the step (spool_drum.hpp): no lag, so no
 * stick-slip. The other methods read the last step's tension: a massless drum then pays out the spool
 * segment's stretch while the tension is above the brake, a massive one integrates its speed.
 */
class BrakeWinch : public Winch
{
 public:
  double lengthChange(const WinchInput& in) override;
  bool drum(const WinchInput& in, SpoolDrum* drum) override;
};

/**
 * `constant_tension`: an auto-tension winch. It pays out when the spool-end tension is above target_tension
 * + tension_deadband and reels in when it is below target_tension - tension_deadband, as fast as keeps it at
 * that edge, within max_winch_speed and max_winch_acceleration; in between it stands. With direct this is
 * met within the step (spool_drum.hpp). The other methods read the last step's tension and move at a speed
 * that grows with the excess over the deadband, reaching max_winch_speed at an excess of the target itself.
 * At the motor's stall pull (winchPull()) the drum gives way, whatever the acceleration limit: a reel-in
 * stops, and pulled harder it pays out, so a reel-in never pulls harder than the motor.
 */
class ConstantTensionWinch : public Winch
{
 public:
  double lengthChange(const WinchInput& in) override;
  bool drum(const WinchInput& in, SpoolDrum* drum) override;
};

/// `speed`: pays out (positive) or reels in at winch_speed, or towards the target length, where it stops
/// without overshoot; its drive's speed changes by at most max_winch_acceleration. A reel-in without a target
/// stops so at min_deployed_length, and stands there (commanded 0, no drum handed to the solver) for as long as
/// winch_speed asks past it. A reel-in stops (the motor gives way) when the spool tension reaches the motor's stall
/// pull (TetherParams::winchPull()); with direct within the step (a SpoolDrum of that law), otherwise from the last
/// step's tension.
class SpeedWinch : public Winch
{
 public:
  double lengthChange(const WinchInput& in) override;
  bool drum(const WinchInput& in, SpoolDrum* drum) override;
  /// The speed it heads for [m/s] (negative reeling in) before the acceleration limit: winch_speed, or towards
  /// the target, or a reel-in towards min_deployed_length, no faster than lets it stop there.
  static double commandedSpeed(const WinchInput& in);

 private:
  /// How far a reel-in may go before min_deployed_length [m], <= 0 (0 within 1e-9 m of it).
  static double shortestDistance(const WinchInput& in);
};

/// `locked`: the deployed length never changes.
class LockedWinch : public Winch
{
 public:
  double lengthChange(const WinchInput&) override { return 0.0; }
};

/**
 * `strain`, the paper's rule with hysteresis: pay-out starts when the first free segment is stretched past
 * payout_threshold and goes on while it stays stretched at all and less than the reel-in limit is out;
 * slack beyond (1 + reel_in_slack) times the spool-vehicle distance is reeled in.
 */
class StrainWinch : public Winch
{
 public:
  double lengthChange(const WinchInput& in) override;
  void reset() override { paying_out_ = false; }

 private:
  bool paying_out_ = false;  ///< Latched into pay-out.
};

/// One winch of each mode, kept for the tether's life so a mode's latched state survives a switch.
class WinchModes
{
 public:
  WinchModes();
  Winch& operator[](WinchMode mode);
  void reset();

 private:
  std::array<std::unique_ptr<Winch>, 5> modes_;
};

}  // namespace rov_tether
