#include "cable_layout.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace rov_tether
{
namespace
{

/// A quarter turn [rad].
constexpr double kQuarterTurn = 1.57079632679489661923;

/// A polygon inscribed in a circular arc from `from` to `to` (`distance` apart), bulging towards the unit
/// vector `side` (normal to the chord), whose chords are the segments' rest lengths, so the cable starts
/// with no stretch and no kink. A chord l subtends 2 asin(l / 2R) of the circle; the radius R is found by
/// bisection so that the polygon's ends are `distance` apart, 2 R sin(theta / 2) = distance with theta the
/// sum of the chords' angles, below a full turn (the ends close in monotonically as R shrinks to there).
class InscribedArc
{
 public:
  InscribedArc(const Position& from, const Position& to, const Position& side, const double* rest, std::size_t count,
               double distance)
      : side_(side), rest_(rest), count_(count)
  {
    direction_ = distance > 1e-9 ? Position((to - from) / distance) : Position::UnitX();
    double longest = 0.0, length = 0.0;
    for (std::size_t k = 0; k < count; ++k)
    {
      longest = std::max(longest, rest[k]);
      length += rest[k];
    }
    // R from a full turn (the ends meet) to a nearly straight polygon.
    double lo = 0.5 * longest, hi = 1e6 * std::max(length, 1e-9);
    for (int k = 0; k < 200 && total(lo) > 2.0 * kPi; ++k)
    {
      lo *= 1.01;
    }
    for (int k = 0; k < 200; ++k)
    {
      const double r = std::sqrt(lo * hi);  // bisection on log R: R spans many decades
      (reach(r) > distance ? hi : lo) = r;
    }
    radius_ = std::sqrt(lo * hi);
    const double half = 0.5 * total(radius_);
    start_ = -half;
    centre_ = 0.5 * (from + to) - side * (radius_ * std::cos(half));
  }

  /// The angle of the first vertex, and that of each chord: vertex k is at start() plus the first k angles.
  double start() const { return start_; }
  double angleOf(double chord) const { return chordAngle(chord, radius_); }
  /// The point of the circle at angle theta.
  Position at(double theta) const
  {
    return centre_ + radius_ * (std::sin(theta) * direction_ + std::cos(theta) * side_);
  }

 private:
  static constexpr double kPi = 3.14159265358979323846;
  static double chordAngle(double chord, double radius)
  {
    return 2.0 * std::asin(std::min(chord / (2.0 * radius), 1.0));
  }
  double total(double radius) const
  {
    double sum = 0.0;
    for (std::size_t k = 0; k < count_; ++k)
    {
      sum += chordAngle(rest_[k], radius);
    }
    return sum;
  }
  double reach(double radius) const { return 2.0 * radius * std::sin(0.5 * std::min(total(radius), 2.0 * kPi)); }

  Position side_;
  const double* rest_;
  std::size_t count_;
  Position direction_ = Position::UnitX();
  Position centre_ = Position::Zero();
  double radius_ = 1.0;
  double start_ = 0.0;
};

}  // namespace

CableLayout::CableLayout(const TetherParams& params)
    : stiffness_(params.elasticBending() && (params.solver == SolverType::kDirect || params.solver == SolverType::kXpbd)
                     ? params.largestBendingStiffness()
                     : 0.0),
      weight_(params.weight_in_water),
      seabed_z_(params.seabed_z),
      surface_z_(params.water_surface_z)
{
}

void CableLayout::layOut(Cable& cable, const Position& spool, const Position* vehicle, double length) const
{
  for (std::size_t i = 0; i <= cable.first; ++i)
  {
    cable.place(i, spool);
  }
  if (vehicle == nullptr)
  {
    layFree(cable, spool, length);
    return;
  }
  const Chord chord = chordOf(spool, *vehicle, length);
  lay(cable, chord, slackSide(chord.direction));
  if (std::isfinite(seabed_z_) && chord.offset > 0.0 && lowest(cable) < seabed_z_)
  {
    bowAboveSeabed(cable, chord);
  }
  cable.place(cable.size() - 1, *vehicle);
}

CableLayout::Chord CableLayout::chordOf(const Position& spool, const Position& vehicle, double length)
{
  Chord chord;
  chord.spool = spool;
  chord.length = length;
  chord.end = vehicle;
  const Position span = chord.end - spool;
  chord.distance = span.norm();
  chord.middle = spool + 0.5 * span;  // taut or stretched: a straight line
  chord.direction = chord.distance > 1e-9 ? Position(span / chord.distance) : Position::UnitX();
  // The V's legs are each half the cable: the apex is sqrt((L/2)^2 - (d/2)^2) off the chord's middle.
  chord.offset = chord.distance < length
                     ? std::sqrt(std::max(0.25 * (length * length - chord.distance * chord.distance), 0.0))
                     : 0.0;
  return chord;
}

void CableLayout::layFree(Cable& cable, const Position& spool, double length) const
{
  // Above the surface every cable is heavy (its weight in air): it hangs down to the water first. Below it, what
  // is left of the cable rises when its net weight in water is negative, else sinks.
  const bool in_air = spool.z() > surface_z_;  // false without a surface (NaN)
  const double drop_in_air = in_air ? spool.z() - surface_z_ : 0.0;
  const bool rises = netWeightBeyond(cable, drop_in_air) < 0.0;
  const double inf = std::numeric_limits<double>::infinity();
  const double to_seabed = std::isfinite(seabed_z_) ? std::max(spool.z() - seabed_z_, 0.0) : inf;
  const double to_surface = std::isfinite(surface_z_) ? std::max(surface_z_ - spool.z(), 0.0) : inf;
  const double up = rises && !in_air ? 1.0 : -1.0;
  const double vertical = rises ? (in_air ? drop_in_air : to_surface) : to_seabed;
  if (vertical >= length)
  {
    // Straight up or down, all of it: as a free end was laid before surface and seabed were heeded, to the bit.
    Chord chord;
    chord.spool = spool;
    chord.length = length;
    chord.end = spool + up * length * Position::UnitZ();
    chord.middle = 0.5 * (spool + chord.end);
    layOnLegs(cable, chord, chord.middle);
    return;
  }
  // Up or down to the surface or the seabed it stops at, then along it in +x. A cable that resists bending turns
  // onto the level along a circle of radius r tangent to it (r 0: a corner): from the vertical where the drop is
  // r or more, else from the spool itself at the angle that circle has there, so there is no corner either way.
  // A cable too short for the whole path ends on the arc.
  const double r = cornerRadius(cable, drop_in_air, length);
  const double start = r > vertical ? std::asin(1.0 - vertical / r) : 0.0;  // the circle's angle at the arc's start
  const double straight = std::max(vertical - r, 0.0), turned = r * (kQuarterTurn - start);
  double arc = 0.0;
  for (std::size_t i = cable.first; i < cable.size(); ++i)
  {
    const double angle = r > 0.0 ? start + std::clamp(arc - straight, 0.0, turned) / r : 0.0;
    const double rise = std::min(arc, straight) + r * (std::sin(angle) - std::sin(start));
    const double run = r * (std::cos(start) - std::cos(angle)) + std::max(arc - straight - turned, 0.0);
    cable.place(i, Position(spool.x() + run, spool.y(), spool.z() + up * rise));
    arc += i + 1 < cable.size() ? cable.rest[i] : 0.0;
  }
}

double CableLayout::cornerRadius(const Cable& cable, double drop_in_air, double length) const
{
  if (!elastic())
  {
    return 0.0;
  }
  // A weightless cable has no length its weight bends it over: the whole cable's (as a heavy one's is at most).
  const double weight = std::abs(netWeightBeyond(cable, drop_in_air)) / std::max(length - drop_in_air, 1e-9);
  return weight > 0.0 ? std::min(std::cbrt(stiffness_ / weight), length) : length;
}

double CableLayout::netWeightBeyond(const Cable& cable, double from) const
{
  const CableLoading& load = cable.loading;
  double weight = 0.0, arc = 0.0;
  for (std::size_t j = cable.first; j + 1 < cable.size(); ++j)
  {
    const double beyond = std::clamp(arc + cable.rest[j] - from, 0.0, cable.rest[j]);  // of segment j
    weight += (load.empty() ? weight_ : load.weight[j]) * beyond;
    arc += cable.rest[j];
    if (!load.empty() && arc > from)
    {
      weight -= load.point_force[j + 1];  // an attachment's net buoyancy on particle j + 1, up positive
    }
  }
  return weight;
}

Position CableLayout::slackSide(const Position& direction)
{
  // Slack hangs below the chord (sideways when the chord is vertical).
  Position down = -Position::UnitZ() + direction * direction.z();
  if (down.norm() < 0.1)
  {
    down = Position::UnitX() - direction * direction.x();
  }
  return down.normalized();
}

void CableLayout::lay(Cable& cable, const Chord& chord, const Position& side) const
{
  if (elastic() && chord.offset > 0.0 && cable.size() > cable.first + 1)
  {
    layOnArc(cable, chord, side);
  }
  else
  {
    layOnLegs(cable, chord, chord.middle + chord.offset * side);
  }
}

void CableLayout::layOnArc(Cable& cable, const Chord& chord, const Position& side)
{
  const std::size_t n = cable.size();
  const std::size_t f = cable.first;
  const InscribedArc shape(chord.spool, chord.end, side, &cable.rest[f], n - 1 - f, chord.distance);
  double theta = shape.start();
  for (std::size_t i = f; i < n; ++i)
  {
    cable.place(i, shape.at(theta));
    theta += i + 1 < n ? shape.angleOf(cable.rest[i]) : 0.0;
  }
}

void CableLayout::layOnLegs(Cable& cable, const Chord& chord, const Position& apex)
{
  const std::size_t n = cable.size();
  const double length = chord.length;
  double arc = 0.0;
  for (std::size_t i = cable.first; i < n; ++i)
  {
    const double fraction = length > 0.0 ? std::min(arc / length, 1.0) : 0.0;
    cable.place(i, fraction <= 0.5 ? Position(chord.spool + 2.0 * fraction * (apex - chord.spool))
                                   : Position(apex + (2.0 * fraction - 1.0) * (chord.end - apex)));
    if (i + 1 < n)
    {
      arc += cable.rest[i];
    }
  }
}

double CableLayout::lowest(const Cable& cable)
{
  double z = std::numeric_limits<double>::infinity();
  for (std::size_t i = cable.first + 1; i < cable.size(); ++i)
  {
    z = std::min(z, cable.z[i]);
  }
  return z;
}

void CableLayout::bowAboveSeabed(Cable& cable, const Chord& chord) const
{
  // Hanging down, the slack would go through the flat seabed: bowed sideways instead, level across the chord,
  // from where it sinks onto the seabed. (Laid through it, the seabed's projection flattened metres of sag in
  // one step; a rod folded, its solve failed, and the recovery laid it out the same way again.) An arc of
  // more than half a circle still reaches past its lower end along a sloping chord: what of it is below the
  // seabed (centimetres) is put on it.
  const Position level = chord.direction.cross(Position::UnitZ());
  lay(cable, chord, level.norm() > 1e-6 ? Position(level.normalized()) : Position(Position::UnitX()));
  for (std::size_t i = cable.first + 1; i < cable.size(); ++i)
  {
    cable.z[i] = cable.pz[i] = std::max(cable.z[i], seabed_z_);
  }
}

}  // namespace rov_tether
