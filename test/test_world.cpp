// World: tethers stepped in lockstep. Lockstep must not change any tether's own motion (its physics
// does not depend on the others yet), so a tether in a world moves exactly as it does alone. (The order of
// the interleaved steps is not observable from outside; what is pinned is that every call leaves each
// tether within one of its own steps of the target.)
#include <gtest/gtest.h>

#include <memory>

#include "rov_tether/core/world.hpp"
#include "test_helpers.hpp"

namespace rov_tether::test
{
namespace
{

std::unique_ptr<Tether> pulledTether(double time_step, double y)
{
  TetherParams params;
  params.time_step = time_step;
  params.noise = 0.001;  // seeded noise and a varying current: state a tether could share by mistake
  params.current_variation = 0.05;
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
  world.setContactBetweenTethers(false);  // no obstacles and no contact: nothing couples the tethers
  ASSERT_TRUE(world.add("a", pulledTether(0.005, 0.0)).ok);
  ASSERT_TRUE(world.add("b", pulledTether(0.004, 3.0)).ok);
  std::unique_ptr<Tether> alone_a = pulledTether(0.005, 0.0);
  std::unique_ptr<Tether> alone_b = pulledTether(0.004, 3.0);
  std::size_t total = 0;
  for (int k = 1; k <= 39; ++k)
  {
    const double t = 0.1 * k;
    std::size_t steps = 0;
    ASSERT_TRUE(world.advanceTo(t, &steps).ok);
    total += steps;
    ASSERT_TRUE(alone_a->advanceTo(t).ok);
    ASSERT_TRUE(alone_b->advanceTo(t).ok);
    // Lockstep: after every call each tether is within one of its own steps of the target.
    ASSERT_GT(world.tether(0).time(), t - 0.005 - 1e-12);
    ASSERT_GT(world.tether(1).time(), t - 0.004 - 1e-12);
  }
  EXPECT_EQ(positions(world.tether(0)), positions(*alone_a));  // bit for bit
  EXPECT_EQ(positions(world.tether(1)), positions(*alone_b));
  EXPECT_EQ(world.tether(0).stepCount(), alone_a->stepCount());
  EXPECT_EQ(world.tether(1).stepCount(), alone_b->stepCount());
  EXPECT_EQ(total, alone_a->stepCount() + alone_b->stepCount());  // the steps the world reports
  EXPECT_EQ(world.time(), std::min(world.tether(0).time(), world.tether(1).time()));
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
