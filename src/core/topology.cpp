#include "rov_tether/core/topology.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace rov_tether::topology
{
namespace
{

constexpr double kPi = 3.14159265358979323846;

/// Point i of the closed curve: the polyline's points, then its first again (the closing chord).
Position closedAt(const Polyline& c, std::size_t i) { return c.at(i < c.count ? i : 0); }

/// Squared distance from q to the segment [a, b].
double segmentDistanceSquared(const Eigen::Vector2d& q, const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  const Eigen::Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double s = length2 > 0.0 ? std::clamp((q - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (a + s * ab - q).squaredNorm();
}

/// asin clamped to its domain (rounding can put a dot product of unit vectors just beyond 1).
double safeAsin(double v) { return std::asin(std::clamp(v, -1.0, 1.0)); }

/// The signed solid angle, over 4 pi, that segment [p1, p2] and segment [p3, p4] subtend of each other
/// (Klenin and Langowski 2000; docs/references.md). 0 for segments in one plane.
double pairLinking(const Position& p1, const Position& p2, const Position& p3, const Position& p4)
{
  const Position r13 = p3 - p1, r14 = p4 - p1, r23 = p3 - p2, r24 = p4 - p2;
  Position n[4] = {r13.cross(r14), r14.cross(r24), r24.cross(r23), r23.cross(r13)};
  for (Position& v : n)
  {
    const double length = v.norm();
    if (!(length > 1e-300))
    {
      return 0.0;  // a degenerate quadrilateral (touching or collinear segments): no solid angle
    }
    v /= length;
  }
  const double omega =
      safeAsin(n[0].dot(n[1])) + safeAsin(n[1].dot(n[2])) + safeAsin(n[2].dot(n[3])) + safeAsin(n[3].dot(n[0]));
  const double orientation = (p4 - p3).cross(p2 - p1).dot(r13);
  return orientation > 0.0 ? omega / (4.0 * kPi) : orientation < 0.0 ? -omega / (4.0 * kPi) : 0.0;
}

/// The signed angle [rad] the polyline sweeps around the line through `point` along `axis`, closed by its
/// chord back to the first point when `closed`; NaN where windingTurns and windingAngle say.
double sweptAngle(const Polyline& curve, const Position& point, const Position& axis, double clearance, bool closed)
{
  const double length = axis.norm();
  if (curve.count < 2 || !(length > 0.0))
  {
    return std::numeric_limits<double>::quiet_NaN();
  }
  // Coordinates in the plane across the axis: u and w, orthonormal and normal to it.
  const Position k = axis / length;
  const Position helper = std::abs(k.x()) < 0.9 ? Position::UnitX() : Position::UnitY();
  const Position u = k.cross(helper).normalized();
  const Position w = k.cross(u);
  auto project = [&](const Position& p)
  {
    const Position d = p - point;
    return Eigen::Vector2d(d.dot(u), d.dot(w));
  };
  const double clearance2 = clearance * clearance;
  double angle = 0.0;
  Eigen::Vector2d previous = project(curve.at(0));
  const std::size_t last = closed ? curve.count : curve.count - 1;
  for (std::size_t i = 1; i <= last; ++i)
  {
    const Eigen::Vector2d next = project(closedAt(curve, i));
    if (segmentDistanceSquared(Eigen::Vector2d::Zero(), previous, next) <= clearance2)
    {
      return std::numeric_limits<double>::quiet_NaN();  // the curve meets the axis: no angle
    }
    // The angle swept from `previous` to `next` as seen from the axis, in (-pi, pi): a straight segment
    // that keeps off the axis never sweeps pi or more.
    const double cross = previous.x() * next.y() - previous.y() * next.x();
    angle += std::atan2(cross, previous.dot(next));
    previous = next;
  }
  return angle;
}

}  // namespace

Polyline deployed(const Cable& cable)
{
  const std::size_t f = cable.first;
  const std::size_t n = cable.size();
  return {cable.x.data() + f, cable.y.data() + f, cable.z.data() + f, n > f ? n - f : 0};
}

double windingTurns(const Polyline& curve, const Position& point, const Position& axis, double clearance)
{
  return sweptAngle(curve, point, axis, clearance, true) / (2.0 * kPi);
}

double windingAngle(const Polyline& curve, const Position& point, const Position& axis, double clearance)
{
  return sweptAngle(curve, point, axis, clearance, false);
}

double linkingNumber(const Polyline& a, const Polyline& b)
{
  if (a.count < 2 || b.count < 2)
  {
    return 0.0;  // a point is linked with nothing
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < a.count; ++i)
  {
    const Position p1 = a.at(i), p2 = closedAt(a, i + 1);
    for (std::size_t j = 0; j < b.count; ++j)
    {
      sum += pairLinking(p1, p2, b.at(j), closedAt(b, j + 1));
    }
  }
  return sum;
}

}  // namespace rov_tether::topology
