#pragma once

#include <array>
#include <memory>

#include "rov_tether/cable.hpp"
#include "rov_tether/tether_params.hpp"

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
  Position spool;    ///< Outlet [m].
  Position vehicle;  ///< Attachment point [m] (when attached).
};

/**
 * A winch mode: how much cable to pay out (positive) or reel in this step, before the tether applies the
 * speed and length limits (max_winch_speed, min_deployed_length, cable_length). One small strategy per
 * mode; a new mode is one more class and one more entry in WinchModes.
 */
class Winch
{
 public:
  virtual ~Winch() = default;
  virtual double lengthChange(const WinchInput& in) = 0;
  /// Forgets any latched state (a reset).
  virtual void reset() {}
};

/// The deployed length never changes.
class LockedWinch : public Winch
{
 public:
  double lengthChange(const WinchInput&) override { return 0.0; }
};

/// Pays out (positive) or reels in at winch_speed, or towards the target length and holds it there.
class SpeedWinch : public Winch
{
 public:
  double lengthChange(const WinchInput& in) override;
};

/**
 * The paper's rule with hysteresis: pay-out starts when the first free segment is stretched past
 * payout_threshold and goes on while it stays stretched at all and less than the reel-in limit is out;
 * slack beyond (1 + reel_in_slack) times the spool-vehicle distance is reeled in.
 */
class PassiveWinch : public Winch
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
  std::array<std::unique_ptr<Winch>, 3> modes_;
};

}  // namespace rov_tether
