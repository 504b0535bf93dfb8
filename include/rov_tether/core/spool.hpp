#pragma once

#include "rov_tether/core/cable.hpp"
#include "rov_tether/core/constraint_solver.hpp"

namespace rov_tether
{

/**
 * The spool: where the cable leaves it, how much is off it, and the release and take-back of particles.
 *
 * Every deployed segment but the first (at the spool) has the nominal segment length; the first takes the
 * rest and stays within [kMinFirst, kMaxFirst] segment lengths while particles can be released or taken
 * back, so a length change is smooth: the first segment grows or shrinks, never a jump of a particle. One
 * exception (payOut, `rod_on_drum`): slack paid out by a drum into a rod pushed back at the outlet piles up in the
 * first segment, whose rest length then passes 1.5 segments until the cable moves away and particles can be
 * released from it.
 */
class Spool
{
 public:
  static constexpr double kMinFirst = 0.5;
  static constexpr double kMaxFirst = 1.5;

  explicit Spool(const Position& outlet = Position::Zero()) : outlet_(outlet) {}
  /// The outlet, where particle `first` is pinned [m].
  const Position& outlet() const { return outlet_; }
  void setOutlet(const Position& outlet) { outlet_ = outlet; }
  /// Nominal segment length [m].
  void setSegmentLength(double length) { segment_ = length; }

  /// Cable off the spool: the sum of the deployed segments' rest lengths [m].
  double deployedLength(const Cable& cable) const;
  /// Sets `first` and the rest lengths for `deployed` metres off the spool (positions are not touched).
  void setDeployedLength(Cable& cable, double deployed) const;
  /// Grows (change > 0) or shrinks the first segment by `change` [m], releasing or taking back particles
  /// to keep it within its bounds; masses are updated as Cable::updateMasses does (`mass`, `last_pinned`).
  /// A released particle starts on the first segment with the velocity of the cable material there (paid-out
  /// material leaves the outlet at change / dt along the segment); both halves carry its tension. Both parts of
  /// the split segment keep its strain, but where the segments push and the first is the drum's (`rod_on_drum`: a
  /// rod, direct with bending, paid out by a drum in the solve, whose law holds no force while the segment is
  /// slack) and the first segment is slack (shorter than its rest: a coasting drum paying out into cable pushed
  /// back at the outlet): there the new segment is laid at its rest length a segment from the next particle and
  /// the slack stays in the first segment; none is released while that is shorter than a segment. Split keeping
  /// the strain, a rod's new segment would push with the compression the slack segment held at no force: up to
  /// EA.
  void payOut(Cable& cable, Multipliers& lambda, double change, const LineMass& mass, bool last_pinned,
              bool rod_on_drum = false) const;

 private:
  /// Releases particle first - 1 onto the first segment (payOut); false, nothing changed, when it cannot.
  bool release(Cable& cable, Multipliers& lambda, double change, const LineMass& mass, bool last_pinned,
               bool rod_on_drum) const;
  void merge(Cable& cable, const LineMass& mass, bool last_pinned) const;

  Position outlet_;
  double segment_ = 0.1;
};

}  // namespace rov_tether
