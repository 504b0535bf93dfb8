// CableLayout (src/core/cable_layout.hpp): where a cable is laid at rest between its spool and its vehicle,
// checked on a bare Cable against the shapes its comment promises. Bounds are geometry: a particle is on a
// line or a circle to rounding (1e-9 m over metres), a segment is never longer than its rest length (laid
// unstretched), and the legs of a V add up to the deployed length.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "cable_layout.hpp"
#include "rov_tether/core/cable_sections.hpp"
#include "rov_tether/core/spool.hpp"

namespace rov_tether::test
{
namespace
{

constexpr double kTight = 1e-9;  ///< Rounding over metres of cable [m].
constexpr double kInf = std::numeric_limits<double>::infinity();

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

/// The path a free end off `outlet` is laid along: `vertical` m straight up (`up` 1) or down (-1), then level along
/// +x, turning onto the level along a circle of radius r (0: a corner) tangent to it: from the vertical when the
/// drop is r or more, else from the outlet itself, where the circle through it meets the level tangentially.
struct FreeEndPath
{
  Position outlet;
  double up, vertical, r;
  double start() const { return r > vertical ? std::asin(1.0 - vertical / r) : 0.0; }  // the circle's angle there
  double straight() const { return std::max(vertical - r, 0.0); }
  double turned() const { return r * (0.5 * M_PI - start()); }
  /// The point at arc length s.
  Position at(double s) const
  {
    if (s <= straight())
    {
      return outlet + Position(0.0, 0.0, up * s);
    }
    if (s <= straight() + turned())
    {
      const double angle = start() + (s - straight()) / r;
      return outlet + Position(r * (std::cos(start()) - std::cos(angle)), 0.0,
                               up * (straight() + r * (std::sin(angle) - std::sin(start()))));
    }
    return outlet + Position(r * std::cos(start()) + (s - straight() - turned()), 0.0, up * vertical);
  }
};

/// The largest angle between two consecutive deployed segments [rad].
double sharpestTurn(const LaidCable& laid)
{
  double sharpest = 0.0;
  for (std::size_t j = laid.cable.first; j + 2 < laid.cable.size(); ++j)
  {
    const Position a = laid.at(j + 1) - laid.at(j), b = laid.at(j + 2) - laid.at(j + 1);
    sharpest = std::max(sharpest, std::atan2(a.cross(b).norm(), a.dot(b)));
  }
  return sharpest;
}

// A free end is laid where it settles, the deployed length along its rest lengths: a buoyant one up to the
// surface and along it, a heavy one down to the seabed and along it, in +x; from a spool above the surface
// (a deck) any cable hangs down to the water first (it is heavy in air). Each particle on that path to
// rounding, none above the surface nor below the seabed by more than that, no segment stretched. Seen failing
// before the free end heeded them (laid straight up or down all 30 m: 20 m above the surface, 26 and 14 m below the
// seabed, the deck's buoyant cable 32 m above the surface). A cable that does not resist bending turns a corner; one
// that does (the default EI 0.2 N m^2, and 50 N m^2) turns along a circle of radius (EI / |w|)^(1/3), the length
// over which its weight w bends it, where a corner sprang open at the start (FreeEnd's test): no two segments meet
// at more than the circle's l / r, from a drop shorter than r too (2 m from the deck at EI 50: r 3.7 m), and a cable
// too short for the path (a 29.5 m drop) ends on its arc.
TEST(CableLayout, AFreeEndStopsAtTheSurfaceOrTheSeabedAndLiesAlongIt)
{
  struct Case
  {
    const char* what;
    double weight, spool_z, surface_z, seabed_z;
    double up, vertical;  // the path: up (1) or down (-1) that far, then level
  };
  const double none = std::numeric_limits<double>::quiet_NaN();
  const Case cases[] = {
      {"buoyant, up 10 m to the surface", -1.0, -10.0, 0.0, none, 1.0, 10.0},
      {"heavy, down 4 m to the seabed", 1.0, -10.0, 0.0, -14.0, -1.0, 4.0},
      {"buoyant from a deck, down 2 m to the surface", -1.0, 2.0, 0.0, -14.0, -1.0, 2.0},
      {"heavy from a deck, down 16 m to the seabed", 1.0, 2.0, 0.0, -14.0, -1.0, 16.0},
      {"heavy, down 29.5 m to the seabed", 1.0, -10.0, 0.0, -39.5, -1.0, 29.5},
  };
  for (const Case& c : cases)
    for (const double ei : {0.0, 0.2, 50.0})
    {
      SCOPED_TRACE("EI " + std::to_string(ei));
      TetherParams params;
      params.bending_stiffness = ei;
      params.weight_in_water = c.weight;
      params.water_surface_z = c.surface_z;
      params.seabed_z = c.seabed_z;
      const Position outlet(2.0, -1.0, c.spool_z);
      LaidCable laid(400, 0.1, 30.0, outlet);
      CableLayout(params).layOut(laid.cable, outlet, nullptr, laid.length);
      expectAtRestFromTheSpool(laid, outlet);
      expectNoSegmentStretched(laid);
      const FreeEndPath path{outlet, c.up, c.vertical, std::cbrt(ei / 1.0)};  // |w| is 1 N/m in every case
      // Past a deck's drop to the water the cable is in it, or on the surface once round onto it.
      const double drop = std::max(c.spool_z - c.surface_z, 0.0);
      const double in_water = drop > 0.0 && c.vertical <= drop ? path.straight() + path.turned() : drop;
      double arc = 0.0, off_path = 0.0, highest_past_drop = -kInf, lowest = kInf;
      for (std::size_t i = laid.cable.first; i < laid.cable.size(); ++i)
      {
        const Position p = laid.at(i);
        off_path = std::max(off_path, (p - path.at(arc)).norm());
        if (arc > in_water + kTight)
        {
          highest_past_drop = std::max(highest_past_drop, p.z());
        }
        lowest = std::min(lowest, p.z());
        arc += i + 1 < laid.cable.size() ? laid.cable.rest[i] : 0.0;
      }
      EXPECT_LT(off_path, kTight) << c.what;
      if (ei > 0.0)
      {
        EXPECT_LE(sharpestTurn(laid), 0.1 / path.r + 1e-9) << c.what << ": a corner";
      }
      EXPECT_LE(highest_past_drop, c.surface_z + kTight) << c.what;
      EXPECT_FALSE(lowest < c.seabed_z - kTight) << c.what << ": lowest " << lowest;  // false for no seabed (NaN)
    }
}

// A free end rises or sinks by the net weight in water of the whole cable, its sections and attachments
// included, not by the tether's weight_in_water: 10 m at -0.5 N/m with an 8 N clump at the end weigh
// -5 + 8 = +3 N and hang straight down; 10 m at 0.5 N/m whose last 6 m (from the free end) are a -1.5 N/m
// section weigh 2 - 9 = -7 N and float straight up. Seen failing before (laid by weight_in_water: the first
// up, the second down, their ends 20 m off).
TEST(CableLayout, AFreeEndRisesOrSinksByTheNetWeightOfItsSectionsAndAttachments)
{
  TetherParams clumped;
  clumped.cable_length = 10.0;
  clumped.segment_length = 0.1;
  clumped.weight_in_water = -0.5;
  CableAttachment clump;
  clump.name = "clump";
  clump.mass = 1.0;
  clump.net_buoyancy = -8.0;
  clumped.attachments = {clump};
  TetherParams floated = clumped;
  floated.attachments.clear();
  floated.weight_in_water = 0.5;
  floated.sections = {{6.0, {{"weight_in_water", -1.5}}}, {std::numeric_limits<double>::quiet_NaN(), {}}};
  for (const auto& [params, up] : {std::pair{clumped, -1.0}, std::pair{floated, 1.0}})
  {
    const Position outlet(2.0, -1.0, -3.0);
    LaidCable laid(100, 0.1, 10.0, outlet);
    CableSections::load(params, &laid.cable);
    CableLayout(params).layOut(laid.cable, outlet, nullptr, laid.length);
    expectAtRestFromTheSpool(laid, outlet);
    EXPECT_LT((laid.at(laid.last()) - (outlet + up * 10.0 * Position::UnitZ())).norm(), kTight)
        << (up < 0.0 ? "clumped" : "floated");
  }
}

}  // namespace rov_tether::test
