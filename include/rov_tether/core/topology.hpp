#pragma once
/**
 * Topology of tethers: how many turns a tether makes around an axis (a pillar, a riser, a vehicle's
 * thruster guard) and how two tethers are linked. Both are properties of closed curves, so a tether is
 * closed by the straight chord from its vehicle end back to its spool: a tether that goes around a pillar
 * and comes back the same way reads 0 turns, one that stays wrapped reads 1.
 *
 * Pure geometry over a polyline (no Cable, no solver): the contact work calls it with the deployed
 * particles of each tether. Nothing here allocates. Closed forms and sources: docs/references.md,
 * "Wraps and links".
 */

#include <cstddef>

#include "rov_tether/core/cable.hpp"

namespace rov_tether::topology
{

/// A read-only view of points `first` .. `first + count - 1` of three coordinate arrays (a Cable's
/// deployed particles, or any polyline).
struct Polyline
{
  const double* x = nullptr;
  const double* y = nullptr;
  const double* z = nullptr;
  std::size_t count = 0;

  Position at(std::size_t i) const { return {x[i], y[i], z[i]}; }
};

/// The deployed part of a cable, spool outlet first, vehicle end last.
Polyline deployed(const Cable& cable);

/// The signed number of turns the polyline, closed by the chord from its last point back to its first,
/// makes around the infinite line through `point` along `axis` (any length, not zero); positive counter-
/// clockwise seen from the tip of `axis`. An integer, up to rounding, for a curve that keeps off the
/// line. NaN when a point of the curve or of its closing chord lies within `clearance` [m] of the line,
/// where the count is not defined.
double windingTurns(const Polyline& curve, const Position& point, const Position& axis, double clearance = 1e-9);

/// The signed angle [rad] the open polyline, from its first point to its last (no closing chord), sweeps
/// around the same line; positive counter-clockwise seen from the tip of `axis`. It grows continuously as a
/// tether is wound: pi half way round a pillar, 2 pi once round, 1.5 pi for three quarters, where
/// windingTurns already reads 0 or 1 (its chord closes the curve one way or the other). NaN when a point of
/// the curve (not of the chord) lies within `clearance` [m] of the line, or for fewer than two points.
double windingAngle(const Polyline& curve, const Position& point, const Position& axis, double clearance = 1e-9);

/// The Gauss linking number of two polylines, each closed by its own chord: the sum over every pair of
/// segments of the signed solid angle one subtends from the other, over 4 pi (exact for polygons). An
/// integer, up to rounding, when neither closed curve passes through the other; 0 for curves that can be
/// pulled apart, +-1 for two rings linked once, +-k for a curve winding k times around the other's core.
/// O(n m), four arcsines a pair: 100 by 100 segments take 0.5 ms, 1,000 by 1,000 47 ms (BM_LinkingNumber).
double linkingNumber(const Polyline& a, const Polyline& b);

}  // namespace rov_tether::topology
