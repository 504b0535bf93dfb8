#pragma once

#include "rov_tether/core/cable.hpp"
#include "rov_tether/core/tether_params.hpp"

namespace rov_tether
{

/**
 * How a cable is laid out at rest between its spool outlet and its vehicle, or hanging from the spool with a
 * free end: when it is built, when a vehicle attaches or jumps, after a reset or a failure. Only the
 * particles' places (positions equal to previous positions: no velocity); masses, multipliers and contact
 * are the caller's (Tether::layOut).
 *
 * The deployed particles are put by arc length along the rest lengths the spool gave them, so that no
 * segment starts stretched:
 * - taut (the deployed length at most the spool-vehicle distance): a straight line from the spool;
 * - slack: two straight legs spool -> apex -> vehicle as long as the cable, the apex below the chord's middle
 *   (sideways when the chord is vertical); for a cable that resists bending (TetherParams::elasticBending():
 *   EI > 0 on the tether or in a section; a solver that bends: direct or xpbd) a circular arc in the same plane whose
 *   chords are the rest lengths instead, as a V's kink would spring open in the first steps (a 2 m cable at
 *   EI 0.2 N m^2 pushed its vehicle with 1 N);
 * - slack that would hang through a flat seabed (`seabed_z`): bowed sideways, level across the chord, and
 *   what of it is still below the seabed put on it;
 * - no vehicle (a free end): where it settles. Above the water surface (`water_surface_z`) any cable is heavy: it
 *   hangs straight down to the surface. In the water, the cable beyond that point rises straight up when its net
 *   weight in water is negative (its sections' `weight_in_water` over their lengths less its attachments'
 *   `net_buoyancy`), else it hangs straight down; it stops at the surface or the seabed (`seabed_z`) and the rest
 *   of it lies along that level in +x. A cable that resists bending turns onto the level along a circle of radius
 *   (EI / |w|)^(1/3) tangent to it, from the vertical (or from the spool, tilted, when the drop is shorter than the
 *   radius), and a cable too short for that path ends on the arc (a right-angled corner at EI 50 N m^2 sprang open
 *   at the start with 3.9 times the spool's settled tension). Without a surface or a seabed in its way, straight up
 *   or down, all of it.
 *   (A cable whose net weight changes sign along it, a heavy length with a buoyant tail, is laid by the whole's
 *   and folds as it settles.)
 * Particles still on the spool sit at the outlet; the vehicle particle sits on the vehicle. Allocates
 * nothing.
 */
class CableLayout
{
 public:
  /// Takes what the layout depends on from `params` (bending, solver, seabed_z, water_surface_z, weight_in_water).
  explicit CableLayout(const TetherParams& params);

  /// Places every particle of `cable` at rest. The rest lengths (and `cable.first`) are as the spool set
  /// them, `length` is the deployed length they add up to [m]; `vehicle` is the vehicle attachment [m], or
  /// null for a free end.
  void layOut(Cable& cable, const Position& spool, const Position* vehicle, double length) const;

 private:
  /// The line the deployed cable is laid along: its two ends, the chord's middle and direction, and how far
  /// a slack cable's V reaches off the chord (0 when taut or free).
  struct Chord
  {
    Position spool;
    Position end;
    Position middle;
    Position direction = Position::UnitX();
    double distance = 0.0;  ///< |end - spool| with a vehicle, else 0 [m].
    double offset = 0.0;    ///< How far the V's apex is off the chord [m].
    double length = 0.0;    ///< Deployed length [m].
  };

  static Chord chordOf(const Position& spool, const Position& vehicle, double length);
  /// Lays a free end (no vehicle): vertical from the spool to where it stops, then level along +x, turning onto
  /// the level along a circle of radius cornerRadius() for a cable that resists bending.
  void layFree(Cable& cable, const Position& spool, double length) const;
  /// The radius a free end turns onto the seabed or the surface with, `length` deployed: 0 for a cable that does not
  /// resist bending, else (EI / |w|)^(1/3), the length over which a heavy rod's weight bends it (w its mean net
  /// weight in water beyond the spool's drop in air), at most `length` (a weightless cable's) [m].
  double cornerRadius(const Cable& cable, double drop_in_air, double length) const;
  /// Net weight in water, down positive, of the deployed cable beyond arc length `from` off the spool: its
  /// segments' (cable.loading's, else weight_in_water) and its attachments' [N].
  double netWeightBeyond(const Cable& cable, double from) const;
  /// The unit vector slack hangs towards: down, normal to the chord (sideways for a vertical chord).
  static Position slackSide(const Position& direction);
  /// Lays the deployed particles along the arc or the two legs bowed towards the unit vector `side`.
  void lay(Cable& cable, const Chord& chord, const Position& side) const;
  static void layOnArc(Cable& cable, const Chord& chord, const Position& side);
  static void layOnLegs(Cable& cable, const Chord& chord, const Position& apex);
  /// Lowest z of the free deployed particles (those after the outlet) [m].
  static double lowest(const Cable& cable);
  /// The slack bowed sideways, level across the chord, and what is still below seabed_z put on it.
  void bowAboveSeabed(Cable& cable, const Chord& chord) const;

  /// The cable resists bending (slack is laid on an arc, a free end turns onto the level on one).
  bool elastic() const { return stiffness_ > 0.0; }

  double stiffness_;  ///< The cable's largest EI, 0 when it does not resist bending (or the solver bends none) [N m^2].
  double weight_;     ///< weight_in_water of a uniform cable (no cable.loading) [N/m].
  double seabed_z_;   ///< The flat seabed's height, NaN for none [m].
  double surface_z_;  ///< The water surface's height, NaN for none [m].
};

}  // namespace rov_tether
