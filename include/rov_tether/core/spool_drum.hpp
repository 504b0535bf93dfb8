#pragma once

#include <array>
#include <cstddef>
#include <limits>

namespace rov_tether
{

/**
 * The winch drum at the spool end, as the direct solver takes it into one step: the spool segment and the
 * drum act in series, so the segment's force is a law of its stretch c = |d| - L (L its rest length at the
 * step's start) that the solver meets exactly, with no lag between a pull and the pay-out it causes.
 *
 * Forces are multipliers [kg m] (force times h^2), lengths in metres. Over the step the drum pays out s
 * (negative: reels in), min_payout <= s <= max_payout (the speed and acceleration limits, the cable left).
 * The drum's characteristic, s against the segment's force lambda:
 * - massless (inertia 0): it stands while floor < lambda < brake, pays out exactly as fast as keeps lambda at
 *   `brake`, reels in exactly as fast as keeps it at `floor` (a brake: no floor; an auto-tension winch:
 *   both);
 * - with an equivalent mass m at its radius (a brake only): m (s - coast) = lambda - brake while it turns,
 *   coast being its pay-out at the last speed, so a moving drum slows down when the pull drops below the
 *   brake, and stops;
 * - the motor's stall pull `stall`: there the motor gives way, however the acceleration limit stood: the
 *   drum stops reeling in and, pulled harder, is back-driven, paying out up to `slip` (the speed limit), so
 *   the segment's force does not pass the stall pull while the drum can still turn.
 * The segment stretches elastically by alpha lambda (alpha its compliance), so c = s(lambda) + alpha lambda
 * for lambda > 0, and lambda = 0 while c <= s(0) (the segment slack). This is a continuous, monotone,
 * piecewise linear law lambda = force(c): a convex energy for the primal path, a linear row for the dual one
 * on each of its pieces.
 */
class SpoolDrum
{
 public:
  double brake = 0.0;       ///< Force at which it pays out, times h^2 [kg m].
  double floor = -1.0;      ///< Force below which it reels in, times h^2 [kg m]; negative: never.
  double inertia = 0.0;     ///< Equivalent mass at the drum radius [kg]; 0 = massless (pay-out side).
  double coast = 0.0;       ///< Pay-out over the step at the drum's last speed [m].
  double min_payout = 0.0;  ///< Least pay-out in the step [m] (negative: the most reel-in).
  double max_payout = 0.0;  ///< Most pay-out in the step [m].
  /// Force at or above which the drum does not reel in, times h^2 [kg m]: the motor's stall pull; infinity:
  /// none.
  double stall = std::numeric_limits<double>::infinity();
  double slip = 0.0;    ///< Most pay-out in the step once pulled past `stall` [m] (max_winch_speed, cable left).
  double payout = 0.0;  ///< The solver's answer: paid out over the step [m].

  /// Builds the law for the spool segment's compliance alpha [1/kg]; call after setting the fields.
  void prepare(double alpha);

  /// A piece of the law as the row of a linear system: lambda = value when `fixed`, else
  /// c - offset - compliance lambda = 0.
  struct Row
  {
    bool fixed;
    double value;       ///< The fixed lambda [kg m], or the offset [m].
    double compliance;  ///< [1/kg]
  };

  /// The piece holding stretch c [m] (0: the slack piece).
  std::size_t pieceOf(double c) const;
  /// That piece's row.
  Row row(std::size_t piece) const;
  /// The segment's force lambda for stretch c (the law).
  double force(double c) const;
  /// d force / d c: 0 on a piece where the force is fixed.
  double stiffness(double c) const;
  /// The law's energy, the integral of force from the slack end to c (convex) [kg m^2].
  double energy(double c) const;
  /// The drum's pay-out over the step when the segment ends at stretch c: c - alpha force(c) where the
  /// segment pulls, s(0) where it is slack.
  double payoutAt(double c) const;
  /// How far stretch c [m] is from the nearest stretch at which the law gives force lambda [kg m] (0 where it
  /// does; the law's pieces of a fixed force give it over an interval); infinity for a lambda below 0, which
  /// no stretch gives.
  double stretchOff(double c, double lambda) const;
  /// The force lambda that meets the law when the rest of the chain answers it linearly: lambda =
  /// force(a - b lambda), b >= 0 (more force, less stretch). Unique (the law is monotone), found exactly
  /// on its piece.
  double forceAgainst(double a, double b) const;

 private:
  /// A piece: from stretch c0, where the force is lambda0, rising by `slope` per metre of stretch.
  struct Piece
  {
    double c0, lambda0, slope;
  };
  std::array<Piece, 10> pieces_{};
  std::size_t count_ = 0;
  double alpha_ = 0.0;
  double slack_payout_ = 0.0;  ///< s(0).
};

}  // namespace rov_tether
