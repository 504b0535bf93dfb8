// World: tethers stepped in lockstep. Lockstep must not change any tether's own motion (its physics
// does not depend on the others yet), so a tether in a world moves exactly as it does alone.
#include <gtest/gtest.h>

#include <memory>

#include "rov_tether/world.hpp"
#include "test_helpers.hpp"

namespace rov_tether::test
{
namespace
{

std::unique_ptr<Tether> pulledTether(double time_step, double y)
{
  TetherParams params;
  params.time_step = time_step;
  auto tether = std::make_unique<Tether>(params, Position(0.0, y, 0.0), Position(1.5, y, 0.0));
  for (int k = 1; k <= 100; ++k)
  {
    EXPECT_TRUE(tether->addVehicleSample(0.05 * k, Position(1.5 + 0.05 * k, y, -0.02 * k)).ok);
  }
  return tether;
}

TEST(World, ATetherInAWorldMovesExactlyAsAlone)
{
  World world;
  ASSERT_TRUE(world.add("a", pulledTether(0.005, 0.0)).ok);
  ASSERT_TRUE(world.add("b", pulledTether(0.004, 3.0)).ok);
  std::unique_ptr<Tether> alone = pulledTether(0.005, 0.0);
  std::size_t steps = 0;
  for (double t = 0.1; t < 4.0; t += 0.1)
  {
    ASSERT_TRUE(world.advanceTo(t, &steps).ok);
    ASSERT_TRUE(alone->advanceTo(t).ok);
  }
  EXPECT_EQ(positions(world.tether(0)), positions(*alone));  // bit for bit
  EXPECT_EQ(world.tether(0).stepCount(), alone->stepCount());
  // Both reached the target within one of their own steps; the world time is the earliest of them.
  EXPECT_NEAR(world.tether(0).time(), 3.9, 0.005);
  EXPECT_NEAR(world.tether(1).time(), 3.9, 0.004);
  EXPECT_LE(world.time(), std::min(world.tether(0).time(), world.tether(1).time()));
}

TEST(World, NamesAreUniqueAndBadTimesAreRefused)
{
  World world;
  EXPECT_TRUE(world.add("a", pulledTether(0.005, 0.0)).ok);
  EXPECT_FALSE(world.add("a", pulledTether(0.005, 1.0)).ok);
  EXPECT_FALSE(world.add("", pulledTether(0.005, 1.0)).ok);
  EXPECT_FALSE(world.add("c", nullptr).ok);
  EXPECT_EQ(world.size(), 1u);
  EXPECT_EQ(world.find("a"), 0u);
  EXPECT_EQ(world.find("b"), World::npos);
  EXPECT_FALSE(world.advanceTo(std::nan(""), nullptr).ok);
  EXPECT_FALSE(world.advanceTo(2e10, nullptr).ok);
  EXPECT_EQ(world.tether(0).stepCount(), 0u);
}

}  // namespace
}  // namespace rov_tether::test
