// Contact with obstacles and between tethers (World, WorldContact) and the topology it reports. Each bound
// comes from geometry or a conservation law, stated at the test; docs/references.md, "Wraps and links".
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>

#include "rov_tether/core/obstacle.hpp"
#include "rov_tether/core/segment_grid.hpp"
#include "rov_tether/core/topology.hpp"
#include "rov_tether/core/world.hpp"
#include "test_helpers.hpp"

namespace rov_tether::test
{
namespace
{

constexpr double kPi = 3.14159265358979323846;

using Path = std::function<Position(double)>;

/// A neutrally buoyant cable without noise, held taut by a constant-tension winch.
TetherParams tautParams(double tension)
{
  TetherParams p;
  p.noise = 0.0;
  p.weight_in_water = 0.0;
  p.bending_stiffness = 0.0;
  p.cable_length = 80.0;
  p.winch_mode = WinchMode::kConstantTension;
  p.target_tension = tension;
  p.max_winch_speed = 3.0;
  // A motor that never gives way (the stall pull has its own tests, test_winch): the contact scenes here were
  // built on a winch whose pay-out only the acceleration limit holds back; with the derived pull (1.25 x the
  // target) a's winch yields as b is pulled across it.
  p.max_winch_pull = 1e7;
  return p;
}

std::unique_ptr<Obstacle> primitive(const std::string& name, ShapeType type, const Position& at, double radius,
                                    double length, double friction)
{
  ObstacleSpec spec;
  spec.name = name;
  spec.type = type;
  spec.position = at;
  spec.radius = radius;
  spec.length = length;
  spec.friction = friction;
  Status status;
  auto made = makePrimitive(spec, &status);
  EXPECT_TRUE(status.ok) << status.message;
  return made;
}

/// Feeds every tether's vehicle one sample a step from its path and advances the world to `to`, calling
/// `each` after every step.
void drive(World& world, const std::vector<Path>& paths, double from, double to, const std::function<void()>& each = {})
{
  const double dt = world.tether(0).params().time_step;
  for (double t = from + dt; t <= to + 1e-9; t += dt)
  {
    for (std::size_t i = 0; i < paths.size(); ++i)
    {
      ASSERT_TRUE(world.tether(i).addVehicleSample(t, paths[i](t)).ok);
    }
    ASSERT_TRUE(world.advanceTo(t - dt).ok);
    if (each)
    {
      each();
    }
  }
}

double entry(const World& world, TopologyEntry::Kind kind, std::size_t tether, std::size_t object)
{
  std::vector<TopologyEntry> out;
  world.topology(out);
  for (const TopologyEntry& e : out)
  {
    if (e.kind == kind && e.tether == tether && e.object == object)
    {
      return e.value;
    }
  }
  return std::nan("");
}

/// Deepest overlap of any deployed segment of `tether` with the vertical pole of radius `pole` at the origin
/// (axis z): (pole + r) minus the segment's distance from the axis, at most 0 when nothing overlaps [m].
double poleOverlap(const Tether& tether, double pole)
{
  double worst = -1e9;
  const double r = 0.5 * tether.params().diameter;
  for (std::size_t k = 0; k + 1 < tether.deployedParticleCount(); ++k)
  {
    Push push;
    const Position a = tether.particle(k), b = tether.particle(k + 1);
    if (pushCapsule(a, b, r, Position(0, 0, -50), Position(0, 0, 50), pole, &push))
    {
      worst = std::max(worst, push.depth);
    }
  }
  return worst;
}

// The grid's pair lists stand in for a query (SegmentGrid): World files every segment with a margin of the
// widest radius w plus a skin, and while every segment stays within the skin of where it was filed, a
// segment touches only its pairs: two capsules that touch have boxes within r_a + r_b <= 2w of each other,
// so their filed boxes were within 2w + 2 skin, twice the margin (no slack). Three tangled cables (random
// walks of 0.1 m steps in a 1 m cube, so they cross each other and themselves), every particle moved by the
// skin along each axis, each way at random: every touching pair (exact capsule test, not neighbours along
// a cable) is listed, and pairsOf answers for every segment (none moved further than the skin).
TEST(SegmentGrid, ListsEveryPairOfCapsulesThatCanTouchAfterTheyMove)
{
  const double w = 0.02, skin = 0.01;  // World's: skin = max(2 x last motion, kSkin w)
  const std::vector<std::size_t> gap = {2, 2, 2};
  std::uint64_t state = 7;
  auto uniform = [&state]()
  {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  auto jitter = [&](double size) -> Position
  { return Position(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5) * (2.0 * size); };
  std::vector<Cable> cables(3);
  for (Cable& cable : cables)
  {
    cable.resize(61);
    Position at(uniform(), uniform(), uniform());
    for (std::size_t i = 0; i < cable.size(); ++i)
    {
      cable.place(i, at);
      at += 0.1 * jitter(1.0).normalized();
      at = at.cwiseMax(Position::Zero()).cwiseMin(Position::Ones());
    }
  }
  std::vector<const Cable*> filed = {&cables[0], &cables[1], &cables[2]};
  SegmentGrid grid;
  grid.build(filed, 3.0 * std::max(0.1, 2.0 * skin) + 2.0 * w, w + skin, gap, skin);  // as World::refreshContact
  int touching = 0;
  for (int round = 0; round < 20; ++round)
  {
    std::vector<Cable> now = cables;
    for (std::size_t c = 0; c < 3; ++c)
    {
      for (std::size_t i = 0; i < now[c].size(); ++i)
      {
        // To a corner of its skin's cube: as far as the skin lets it (the margin has no slack for it).
        const Position corner(uniform() < 0.5 ? -skin : skin, uniform() < 0.5 ? -skin : skin,
                              uniform() < 0.5 ? -skin : skin);
        now[c].place(i, cables[c].position(i) + corner);
      }
      ASSERT_TRUE(grid.holds(c, now[c])) << c;  // every particle within the skin of its segments' boxes
    }
    for (std::size_t a = 0; a < 3; ++a)
    {
      for (std::size_t j = 0; j + 1 < now[a].size(); ++j)
      {
        Aabb box;
        box.grow(now[a].position(j)), box.grow(now[a].position(j + 1));
        const SegmentGrid::Entry* first = nullptr;
        const SegmentGrid::Entry* last = nullptr;
        ASSERT_TRUE(grid.pairsOf(a, j, box, &first, &last)) << a << ", " << j;
        for (std::size_t c = 0; c < 3; ++c)
        {
          for (std::size_t s = 0; s + 1 < now[c].size(); ++s)
          {
            Push push;
            if ((c == a && (s > j ? s - j : j - s) <= gap[c]) ||
                !pushCapsule(now[a].position(j), now[a].position(j + 1), w, now[c].position(s), now[c].position(s + 1),
                             w, &push))
            {
              continue;
            }
            ++touching;
            const bool listed =
                std::any_of(first, last, [&](const SegmentGrid::Entry& e) { return e.cable == c && e.segment == s; });
            EXPECT_TRUE(listed) << "round " << round << ": segment " << j << " of cable " << a << " touches segment "
                                << s << " of cable " << c;
          }
        }
      }
    }
  }
  EXPECT_GT(touching, 100);  // coverage: the tangle touches often
  // The skin's edge: a particle higher than both its neighbours tops both its segments' boxes. Raised by
  // 0.99 of the skin its cable still holds; by 1.01 it does not, and its segments query instead of taking
  // their pairs. A paid-out cable (another spool outlet: a segment never filed) does not hold either.
  std::size_t top = 1;
  while (top + 1 < cables[1].size() &&
         !(cables[1].z[top] >= cables[1].z[top - 1] && cables[1].z[top] >= cables[1].z[top + 1]))
  {
    ++top;
  }
  ASSERT_LT(top + 1, cables[1].size());
  for (const double raised : {0.99, 1.01})
  {
    Cable moved = cables[1];
    moved.place(top, cables[1].position(top) + Position(0.0, 0.0, raised * skin));
    Aabb box;
    box.grow(moved.position(top)), box.grow(moved.position(top + 1));
    const SegmentGrid::Entry* first = nullptr;
    const SegmentGrid::Entry* last = nullptr;
    EXPECT_EQ(grid.holds(1, moved), raised < 1.0) << raised;
    EXPECT_EQ(grid.pairsOf(1, top, box, &first, &last), raised < 1.0) << raised;
  }
  Cable paid_out = cables[2];
  paid_out.first = 1;
  EXPECT_FALSE(grid.holds(2, paid_out));
}

// A vehicle circling a pillar: the tether, closed by the chord from the vehicle back to the spool, winds
// around the pillar's axis as many times as the vehicle went round (a closed curve's winding number about a
// line it does not meet is an integer, and the tether cannot cross the pillar). Counter-clockwise seen from
// +z (the axis) is positive. Twice round: +2; twice back: 0; twice the other way: -2; within 0.1 of the
// integers, the tolerance.
TEST(Contact, WrapTurnsCountTheTimesTheVehicleCircledThePillar)
{
  for (const double sense : {1.0, -1.0})
  {
    World world;
    world.setContactBetweenTethers(true);  // the second turn lies on the first
    const Position spool(-4.0, 0.0, 0.0);
    const double orbit = 1.5;
    TetherParams p = tautParams(5.0);
    p.segment_length = 0.2;  // a third of the pillar's radius: a fine enough polygon, half the cost
    ASSERT_TRUE(world.add("rov", std::make_unique<Tether>(p, spool, Position(-orbit, 0.0, 0.0))).ok);
    std::vector<std::unique_ptr<Obstacle>> obstacles;
    // A smooth pillar (friction 0.1): at 0.5, two turns would hold e^(0.5 x 4 pi) = 535 times the winch's 5 N
    // against the vehicle unwinding them (Known limitations).
    obstacles.push_back(primitive("pillar", ShapeType::Cylinder, Position::Zero(), 0.3, 10.0, 0.1));
    ASSERT_TRUE(world.setObstacles(std::move(obstacles)).ok);
    const double speed = 1.0, lap = 2.0 * kPi * orbit / speed;
    // Out twice round, then back twice round, each along the circle from the west point.
    const Path path = [&](double t)
    {
      const double turned = t < 2.0 * lap ? t / lap : 4.0 - t / lap;  // laps done, going out then back
      const double angle = kPi + sense * 2.0 * kPi * turned;
      return Position(orbit * std::cos(angle), orbit * std::sin(angle), 0.0);
    };
    double worst = -1e9;
    drive(world, {path}, 0.0, 2.0 * lap + 1.0, [&] { worst = std::max(worst, poleOverlap(world.tether(0), 0.3)); });
    EXPECT_NEAR(entry(world, TopologyEntry::Kind::WrapTurns, 0, 0), 2.0 * sense, 0.1) << "sense " << sense;
    // The unclosed wrap angle follows the vehicle: it has come 1 s (1/lap of a turn) back from two turns, and
    // the cable runs from the spool's side (west, where the vehicle started) round to it. 0.05 rad: the
    // vehicle end sits one step (0.67 rad/s x time_step) behind the last sample.
    const double dt = world.tether(0).params().time_step;
    std::printf(
        "[ measured ] sense %+.0f, 1 s short of two turns: wrap_turns %.3f, wrap_angle %.4f rad (expected %.4f)\n",
        sense, entry(world, TopologyEntry::Kind::WrapTurns, 0, 0), entry(world, TopologyEntry::Kind::WrapAngle, 0, 0),
        sense * 2.0 * kPi * (2.0 - (1.0 - dt) / lap));
    EXPECT_NEAR(entry(world, TopologyEntry::Kind::WrapAngle, 0, 0), sense * 2.0 * kPi * (2.0 - (1.0 - dt) / lap), 0.05)
        << "sense " << sense;
    drive(world, {path}, 2.0 * lap + 1.0, 4.0 * lap + 1.0,
          [&] { worst = std::max(worst, poleOverlap(world.tether(0), 0.3)); });
    EXPECT_NEAR(entry(world, TopologyEntry::Kind::WrapTurns, 0, 0), 0.0, 0.1) << "sense " << sense;
    EXPECT_NEAR(entry(world, TopologyEntry::Kind::WrapAngle, 0, 0), -sense * 2.0 * kPi * (1.0 - dt) / lap, 0.05)
        << "sense " << sense;
    // The bound on penetration: below 10% of the cable's diameter.
    EXPECT_LT(worst, 0.1 * world.tether(0).params().diameter);
  }
}

// A 2 m/s sweep into a 5 cm pole: the tether's middle must catch on the pole, not pass through it. Caught,
// the tether closed by its chord (which passes the pole on the far side) winds once around the pole's axis;
// passed through, 0. Every step the overlap stays below 10% of the diameter (the bound).
TEST(Contact, NoTunnellingThroughAThinPoleAtTwoMetresASecond)
{
  World world;
  TetherParams p = tautParams(10.0);
  ASSERT_TRUE(world.add("rov", std::make_unique<Tether>(p, Position(0.0, -5.0, 0.0), Position(-3.0, 5.0, 0.0))).ok);
  std::vector<std::unique_ptr<Obstacle>> obstacles;
  obstacles.push_back(primitive("pole", ShapeType::Cylinder, Position::Zero(), 0.025, 10.0, 0.5));
  ASSERT_TRUE(world.setObstacles(std::move(obstacles)).ok);
  const Path sweep = [](double t) { return Position(-3.0 + 2.0 * std::min(t, 3.0), 5.0, 0.0); };
  double worst = -1e9;
  drive(world, {sweep}, 0.0, 4.0, [&] { worst = std::max(worst, poleOverlap(world.tether(0), 0.025)); });
  EXPECT_NEAR(std::abs(entry(world, TopologyEntry::Kind::WrapTurns, 0, 0)), 1.0, 0.1);
  EXPECT_LT(worst, 0.1 * p.diameter);
}

// Two tethers whose vehicles swap sides twice in the same sense, one passing over the other each time:
// one full twist of two strands, each closed by its chord back to its spool, links them once (as two rings
// linked once: Gauss linking number +-1). The sign follows the right-hand rule of the twist about the
// vehicles' direction, +x here: the vehicles turn counter-clockwise seen from +x, so +1. Without contact
// between tethers the taut strands pass through each other and untwist: 0.
TEST(Contact, TwistedTethersReadTheLinkingNumberTheirVehiclesMade)
{
  for (const bool contact : {true, false})
  {
    World world;
    world.setContactBetweenTethers(contact);
    const TetherParams p = tautParams(5.0);
    ASSERT_TRUE(world.add("a", std::make_unique<Tether>(p, Position(0.0, -0.5, 0.0), Position(6.0, -0.5, 0.0))).ok);
    ASSERT_TRUE(world.add("b", std::make_unique<Tether>(p, Position(0.0, 0.5, 0.0), Position(6.0, 0.5, 0.0))).ok);
    // The vehicles turn about the point (6, 0, 0), half a metre off it, one turn in 8 s, counter-clockwise
    // seen from +x (y then z), then hold.
    const auto around = [](double phase)
    {
      return [phase](double t)
      {
        const double angle = phase + 2.0 * kPi * std::min(t, 8.0) / 8.0;
        return Position(6.0, 0.5 * std::cos(angle), 0.5 * std::sin(angle));
      };
    };
    drive(world, {around(-0.5 * kPi + -0.5 * kPi), around(0.0)}, 0.0, 10.0);
    const double link = entry(world, TopologyEntry::Kind::LinkingNumber, 0, 1);
    if (contact)
    {
      EXPECT_NEAR(link, 1.0, 0.1);
    }
    else
    {
      EXPECT_NEAR(link, 0.0, 0.1);
    }
  }
}

/// Two taut tethers crossing 0.3 m apart: a along x at z = 0, b along y above it, whose vehicle is pulled
/// down at 1 m/s for 3 s (through where a was), then held.
struct Crossing
{
  World world;
  TetherParams p = tautParams(10.0);
  std::vector<Path> paths;
  explicit Crossing(bool contact, double friction = 0.3)
  {
    p.cable_friction = friction;
    world.setContactBetweenTethers(contact);
    EXPECT_TRUE(world.add("a", std::make_unique<Tether>(p, Position(-5.0, 0.0, 0.0), Position(5.0, 0.0, 0.0))).ok);
    EXPECT_TRUE(world.add("b", std::make_unique<Tether>(p, Position(0.0, -5.0, 0.3), Position(0.0, 5.0, 0.3))).ok);
    paths = {[](double) { return Position(5.0, 0.0, 0.0); },
             [](double t) { return Position(0.0, 5.0, 0.3 - 1.0 * std::min(t, 3.0)); }};
  }
  /// The closest points of the two cables (segment against segment): b's minus a's.
  Position gap() const
  {
    const Tether &a = world.tether(0), &b = world.tether(1);
    Position best = Position::Constant(1e9);
    for (std::size_t i = 0; i + 1 < a.deployedParticleCount(); ++i)
    {
      for (std::size_t k = 0; k + 1 < b.deployedParticleCount(); ++k)
      {
        double s = 0.0, u = 0.0;
        const Position pa = a.particle(i), qa = a.particle(i + 1), pb = b.particle(k), qb = b.particle(k + 1);
        closestSegmentParameters(pa, qa, pb, qb, &s, &u);
        const Position d = (pb + u * (qb - pb)) - (pa + s * (qa - pa));
        if (d.norm() < best.norm())
        {
          best = d;
        }
      }
    }
    return best;
  }
};

// Two tethers pulled across each other at 1 m/s never pass through: tether b, 0.3 m above a taut tether a,
// has its vehicle pulled down at 1 m/s through a. At every step the cables' axes stay at least 90% of two
// radii apart (the 10% bound on penetration) and b's closest point stays above a's (not through).
// Without contact b passes through a.
TEST(Contact, TethersPulledAcrossEachOtherDoNotPassThrough)
{
  for (const bool contact : {true, false})
  {
    Crossing scene(contact);
    double closest = 1e9, lowest = 1e9;
    drive(scene.world, scene.paths, 0.0, 4.0,
          [&]
          {
            const Position gap = scene.gap();
            closest = std::min(closest, gap.norm());
            lowest = std::min(lowest, gap.z());
          });
    if (contact)
    {
      EXPECT_GT(closest, 0.9 * scene.p.diameter);
      EXPECT_GT(lowest, 0.0);
    }
    else
    {
      EXPECT_LT(lowest, -0.5);  // b's vehicle ends 2.7 m under a
    }
  }
}

// Two vehicles that meet (pose streams pass through each other: they cannot feel each other) press each
// cable's end segment into the other one's. A contact next to a pinned end (the vehicle) can only be
// resolved by the segment's free end; moving it far enough to clear the contact point took d / (1 - t),
// without bound as the contact nears the pinned end: the cables were thrown 180 m and read 1e11 N. A
// particle of a cable fixed at its spool cannot be further from the spool than the cable's length along
// it, stretched by its tension: 4 m of cable (EA 1e5 N) reaching further than 4.2 m would be 5% strain,
// 5 kN. Nor may the solve fail (re-laying the cable).
TEST(Contact, TwoVehiclesThatMeetDoNotThrowTheirCables)
{
  World world;
  world.setContactBetweenTethers(true);
  std::vector<Path> paths;
  for (const double side : {-1.0, 1.0})
  {
    TetherParams p;
    p.noise = 0.0;
    p.segment_length = 0.1;
    p.cable_length = 4.0;
    p.initial_deployed_length = 4.0;
    p.weight_in_water = 1.0;
    p.winch_mode = WinchMode::kLocked;
    const Position spool(side, -1.2, -0.5), start(side, 2.2, -0.5);
    // Mirror images in x, so both vehicles are at (0.15, 1.7, -1.05) at t = 2 s, crossing there at 1 m/s.
    paths.push_back(
        [side, start](double t)
        {
          const double s = std::min(1.0, t / 4.0);
          return Position(start + s * Position(-2.0 * side + 0.3 * std::sin(0.8 * t), -1.0, -1.1));
        });
    ASSERT_TRUE(world.add(side < 0.0 ? "a" : "b", std::make_unique<Tether>(p, spool, start)).ok);
  }
  ASSERT_GT(world.tether(0).params().axial_stiffness, 0.99e5);
  double furthest = 0.0;
  drive(world, paths, 0.0, 3.0,
        [&]
        {
          for (std::size_t k = 0; k < world.size(); ++k)
          {
            const Tether& tether = world.tether(k);
            for (std::size_t i = 0; i < tether.deployedParticleCount(); ++i)
            {
              furthest = std::max(furthest, (tether.particle(i) - tether.particle(0)).norm());
            }
          }
        });
  EXPECT_LT(furthest, 4.2) << "from the spool, on 4 m of cable";
  for (std::size_t k = 0; k < world.size(); ++k)
  {
    EXPECT_EQ(world.tether(k).recoveryCount(), 0u) << world.tether(k).lastFailure();
  }
}

// A cable laid out afresh is at rest, not in motion: with contact on (here a lone tether, which contacts itself),
// a constant-tension winch (10 N, deadband 1 N) whose vehicle attaches 10 m away, and again after a reset, holds
// the cable taut along the 10 m chord like a tether without contact. The winch does not move while the spool
// tension is within the deadband of the target, so at rest that is where it reads; and a taut weightless cable
// lies on its chord, so it is deployed to the chord's 10 m plus its stretch (10 N / EA) and one step's pay-out.
// Before the re-lay was taken as the start of the step's motion, its 8 m jump read as motion: the next step took
// 64 contact sub-steps, the spool read 0 N, and the winch paid out at full speed for ever (17 m by 3 s, the
// cable winding onto itself; a reset beside another tether read kilonewtons).
TEST(Contact, ACableLaidOutAfreshIsNotMotion)
{
  TetherParams p = tautParams(10.0);
  // The winch's own stall pull (1.25 x (target + deadband)): the free cable hangs slack before the vehicle
  // attaches, so the winch is reeling in when it does, and a motor that never gives way would take half a
  // second (max_winch_acceleration) to stop, stretching the cable to a kilonewton.
  p.max_winch_pull = 0.0;
  World world;
  world.setContactBetweenTethers(true);
  ASSERT_TRUE(world.add("a", std::make_unique<Tether>(p, Position(-5.0, 0.0, 0.0))).ok);
  const Position vehicle(5.0, 0.0, 0.0);
  const double chord = 10.0, dt = p.time_step;
  const auto settled = [&](double from, double to)
  {
    for (double t = from + dt; t <= to + 1e-9; t += dt)
    {
      if (t > from + 0.2)
      {
        ASSERT_TRUE(world.tether(0).addVehicleSample(t, vehicle).ok);
      }
      ASSERT_TRUE(world.advanceTo(t - dt).ok);
      const Tether& a = world.tether(0);
      if (t > from + 1.5)
      {
        const TetherSummary s = a.summary();
        ASSERT_NEAR(s.tension_spool, p.target_tension, p.tension_deadband + 1e-6) << "t " << t;
        ASSERT_LT(a.deployedLength(), chord * (1.0 + p.target_tension / p.axial_stiffness) + p.max_winch_speed * dt)
            << "t " << t;
        ASSERT_EQ(a.lastSubsteps(), p.substeps) << "t " << t;
      }
    }
  };
  settled(0.0, 4.0);
  ASSERT_TRUE(world.tether(0).reset(4.0).ok);
  settled(4.0, 8.0);
}

// The grid between tethers is filed once a round of steps, and what a contact keeps (holds, reactions,
// sizes) belongs to the cable as laid out. A clock that goes back (every tether reset to an earlier time,
// as the node does when a bag loops) and a cable rebuilt must leave contact as right as in a fresh run:
// for 2 s a's vehicle is pulled 4 m aside, then both tethers are reset to t = 0 and the crossing of the
// test above is driven, which never passes through (the same bounds as above); then a's cable is rebuilt
// with segments half as long, and the crossing goes on the same. (Without any refiling of the grid it
// fails; the reset alone is also caught by the re-layout's motion, so this guards both together.)
TEST(Contact, AClockThatGoesBackOrARebuiltCableKeepsTetherContact)
{
  Crossing scene(true);
  const std::vector<Path> aside = {[](double t) { return Position(5.0, 2.0 * std::min(t, 2.0), 0.0); },
                                   [](double) { return Position(0.0, 5.0, 0.3); }};
  drive(scene.world, aside, 0.0, 2.0);
  for (std::size_t i = 0; i < scene.world.size(); ++i)
  {
    ASSERT_TRUE(scene.world.tether(i).reset(0.0).ok);
  }
  double closest = 1e9, lowest = 1e9;
  const auto watch = [&]
  {
    const Position gap = scene.gap();
    closest = std::min(closest, gap.norm());
    lowest = std::min(lowest, gap.z());
  };
  drive(scene.world, scene.paths, 0.0, 2.0, watch);
  TetherParams finer = scene.p;
  finer.segment_length = 0.5 * scene.p.segment_length;
  ASSERT_TRUE(scene.world.tether(0).setParams(finer).ok);
  drive(scene.world, scene.paths, 2.0, 4.0, watch);
  EXPECT_GT(closest, 0.9 * scene.p.diameter);
  EXPECT_GT(lowest, 0.0);
}

// Newton's third law between tethers: b pulled down onto a pushes a down as hard as a holds b up, and
// what holds b back as it slides on a drags a along. The two weightless cables together are a body held
// by their four ends alone, each pulled along its end segment by its end tension, so those four pulls
// balance whenever the cables are at rest, and on average over time whatever they do (their momentum
// stays bounded). b's vehicle stops after 3 s. Frictionless, the crossing comes to rest: the residual at
// 8 s is held to 5% of the load b carries (about 2 T sin(theta) = 2 N). With friction 0.3, b sticks and
// slips on a: the pulls averaged over 10..30 s balance to 5% of the load. With contact one-sided (b moved
// out of a, a never pushed: the first version) a stays straight, and the residual is the whole load.
TEST(Contact, TethersPushEachOtherEquallyAndOppositely)
{
  // The pull of a tether's ends on the cable: toward each end along its end segment, of its end tension.
  const auto endPulls = [](const Tether& t) -> Position
  {
    const TetherSummary s = t.summary();
    const std::size_t n = t.deployedParticleCount();
    return s.tension_spool * (t.particle(0) - t.particle(1)).normalized() +
           s.tension_vehicle * (t.particle(n - 1) - t.particle(n - 2)).normalized();
  };
  {
    Crossing scene(true, 0.0);
    drive(scene.world, scene.paths, 0.0, 8.0);
    const Position on_a = endPulls(scene.world.tether(0)), on_b = endPulls(scene.world.tether(1));
    // b rests on a: its ends pull it down, a's pull a up (a is pushed down at the crossing).
    EXPECT_LT(on_b.z(), -1.0);
    EXPECT_LT((on_a + on_b).norm(), 0.05 * std::abs(on_b.z()))
        << "frictionless: a " << on_a.transpose() << ", b " << on_b.transpose();
  }
  {
    Crossing scene(true, 0.3);
    drive(scene.world, scene.paths, 0.0, 10.0);
    Position sum = Position::Zero();
    double load = 0.0;
    int samples = 0;
    drive(scene.world, scene.paths, 10.0, 30.0,
          [&]
          {
            const Position on_b = endPulls(scene.world.tether(1));
            sum += endPulls(scene.world.tether(0)) + on_b;
            load += std::abs(on_b.z());
            ++samples;
          });
    EXPECT_LT(sum.norm() / samples, 0.05 * load / samples)
        << "friction 0.3: mean residual " << (sum / samples).transpose();
  }
}

/// What a cable pulled around a pillar reads: the mean tensions of its spool and vehicle segments over the
/// last 5 s, and the angle it turns through on the pillar at the end.
struct PillarPull
{
  double spool = 0.0, vehicle = 0.0, angle = 0.0;
};

/// A weightless cable (Morison drag: 0.1 N of axial drag at 0.2 m/s over its 8 m, 0.5% of 20 N) runs north
/// from a braked spool (20 N) along the west side of a 0.5 m pillar with Coulomb friction mu; the vehicle
/// crosses over the pillar's north side in 3 s, then pulls the cable off the spool at 0.2 m/s: south down
/// the east side (the cable turns through pi on the pillar) or away east (about pi / 2).
PillarPull pullAroundPillar(double mu, bool south)
{
  TetherParams p = tautParams(0.0);
  p.winch_mode = WinchMode::kBrake;
  p.brake_tension = 20.0;
  p.drag_model = DragModel::kMorison;
  p.initial_deployed_length = 7.0;
  const double reach = 0.5 + 0.5 * p.diameter;  // the cable's axis on the pillar's surface
  World world;
  EXPECT_TRUE(
      world.add("rov", std::make_unique<Tether>(p, Position(-reach, -5.0, 0.0), Position(-reach, 2.0, 0.0))).ok);
  std::vector<std::unique_ptr<Obstacle>> obstacles;
  obstacles.push_back(primitive("pillar", ShapeType::Cylinder, Position::Zero(), 0.5, 4.0, mu));
  EXPECT_TRUE(world.setObstacles(std::move(obstacles)).ok);
  const Path path = [&](double t)
  {
    const double a = std::min(t, 3.0) / 3.0, v = 0.2 * std::max(t - 3.0, 0.0);
    return south ? Position(-reach + 2.0 * reach * a, 2.0 - v, 0.0)
                 : Position(-reach + (2.0 * reach + 3.0) * a + v, 2.0, 0.0);
  };
  PillarPull out;
  int samples = 0;
  std::vector<double> tensions;
  drive(world, {path}, 0.0, 23.0,
        [&]
        {
          if (world.tether(0).time() > 18.0)  // wrapped, and past the snap taut at about 16.5 s, from 18 s on
          {
            world.tether(0).computeSegmentTensions(tensions);
            out.spool += tensions.front(), out.vehicle += tensions.back(), ++samples;
          }
        });
  out.spool /= samples, out.vehicle /= samples;
  out.angle = entry(world, TopologyEntry::Kind::ContactAngle, 0, 0);
  return out;
}

// A frictionless contact carries no force along the cable, so a weightless cable has one tension on both
// sides of a pillar (string statics: dT/ds = the friction per length, here 0): the vehicle's segment and
// the spool's carry the same tension within 1% (the bound), the spool's that of its slipping brake.
TEST(Contact, FrictionlessPillarCarriesTheSameTensionOnBothSides)
{
  const PillarPull pull = pullAroundPillar(0.0, true);
  EXPECT_NEAR(pull.angle, kPi, 0.1 * kPi);
  EXPECT_NEAR(pull.vehicle / pull.spool, 1.0, 0.01);
}

// The capstan: a cable sliding over a fixed cylinder with friction mu, held back at T0 on one side, needs
// T1 = T0 e^(mu theta) on the other (Euler-Eytelwein; docs/references.md), theta the angle it turns through
// on the cylinder, here as the topology reports it. Within 10% (the bound) at two wrap angles and
// two coefficients.
TEST(Contact, CapstanRatioAtTwoWrapAngles)
{
  for (const bool south : {true, false})
  {
    for (const double mu : {0.3, 0.6})
    {
      const PillarPull pull = pullAroundPillar(mu, south);
      EXPECT_NEAR(pull.angle, south ? kPi : 0.5 * kPi, 0.15 * kPi) << "mu " << mu;
      const double capstan = std::exp(mu * pull.angle);
      EXPECT_NEAR(pull.vehicle / pull.spool, capstan, 0.1 * capstan)
          << "mu " << mu << ", theta " << pull.angle << ", spool " << pull.spool << " N, vehicle " << pull.vehicle
          << " N";
    }
  }
}

/// The capstan scene above in a world (a brake-held cable drawn round a pillar, wrapped by half a turn), driven 18 s,
/// so that the record of what the cable touched is full; `params` gets the tether's parameters.
void wrapHalfATurn(World& world, TetherParams* params)
{
  TetherParams p = tautParams(0.0);
  p.winch_mode = WinchMode::kBrake;
  p.brake_tension = 20.0;
  p.initial_deployed_length = 7.0;
  const double reach = 0.5 + 0.5 * p.diameter;
  ASSERT_TRUE(
      world.add("rov", std::make_unique<Tether>(p, Position(-reach, -5.0, 0.0), Position(-reach, 2.0, 0.0))).ok);
  std::vector<std::unique_ptr<Obstacle>> obstacles;
  obstacles.push_back(primitive("pillar", ShapeType::Cylinder, Position::Zero(), 0.5, 4.0, 0.0));
  ASSERT_TRUE(world.setObstacles(std::move(obstacles)).ok);
  const Path path = [&](double t)
  {
    const double a = std::min(t, 3.0) / 3.0, v = 0.2 * std::max(t - 3.0, 0.0);
    return Position(-reach + 2.0 * reach * a, 2.0 - v, 0.0);
  };
  drive(world, {path}, 0.0, 18.0);
  ASSERT_NEAR(entry(world, TopologyEntry::Kind::ContactAngle, 0, 0), kPi, 0.1 * kPi);  // as in the capstan scene
  *params = p;
}

// What a tether touched is recorded per segment of the cable that touched it. A cable rebuilt (here with twice as
// many segments, laid out anew at its deployed length) has touched nothing yet: until its next step the topology
// reports no contact angle for it (it read the old record, half as long, past its end, for joints of another
// cable), while its wrap, a property of its shape, is still reported. The scene is the capstan's above (the cable
// drawn round a pillar, wrapped by half a turn).
TEST(Contact, ARebuiltCableHasTouchedNothingUntilItsNextStep)
{
  World world;
  TetherParams p;
  ASSERT_NO_FATAL_FAILURE(wrapHalfATurn(world, &p));
  TetherParams finer = world.tether(0).params();
  finer.segment_length = 0.5 * p.segment_length;
  ASSERT_TRUE(world.tether(0).setParams(finer).ok);
  EXPECT_TRUE(std::isnan(entry(world, TopologyEntry::Kind::ContactAngle, 0, 0)));
  EXPECT_FALSE(std::isnan(entry(world, TopologyEntry::Kind::WrapTurns, 0, 0)));
}

// The same with a rebuild that keeps the particle count (cable_length and segment_length doubled together): the
// record is of the cable's size, so only its being dropped on the rebuild keeps the topology from reading the old
// cable's contacts as the new one's (before, the contact angle on the pillar read on for joints of the re-laid cable,
// which had touched nothing). The wrap, a property of the shape, is still reported.
TEST(Contact, ACableRebuiltWithItsParticleCountHasTouchedNothingUntilItsNextStep)
{
  World world;
  TetherParams p;
  ASSERT_NO_FATAL_FAILURE(wrapHalfATurn(world, &p));
  const std::size_t particles = world.tether(0).state().size();
  TetherParams scaled = world.tether(0).params();
  scaled.cable_length = 2.0 * p.cable_length;
  scaled.segment_length = 2.0 * p.segment_length;
  ASSERT_TRUE(world.tether(0).setParams(scaled).ok);
  ASSERT_EQ(world.tether(0).state().size(), particles) << "the rebuild was to keep the particle count";
  EXPECT_TRUE(std::isnan(entry(world, TopologyEntry::Kind::ContactAngle, 0, 0)));
  EXPECT_TRUE(std::isnan(entry(world, TopologyEntry::Kind::CapstanRatio, 0, 0)));
  EXPECT_FALSE(std::isnan(entry(world, TopologyEntry::Kind::WrapTurns, 0, 0)));
}

// Several tethers and obstacles, with noise, run twice from the same seed: the same positions bit for bit.
TEST(Contact, SeveralTethersAndObstaclesRunDeterministically)
{
  const auto run = []
  {
    World world;
    world.setContactBetweenTethers(true);
    TetherParams p = tautParams(5.0);
    p.noise = 0.002;
    for (int i = 0; i < 3; ++i)
    {
      EXPECT_TRUE(world
                      .add("t" + std::to_string(i),
                           std::make_unique<Tether>(p, Position(-4.0, i - 1.0, 0.0), Position(-1.5, i - 1.0, 0.0)))
                      .ok);
    }
    std::vector<std::unique_ptr<Obstacle>> obstacles;
    obstacles.push_back(primitive("pillar", ShapeType::Cylinder, Position::Zero(), 0.3, 10.0, 0.5));
    obstacles.push_back(primitive("ball", ShapeType::Sphere, Position(1.0, 1.0, 0.0), 0.4, 0.0, 0.5));
    EXPECT_TRUE(world.setObstacles(std::move(obstacles)).ok);
    std::vector<Path> paths;
    for (int i = 0; i < 3; ++i)
    {
      paths.push_back(
          [i](double t)
          {
            const double angle = kPi + (i - 1.0) * 0.3 + 2.0 * kPi * t / 10.0;
            return Position(1.5 * std::cos(angle), 1.5 * std::sin(angle), 0.1 * i);
          });
    }
    drive(world, paths, 0.0, 3.0);
    std::vector<std::vector<Position>> out;
    for (std::size_t i = 0; i < world.size(); ++i)
    {
      out.push_back(positions(world.tether(i)));
    }
    return out;
  };
  EXPECT_EQ(run(), run());
}

}  // namespace
}  // namespace rov_tether::test
