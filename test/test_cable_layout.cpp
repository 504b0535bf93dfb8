// CableLayout (src/core/cable_layout.hpp): where a cable is laid at rest between its spool and its vehicle,
// checked on a bare Cable against the shapes its comment promises. Bounds are geometry: a particle is on a
// line or a circle to rounding (1e-9 m over metres), a segment is never longer than its rest length (laid
// unstretched), and the legs of a V add up to the deployed length.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "cable_layout.hpp"
#include "rov_tether/core/spool.hpp"

namespace rov_tether::test
{
namespace
{

constexpr double kTight = 1e-9;  ///< Rounding over metres of cable [m].

/// A cable of `segments` segments of `segment` m, `deployed` m of it off a spool at `spool`.
struct LaidCable
{
  Cable cable;
  Spool spool;
  double length = 0.0;  ///< The deployed length the spool's rest lengths add up to [m].

  LaidCable(std::size_t segments, double segment, double deployed, const Position& outlet) : spool(outlet)
  {
    cable.resize(segments + 1);
    spool.setSegmentLength(segment);
    spool.setDeployedLength(cable, deployed);
    length = spool.deployedLength(cable);
  }
  Position at(std::size_t i) const { return cable.position(i); }
  /// Particle i's position one step ago [m].
  Position before(std::size_t i) const { return {cable.px[i], cable.py[i], cable.pz[i]}; }
  std::size_t last() const { return cable.size() - 1; }
};

/// The checks every layout keeps: the outlet and the particles on the spool at the outlet, no particle
/// moving (position = previous position), no segment longer than its rest length.
void expectAtRestFromTheSpool(const LaidCable& laid, const Position& outlet)
{
  for (std::size_t i = 0; i <= laid.cable.first; ++i)
  {
    EXPECT_LT((laid.at(i) - outlet).norm(), kTight) << "particle " << i << " on the spool";
  }
  for (std::size_t i = 0; i < laid.cable.size(); ++i)
  {
    EXPECT_EQ(laid.at(i), laid.before(i)) << "particle " << i << " laid with a velocity";
  }
}

void expectNoSegmentStretched(const LaidCable& laid)
{
  for (std::size_t j = laid.cable.first; j < laid.last(); ++j)
  {
    EXPECT_LE((laid.at(j + 1) - laid.at(j)).norm(), laid.cable.rest[j] + kTight) << "segment " << j;
  }
}

/// `params` in two sections (2 m and the rest), each of bending_stiffness `ei`.
TetherParams inSections(TetherParams params, double ei)
{
  params.sections = {{2.0, {{"bending_stiffness", ei}}},
                     {std::numeric_limits<double>::quiet_NaN(), {{"bending_stiffness", ei}}}};
  return params;
}

TetherParams legsParams()
{
  TetherParams params;
  params.bending_stiffness = 0.0;  // a cable that does not resist bending: two straight legs
  return params;
}

}  // namespace

// Taut (the spool-vehicle distance beyond the deployed length): every particle on the straight line from the
// spool to the vehicle, in order, the vehicle particle on the vehicle.
TEST(CableLayout, ATautCableLiesOnTheChordWithItsEndsOnSpoolAndVehicle)
{
  const Position outlet(1.0, 2.0, -3.0), vehicle(6.0, 2.0, -3.0);  // 5 m apart
  LaidCable laid(100, 0.1, 4.0, outlet);
  CableLayout(TetherParams()).layOut(laid.cable, outlet, &vehicle, laid.length);
  expectAtRestFromTheSpool(laid, outlet);
  EXPECT_EQ(laid.at(laid.last()), vehicle);  // pinned on the vehicle
  const Position direction = (vehicle - outlet).normalized();
  double previous = -1.0;
  for (std::size_t i = laid.cable.first; i < laid.cable.size(); ++i)
  {
    const Position from_spool = laid.at(i) - outlet;
    EXPECT_LT(from_spool.cross(direction).norm(), kTight) << "particle " << i << " off the chord";
    EXPECT_GT(from_spool.dot(direction), previous) << "particle " << i << " out of order";
    previous = from_spool.dot(direction);
  }
}

/// ASlackCableHangsOnTwoLegsAsLongAsTheCable with `params`.
void slackCableHangsOnTwoLegs(const TetherParams& params)
{
  const Position outlet(0.0, 0.0, -1.0), vehicle(6.0, 0.0, -1.0);
  LaidCable laid(100, 0.1, 10.0, outlet);
  CableLayout(params).layOut(laid.cable, outlet, &vehicle, laid.length);
  expectAtRestFromTheSpool(laid, outlet);
  expectNoSegmentStretched(laid);
  EXPECT_EQ(laid.at(laid.last()), vehicle);  // pinned on the vehicle
  // Legs of 5 m over a 6 m chord: the apex 4 m below its middle (3-4-5).
  const Position apex(3.0, 0.0, -5.0);
  double lowest = 0.0;
  for (std::size_t i = laid.cable.first; i < laid.cable.size(); ++i)
  {
    const Position p = laid.at(i);
    const Position& leg_start = p.x() <= 3.0 ? outlet : vehicle;
    EXPECT_LT((p - leg_start).cross((apex - leg_start).normalized()).norm(), kTight) << "particle " << i;
    EXPECT_NEAR(p.y(), 0.0, kTight);
    lowest = std::min(lowest, p.z());
  }
  EXPECT_NEAR(lowest, apex.z(), 1e-3);  // a particle at the apex (the legs are 50 segments each)
  EXPECT_NEAR((apex - outlet).norm() + (vehicle - apex).norm(), laid.length, kTight);
}

// Slack, for a cable that does not resist bending: two straight legs spool -> apex -> vehicle, as long as the
// deployed length, the apex straight below the chord's middle; no segment stretched.
TEST(CableLayout, ASlackCableHangsOnTwoLegsAsLongAsTheCable)
{
  // The tether's EI 0, or every section's 0 under the tether's default (the lay-out reads the cable's EI,
  // TetherParams::elasticBending(): it read the tether's alone, and bowed such a cable on an arc).
  for (const TetherParams& params : {legsParams(), inSections(TetherParams(), 0.0)})
  {
    SCOPED_TRACE(params.sections.empty() ? "no sections" : "EI 0 in every section");
    slackCableHangsOnTwoLegs(params);
  }
}

/// ASlackRodLiesOnAnArcWithEverySegmentAtItsRestLength with `params`.
void slackRodLiesOnAnArc(const TetherParams& params)
{
  const Position outlet(0.0, 0.0, -1.0), vehicle(3.0, 0.0, -2.0);
  LaidCable laid(60, 0.1, 5.125, outlet);  // a first segment of 0.125 m: the arc takes unequal chords
  CableLayout(params).layOut(laid.cable, outlet, &vehicle, laid.length);
  expectAtRestFromTheSpool(laid, outlet);
  EXPECT_EQ(laid.at(laid.last()), vehicle);  // pinned on it, not the arc's end found by bisection
  for (std::size_t j = laid.cable.first; j < laid.last(); ++j)
  {
    EXPECT_NEAR((laid.at(j + 1) - laid.at(j)).norm(), laid.cable.rest[j], 1e-6) << "segment " << j;
  }
  // On one circle: the centre is equidistant from the two ends and the middle particle.
  const std::size_t f = laid.cable.first, mid = (f + laid.last()) / 2;
  const Position a = laid.at(f), b = laid.at(mid), c = laid.at(laid.last());
  const Position normal = (b - a).cross(c - a);
  const Position centre =
      a + ((c - a).squaredNorm() * normal.cross(b - a) + (b - a).squaredNorm() * (c - a).cross(normal)) /
              (2.0 * normal.squaredNorm());
  const double radius = (a - centre).norm();
  for (std::size_t i = f; i < laid.cable.size(); ++i)
  {
    EXPECT_NEAR((laid.at(i) - centre).norm(), radius, 1e-6) << "particle " << i;
    EXPECT_NEAR(laid.at(i).y(), 0.0, kTight) << "particle " << i;  // in the vertical plane of the chord
  }
  EXPECT_LT(laid.at(mid).z(), std::min(outlet.z(), vehicle.z()));  // bowed down, below the chord
}

// Slack, for a cable that resists bending (direct with EI > 0, on the tether or in its sections): on a circular arc
// below the chord, each segment exactly its rest length (no stretch, no kink), from the spool to the vehicle.
TEST(CableLayout, ASlackRodLiesOnAnArcWithEverySegmentAtItsRestLength)
{
  // The tether's EI, or EI only in its sections (the tether's 0): the lay-out reads the cable's EI.
  TetherParams limp;
  limp.bending_stiffness = 0.0;
  for (const TetherParams& params : {TetherParams(), inSections(limp, 0.2)})
  {
    SCOPED_TRACE(params.sections.empty() ? "no sections" : "EI only in the sections");
    slackRodLiesOnAnArc(params);
  }
}

// Slack that would hang through the flat seabed: bowed sideways, and nothing below seabed_z. 20 m over 12 m
// would hang 6-7 m below the chord; 40 m, as a rod, is an arc of more than half a circle, whose level bow
// still reaches past the vehicle's end down the sloping chord, below the seabed unless put on it.
TEST(CableLayout, SlackThatWouldHangThroughTheSeabedIsBowedSidewaysAboveIt)
{
  for (const double length : {20.0, 40.0})
  {
    for (const double ei : {0.0, 0.2})
    {
      TetherParams params;
      params.bending_stiffness = ei;
      params.seabed_z = -5.0;
      const Position outlet(0.0, 0.0, -4.0), vehicle(12.0, 0.0, -4.99);
      LaidCable laid(400, 0.1, length, outlet);
      CableLayout(params).layOut(laid.cable, outlet, &vehicle, laid.length);
      expectAtRestFromTheSpool(laid, outlet);
      expectNoSegmentStretched(laid);
      double widest = 0.0;
      for (std::size_t i = laid.cable.first; i < laid.cable.size(); ++i)
      {
        EXPECT_GE(laid.at(i).z(), params.seabed_z) << length << " m, EI " << ei << ", particle " << i;
        widest = std::max(widest, std::abs(laid.at(i).y()));
      }
      EXPECT_GT(widest, 5.0) << length << " m, EI " << ei << ": not bowed sideways";
    }
  }
}

// No vehicle: straight down from the spool, the deployed length long; up for a cable lighter than water.
TEST(CableLayout, AFreeEndHangsStraightDownOrFloatsStraightUp)
{
  for (const double weight : {1.0, -1.0})
  {
    TetherParams params;
    params.weight_in_water = weight;
    const Position outlet(2.0, -1.0, 0.0);
    LaidCable laid(50, 0.1, 3.0, outlet);
    CableLayout(params).layOut(laid.cable, outlet, nullptr, laid.length);
    expectAtRestFromTheSpool(laid, outlet);
    const double up = weight < 0.0 ? 1.0 : -1.0;
    double arc = 0.0;
    for (std::size_t i = laid.cable.first; i < laid.cable.size(); ++i)
    {
      EXPECT_LT((laid.at(i) - (outlet + up * arc * Position::UnitZ())).norm(), kTight)
          << "weight " << weight << ", particle " << i;
      arc += i + 1 < laid.cable.size() ? laid.cable.rest[i] : 0.0;
    }
  }
}

}  // namespace rov_tether::test
