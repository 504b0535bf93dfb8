// Contact with obstacles and between tethers (World, WorldContact) and the topology it reports. Each bound
// comes from geometry or a conservation law, stated at the test; docs/references.md, "Wraps and links".
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>

#include "rov_tether/obstacle.hpp"
#include "rov_tether/topology.hpp"
#include "rov_tether/world.hpp"
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
    ASSERT_TRUE(world.add("rov", std::make_unique<Tether>(tautParams(5.0), spool, Position(-orbit, 0.0, 0.0))).ok);
    std::vector<std::unique_ptr<Obstacle>> obstacles;
    obstacles.push_back(primitive("pillar", ShapeType::Cylinder, Position::Zero(), 0.3, 10.0, 0.5));
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
    drive(world, {path}, 2.0 * lap + 1.0, 4.0 * lap + 1.0,
          [&] { worst = std::max(worst, poleOverlap(world.tether(0), 0.3)); });
    EXPECT_NEAR(entry(world, TopologyEntry::Kind::WrapTurns, 0, 0), 0.0, 0.1) << "sense " << sense;
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
