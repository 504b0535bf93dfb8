// Wraps and links (contact issue, topology): the turns a tether makes around an axis and the Gauss linking
// number of two tethers, each closed by the chord from its vehicle end back to its spool. Both are integers
// of closed curves, so every expectation is an exact integer (up to rounding, 1e-9), from the curve's
// construction: docs/references.md, "Wraps and links".
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "rov_tether/core/cable.hpp"
#include "rov_tether/core/topology.hpp"

namespace rov_tether::test
{
namespace
{

using topology::linkingNumber;
using topology::Polyline;
using topology::windingAngle;
using topology::windingTurns;

constexpr double kPi = 3.14159265358979323846;
constexpr double kExact = 1e-9;

/// Points kept as three arrays, as a Cable keeps them.
struct Curve
{
  std::vector<double> x, y, z;

  void add(const Position& p)
  {
    x.push_back(p.x());
    y.push_back(p.y());
    z.push_back(p.z());
  }
  Polyline view() const { return {x.data(), y.data(), z.data(), x.size()}; }
  Curve reversed() const
  {
    Curve r;
    for (std::size_t i = x.size(); i-- > 0;)
    {
      r.add(Position(x[i], y[i], z[i]));
    }
    return r;
  }
};

/// A helix around the z axis through (cx, cy): `turns` turns of radius r, rising `rise` per turn,
/// counter-clockwise seen from +z, `per_turn` points a turn. Spool at its start, vehicle at its end.
Curve helix(double turns, double r, double rise, int per_turn = 64, double cx = 0.0, double cy = 0.0)
{
  Curve c;
  const int n = static_cast<int>(std::ceil(turns * per_turn));
  for (int i = 0; i <= n; ++i)
  {
    const double t = turns * 2.0 * kPi * i / n;
    c.add(Position(cx + r * std::cos(t), cy + r * std::sin(t), rise * t / (2.0 * kPi)));
  }
  return c;
}

/// A closed curve on the torus around the circle of radius R in the xy plane (its core): once along the
/// core and `k` times around it (the tube's radius r < R). It links the core k times.
Curve torusCurve(int k, double R, double r, int points = 720)
{
  Curve c;
  for (int i = 0; i < points; ++i)
  {
    const double t = 2.0 * kPi * i / points;
    const double rho = R + r * std::cos(k * t);
    c.add(Position(rho * std::cos(t), rho * std::sin(t), r * std::sin(k * t)));
  }
  return c;
}

/// A circle of radius R in the plane through `centre` normal to `normal` (counter-clockwise about it).
Curve circle(const Position& centre, const Position& normal, double R, int points = 360)
{
  const Position k = normal.normalized();
  const Position u = k.cross(std::abs(k.x()) < 0.9 ? Position::UnitX() : Position::UnitY()).normalized();
  const Position w = k.cross(u);
  Curve c;
  for (int i = 0; i < points; ++i)
  {
    const double t = 2.0 * kPi * i / points;
    c.add(centre + R * (std::cos(t) * u + std::sin(t) * w));
  }
  return c;
}

}  // namespace

// A tether wound n times around a vertical pillar reads n turns, the sign from the sense of winding,
// whatever the pillar's axis vector length or which way up it points (reversing the axis flips the sign).
TEST(Topology, TetherWoundAroundAPillarReadsItsTurns)
{
  const Position pillar(3.0, -2.0, 0.0);
  for (int turns = 1; turns <= 3; ++turns)
  {
    const Curve c = helix(turns, 1.5, 0.4, 64, pillar.x(), pillar.y());
    EXPECT_NEAR(windingTurns(c.view(), pillar, Position(0.0, 0.0, 1.0)), turns, kExact);
    EXPECT_NEAR(windingTurns(c.view(), pillar, Position(0.0, 0.0, -7.0)), -turns, kExact);
    EXPECT_NEAR(windingTurns(c.reversed().view(), pillar, Position(0.0, 0.0, 1.0)), -turns, kExact);
  }
  // Half a turn ends diametrically opposite its start: the closing chord passes through the pillar's axis,
  // where the count is not defined (NaN, not a guess).
  const Curve half = helix(0.5, 1.5, 0.4, 64, pillar.x(), pillar.y());
  EXPECT_TRUE(std::isnan(windingTurns(half.view(), pillar, Position(0.0, 0.0, 1.0))));
}

// A cable wound a known angle round a pillar reads that angle [rad], not closed by a chord: a helix whose
// points all lie on a circle round the axis sweeps exactly its parameter's range (each straight segment
// between two points of the circle sweeps their angle apart, seen from its centre), so the expectations are
// exact up to rounding. Half a turn reads pi where windingTurns has no value (its chord crosses the axis),
// three quarters 1.5 pi where windingTurns reads a whole turn (the chord closes it one way): the angle is what
// shows the wrap building up. The sign follows the sense of winding and the axis' direction, as the turns'.
TEST(Topology, CableWoundAKnownAngleAroundAPillarReadsThatAngle)
{
  const Position pillar(3.0, -2.0, 0.0);
  const Position up(0.0, 0.0, 1.0);
  for (const double angle : {0.3, kPi / 2.0, 3.0, kPi, 1.5 * kPi, 2.0 * kPi, 2.5 * kPi, 6.0 * kPi + 1.0})
  {
    const Curve c = helix(angle / (2.0 * kPi), 1.5, 0.4, 64, pillar.x(), pillar.y());
    EXPECT_NEAR(windingAngle(c.view(), pillar, up), angle, kExact) << angle;
    EXPECT_NEAR(windingAngle(c.view(), pillar, -3.0 * up), -angle, kExact) << angle;
    EXPECT_NEAR(windingAngle(c.reversed().view(), pillar, up), -angle, kExact) << angle;
  }
  EXPECT_TRUE(std::isnan(windingTurns(helix(0.5, 1.5, 0.4, 64, pillar.x(), pillar.y()).view(), pillar, up)));
  EXPECT_NEAR(windingTurns(helix(0.75, 1.5, 0.4, 64, pillar.x(), pillar.y()).view(), pillar, up), 1.0, kExact);
  // Once round and back the same way sweeps nothing; a loop beside the pillar sweeps nothing.
  Curve there_and_back = helix(1.0, 2.0, 0.0, 64);
  const Curve back = helix(1.0, 2.5, 0.0, 64).reversed();
  for (std::size_t i = 0; i < back.x.size(); ++i)
  {
    there_and_back.add(Position(back.x[i], back.y[i], 1.0));
  }
  EXPECT_NEAR(windingAngle(there_and_back.view(), Position::Zero(), up), 0.0, kExact);
  EXPECT_NEAR(windingAngle(helix(1.0, 2.0, 0.3, 64, 10.0, 0.0).view(), Position::Zero(), up), 0.0, kExact);
  // A cable through the axis has no angle; the chord does not count (a half turn's chord crosses it).
  Curve through;
  through.add(Position(-1.0, 0.0, 0.0));
  through.add(Position(1.0, 0.0, 0.0));
  EXPECT_TRUE(std::isnan(windingAngle(through.view(), Position::Zero(), up)));
  EXPECT_FALSE(std::isnan(windingAngle(helix(0.5, 1.5, 0.4, 64).view(), Position::Zero(), up)));
  Curve point;
  point.add(Position(1.0, 0.0, 0.0));
  EXPECT_TRUE(std::isnan(windingAngle(point.view(), Position::Zero(), up)));
}

// Around the pillar and back the same way: 0. Around and held on the far side: the chord closes it
// around the pillar, 1. A tether that never goes around: 0.
TEST(Topology, GoingAroundAndBackReadsZero)
{
  const Position pillar(0.0, 0.0, 0.0);
  const Position up(0.0, 0.0, 1.0);
  Curve there_and_back = helix(1.0, 2.0, 0.0, 64);
  const Curve back = helix(1.0, 2.5, 0.0, 64).reversed();  // back the other way, a little further out
  for (std::size_t i = 0; i < back.x.size(); ++i)
  {
    there_and_back.add(Position(back.x[i], back.y[i], 1.0));
  }
  EXPECT_NEAR(windingTurns(there_and_back.view(), pillar, up), 0.0, kExact);
  const Curve beside = helix(1.0, 2.0, 0.3, 64, 10.0, 0.0);  // a loop 10 m off the pillar
  EXPECT_NEAR(windingTurns(beside.view(), pillar, up), 0.0, kExact);
}

// Two rings linked once (the Hopf link): +-1, the sign flipping with either ring's direction; rings
// apart: 0. The linking number is symmetric.
TEST(Topology, HopfLinkIsOneAndRingsApartAreZero)
{
  const Curve a = circle(Position(0.0, 0.0, 0.0), Position(0.0, 0.0, 1.0), 1.0);
  const Curve b = circle(Position(1.0, 0.0, 0.0), Position(0.0, 1.0, 0.0), 1.0);
  const double lk = linkingNumber(a.view(), b.view());
  EXPECT_NEAR(std::abs(lk), 1.0, kExact);
  EXPECT_NEAR(linkingNumber(b.view(), a.view()), lk, kExact);
  EXPECT_NEAR(linkingNumber(a.reversed().view(), b.view()), -lk, kExact);
  const Curve apart = circle(Position(5.0, 0.0, 0.0), Position(0.0, 1.0, 0.0), 1.0);
  EXPECT_NEAR(linkingNumber(a.view(), apart.view()), 0.0, kExact);
}

// A curve winding k times around a ring's core links it k times (k = 1, 2, 3), with the sign of winding.
TEST(Topology, CurveWindingKTimesAroundARingLinksItKTimes)
{
  const Curve core = circle(Position::Zero(), Position(0.0, 0.0, 1.0), 2.0);
  double sign = 0.0;
  for (int k = 1; k <= 3; ++k)
  {
    const double lk = linkingNumber(core.view(), torusCurve(k, 2.0, 0.5).view());
    std::printf("[ measured ] ring and a curve winding %d times around its core: linking number %.12f\n", k, lk);
    EXPECT_NEAR(std::abs(lk), k, kExact);
    sign = sign == 0.0 ? std::copysign(1.0, lk) : sign;
    EXPECT_EQ(std::copysign(1.0, lk), sign);  // one sense of winding, one sign
  }
}

// The two measures agree: a closed curve's linking number with a long, thin rectangle along an axis (a
// line closed far away) equals its turns around that axis, with the same sign convention (right hand:
// counter-clockwise about the axis is positive).
TEST(Topology, LinkingWithALineIsTheTurnsAroundIt)
{
  const Curve wound = helix(2.0, 1.0, 0.2, 64);
  Curve line;  // up the z axis from -1 km to 1 km, back down 1 mm beside it... far away: 2 km off
  line.add(Position(0.0, 0.0, -1000.0));
  line.add(Position(0.0, 0.0, 1000.0));
  line.add(Position(2000.0, 0.0, 1000.0));
  line.add(Position(2000.0, 0.0, -1000.0));
  const double turns = windingTurns(wound.view(), Position::Zero(), Position(0.0, 0.0, 1.0));
  const double lk = linkingNumber(wound.view(), line.view());
  EXPECT_NEAR(turns, 2.0, kExact);
  EXPECT_NEAR(lk, turns, 1e-3);  // the rectangle's far sides subtend about (r / 1 km)^2 of the sphere
}

// The deployed part of a cable is what is measured: particles still on the spool are not.
TEST(Topology, DeployedViewStartsAtTheSpoolOutlet)
{
  Cable cable;
  cable.resize(6);
  for (std::size_t i = 0; i < 6; ++i)
  {
    cable.place(i, Position(static_cast<double>(i), 0.0, 0.0));
  }
  cable.first = 2;
  const Polyline p = topology::deployed(cable);
  ASSERT_EQ(p.count, 4u);
  EXPECT_EQ(p.at(0), Position(2.0, 0.0, 0.0));
  EXPECT_EQ(p.at(3), Position(5.0, 0.0, 0.0));
}

}  // namespace rov_tether::test
