// World: tethers stepped in lockstep. Lockstep must not change any tether's own motion (its physics
// does not depend on the others yet), so a tether in a world moves exactly as it does alone. (The order of
// the interleaved steps is not observable from outside; what is pinned is that every call leaves each
// tether within one of its own steps of the target.)
#include <gtest/gtest.h>

#include <cstdint>
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

/// Records, around each step, which tether stepped and its step count then (World::advanceTo's observer).
struct StepLog : StepObserver
{
  explicit StepLog(const World& w) : world(w) {}
  void beforeStep(std::size_t i) override
  {
    EXPECT_EQ(open, World::npos) << "a step began inside another";
    open = i;
    before = world.tether(i).stepCount();
  }
  void afterStep(std::size_t i) override
  {
    EXPECT_EQ(open, i) << "a step ended that had not begun";
    EXPECT_EQ(world.tether(i).stepCount(), before + 1) << "told around exactly one step of that tether";
    open = World::npos;
    ++told[i];
  }
  const World& world;
  std::size_t open = World::npos;
  std::uint64_t before = 0;
  std::uint64_t told[2] = {0, 0};
};

TEST(World, AnObserverIsToldAroundEachStepOfTheTetherThatTakesIt)
{
  // The node charges each tether the wall time of its own steps with this (Scheduler); a step told to the
  // wrong tether, or not told, would charge one tether for another's work.
  World world;
  ASSERT_TRUE(world.add("a", pulledTether(0.005, 0.0)).ok);
  ASSERT_TRUE(world.add("b", pulledTether(0.004, 3.0)).ok);
  StepLog log(world);
  std::size_t total = 0;
  for (int k = 1; k <= 10; ++k)
  {
    std::size_t steps = 0;
    ASSERT_TRUE(world.advanceTo(0.1 * k, &steps, &log).ok);
    total += steps;
  }
  EXPECT_EQ(log.open, World::npos);
  EXPECT_EQ(log.told[0], world.tether(0).stepCount());  // 200 steps of 5 ms
  EXPECT_EQ(log.told[1], world.tether(1).stepCount());  // 250 of 4 ms
  EXPECT_EQ(log.told[0] + log.told[1], total);
  EXPECT_GT(log.told[1], log.told[0]);
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
