// tether_node's pieces without a master: PoseInput (checks, frames, attachment, counting), Scheduler
// (clock policy, state grids, skips, a World of several tethers), LoadGovernor and StateBuilder.
#include <gtest/gtest.h>
#include <tf2_ros/buffer.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "../test_helpers.hpp"
#include "rov_tether/ros/load_governor.hpp"
#include "rov_tether/ros/pose_input.hpp"
#include "rov_tether/ros/scheduler.hpp"
#include "rov_tether/ros/tether_publisher.hpp"
#include "rov_tether/world.hpp"

namespace rov_tether::ros_layer
{
namespace
{

/// Throttled log messages (ROS_WARN_THROTTLE) read ros::Time::now(): without a node, wall time.
const bool kTimeInitialised = (ros::Time::init(), true);

geometry_msgs::PoseStamped poseMsg(double x, double y, double z, double stamp, const std::string& frame = "world")
{
  geometry_msgs::PoseStamped msg;
  msg.header.stamp = ros::Time(stamp);
  msg.header.frame_id = frame;
  msg.pose.position.x = x;
  msg.pose.position.y = y;
  msg.pose.position.z = z;
  msg.pose.orientation.w = 1.0;
  return msg;
}

geometry_msgs::TransformStamped transform(const std::string& parent, const std::string& child, double stamp,
                                          const Eigen::Isometry3d& pose)
{
  geometry_msgs::TransformStamped t;
  t.header.stamp = ros::Time(stamp);
  t.header.frame_id = parent;
  t.child_frame_id = child;
  const Eigen::Quaterniond q(pose.rotation());
  t.transform.translation.x = pose.translation().x();
  t.transform.translation.y = pose.translation().y();
  t.transform.translation.z = pose.translation().z();
  t.transform.rotation.x = q.x();
  t.transform.rotation.y = q.y();
  t.transform.rotation.z = q.z();
  t.transform.rotation.w = q.w();
  return t;
}

TetherParams quietParams()
{
  TetherParams params;
  params.noise = 0.0;
  return params;
}

TEST(PoseInput, RefusesNonFiniteAndUnnormalisedPosesAndCountsThem)
{
  Tether tether(quietParams(), Position::Zero());
  tf2_ros::Buffer tf;
  PoseInput input(NodeOptions(), tf, tether);
  int clock_checks = 0;
  const auto before_add = [&](const ros::Time&) { ++clock_checks; };

  auto nan = poseMsg(std::nan(""), 0.0, -1.0, 1.0);
  EXPECT_NE(checkPose(nan.pose).find("not finite"), std::string::npos);
  EXPECT_FALSE(input.onMessage(nan, ros::Time(1.0), before_add));
  auto unnormalised = poseMsg(1.0, 0.0, -1.0, 1.0);
  unnormalised.pose.orientation.w = 1.01;
  EXPECT_NE(checkPose(unnormalised.pose).find("not normalised"), std::string::npos);
  EXPECT_FALSE(input.onMessage(unnormalised, ros::Time(1.0), before_add));
  EXPECT_EQ(input.rejected(), 2u);
  EXPECT_EQ(clock_checks, 0) << "refused numbers never reach the clock policy";
  EXPECT_TRUE(input.lastPoseTime().isZero());

  EXPECT_TRUE(input.onMessage(poseMsg(1.0, 0.0, -1.0, 2.0), ros::Time(2.0), before_add));
  EXPECT_EQ(clock_checks, 1);
  EXPECT_EQ(input.lastPoseTime(), ros::Time(2.0));
  // Older than the last sample: the core refuses it, the input counts it.
  EXPECT_FALSE(input.onMessage(poseMsg(1.5, 0.0, -1.0, 1.5), ros::Time(2.1), before_add));
  EXPECT_EQ(input.rejected(), 3u);
  EXPECT_NEAR(input.lastVehicle().translation().x(), 1.0, 1e-12);
}

TEST(PoseInput, TransformsOtherFramesThroughTheSharedBufferAndAppliesTheAttachmentOffset)
{
  NodeOptions options;
  options.attachment_offset = Eigen::Vector3d(-0.5, 0.0, 0.0);  // 0.5 m behind the vehicle
  TetherParams params = quietParams();
  params.winch_mode = WinchMode::kStrain;
  Tether tether(params, Position::Zero());
  tf2_ros::Buffer tf;
  // The boat frame is 1 m along x and turned 90 degrees about z.
  const Eigen::Isometry3d boat =
      Eigen::Translation3d(1.0, 0.0, 0.0) * Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ());
  ASSERT_TRUE(tf.setTransform(transform("world", "boat", 10.0, boat), "test", true));
  PoseInput input(options, tf, tether);

  // 2 m ahead in the boat frame is world (1, 2, -1); the vehicle faces world y, so the attachment
  // 0.5 m behind it is world (1, 1.5, -1).
  ASSERT_TRUE(input.onMessage(poseMsg(2.0, 0.0, -1.0, 10.0, "boat"), ros::Time(10.0)));
  EXPECT_TRUE(input.lastVehicle().translation().isApprox(Eigen::Vector3d(1.0, 2.0, -1.0), 1e-9));
  tether.advanceTo(10.0 + params.time_step);
  ASSERT_TRUE(tether.vehicleAttached());
  const Position end = tether.particle(tether.deployedParticleCount() - 1);
  EXPECT_TRUE(end.isApprox(Position(1.0, 1.5, -1.0), 1e-6)) << end.transpose();

  EXPECT_FALSE(input.onMessage(poseMsg(2.0, 0.0, -1.0, 10.1, "nowhere"), ros::Time(10.1)));
  EXPECT_EQ(input.rejected(), 1u) << "an unknown frame is refused and counted";
}

TEST(PoseInput, PollsTheVehicleAndTheSpoolFromTf)
{
  NodeOptions options;
  options.pose_source = "tf";
  options.spool_frame = "spool";
  Tether tether(quietParams(), Position::Zero());
  tf2_ros::Buffer tf;
  PoseInput input(options, tf, tether);
  input.poll(ros::Time(1.0));  // nothing in tf yet: warned, nothing taken
  EXPECT_TRUE(input.lastPoseTime().isZero());

  const Eigen::Isometry3d rov(Eigen::Translation3d(2.0, 0.0, -1.0));
  const Eigen::Isometry3d spool(Eigen::Translation3d(0.0, 0.5, 0.0));
  ASSERT_TRUE(tf.setTransform(transform("world", "rov", 1.0, rov), "test"));
  ASSERT_TRUE(tf.setTransform(transform("world", "spool", 1.0, spool), "test"));
  input.poll(ros::Time(1.1));
  EXPECT_EQ(input.lastPoseTime(), ros::Time(1.1));
  EXPECT_TRUE(input.lastVehicle().translation().isApprox(Eigen::Vector3d(2.0, 0.0, -1.0)));
  tether.advanceTo(1.0 + tether.params().time_step);
  EXPECT_TRUE(tether.particle(0).isApprox(Position(0.0, 0.5, 0.0))) << "the spool follows spool_frame";
  input.poll(ros::Time(1.2));  // the same transform again: not a new pose
  EXPECT_EQ(input.lastPoseTime(), ros::Time(1.1));
  EXPECT_EQ(input.rejected(), 0u);
}

/// Records what the scheduler asks of a tether.
class RecordingHooks : public TetherHooks
{
 public:
  explicit RecordingHooks(const Tether& tether) : tether_(tether) {}
  void publishState() override { state_times.push_back(tether_.time()); }
  void beforeAdvance(const ros::Time&) override { ++before; }
  void afterAdvance(const ros::Time&) override { ++after; }
  void restarted() override { ++restarts; }

  std::vector<double> state_times;
  int before = 0, after = 0, restarts = 0;

 private:
  const Tether& tether_;
};

struct OneTether
{
  explicit OneTether(const NodeOptions& options = NodeOptions(), TetherParams params = quietParams())
  {
    world.add("t", std::make_unique<Tether>(params, Position::Zero()));
    hooks = std::make_unique<RecordingHooks>(world.tether(0));
    scheduler.add(options, *hooks);
  }
  World world;
  ros::WallTime wall;
  Scheduler scheduler{world, NodeOptions().interpolation_delay, [this] { return wall; }};
  std::unique_ptr<RecordingHooks> hooks;
};

TEST(Scheduler, StartsBehindRosTimeOnTheStepGridAndPublishesOnTheStateGrid)
{
  OneTether t;
  t.scheduler.tick(ros::Time(0.0));  // simulated time not started
  EXPECT_EQ(t.hooks->before, 0);
  t.scheduler.tick(ros::Time(100.0033));
  EXPECT_EQ(t.hooks->restarts, 1);
  EXPECT_NEAR(t.world.tether(0).time(), 99.9, 1e-9) << "interpolation_delay behind, on the 5 ms grid";
  for (double now = 100.0033; now < 101.0; now += 0.005)
  {
    t.scheduler.tick(ros::Time(now));
  }
  const double period = 1.0 / 30.0;
  ASSERT_GE(t.hooks->state_times.size(), 25u);
  for (double time : t.hooks->state_times)
  {
    // Each state is at the last step before a multiple of 1 / state_rate.
    const double grid = std::ceil(time / period - 1e-9) * period;
    EXPECT_LT(grid - time, 0.005 + 1e-9) << time;
  }
  EXPECT_EQ(t.scheduler.schedule(0).resets, 0u);
}

TEST(Scheduler, ClockJumpsResetAndFallingBehindSkips)
{
  OneTether t;
  t.scheduler.tick(ros::Time(50.0));
  t.scheduler.tick(ros::Time(40.0));  // backwards
  EXPECT_EQ(t.scheduler.schedule(0).resets, 1u);
  EXPECT_NEAR(t.world.tether(0).time(), 39.9, 1e-9);
  t.scheduler.tick(ros::Time(46.0));  // forwards by 6 s > 5 s
  EXPECT_EQ(t.scheduler.schedule(0).resets, 2u);
  EXPECT_EQ(t.hooks->restarts, 3);    // the start, then the two resets
  t.scheduler.tick(ros::Time(48.0));  // 2 s later: more than max_lag (1 s) behind, skipped
  EXPECT_EQ(t.scheduler.schedule(0).skips, 1u);
  EXPECT_EQ(t.scheduler.schedule(0).last_skip_time, ros::Time(48.0));
  EXPECT_NEAR(t.world.tether(0).time(), 47.9, 1e-9);
  t.scheduler.checkClock(ros::Time(47.0));  // a pose that arrives after the clock went back
  EXPECT_EQ(t.scheduler.schedule(0).resets, 3u);
  EXPECT_EQ(t.hooks->before, t.hooks->after);
}

TEST(Scheduler, EachTetherOfAWorldKeepsItsStateGridAndMovesAsAlone)
{
  // Two tethers with different time steps and state rates in one world, against each alone.
  NodeOptions fast, slow;
  fast.state_rate = 30.0;
  slow.state_rate = 10.0;
  TetherParams fine = quietParams(), coarse = quietParams();
  coarse.time_step = 0.01;
  OneTether alone_fast(fast, fine), alone_slow(slow, coarse);

  World world;
  world.add("fast", std::make_unique<Tether>(fine, Position::Zero()));
  world.add("slow", std::make_unique<Tether>(coarse, Position::Zero()));
  Scheduler scheduler(world, fast.interpolation_delay, [] { return ros::WallTime(); });
  RecordingHooks hooks_fast(world.tether(0)), hooks_slow(world.tether(1));
  scheduler.add(fast, hooks_fast, "fast");
  scheduler.add(slow, hooks_slow, "slow");
  for (double now = 20.0; now < 22.0; now += 0.005)
  {
    const double x = 1.0 + 0.5 * (now - 20.0);
    for (Tether* tether :
         {&world.tether(0), &world.tether(1), &alone_fast.world.tether(0), &alone_slow.world.tether(0)})
    {
      tether->addVehicleSample(now, Position(x, 0.0, -1.0));
    }
    scheduler.tick(ros::Time(now));
    alone_fast.scheduler.tick(ros::Time(now));
    alone_slow.scheduler.tick(ros::Time(now));
  }
  EXPECT_EQ(hooks_fast.state_times, alone_fast.hooks->state_times);
  EXPECT_EQ(hooks_slow.state_times, alone_slow.hooks->state_times);
  EXPECT_NEAR(static_cast<double>(hooks_fast.state_times.size()), 3.0 * hooks_slow.state_times.size(), 3.0);
  EXPECT_EQ(test::positions(world.tether(0)), test::positions(alone_fast.world.tether(0)));
  EXPECT_EQ(test::positions(world.tether(1)), test::positions(alone_slow.world.tether(0)));
}

TEST(Scheduler, SharesTheWallTimeByWorkAndOnlyTheOverloadedTetherDegrades)
{
  NodeOptions options;
  options.cpu_budget = 0.3;
  TetherParams light = quietParams(), heavy = quietParams();
  light.iterations = 2;
  heavy.iterations = 40;
  World world;
  world.add("light", std::make_unique<Tether>(light, Position::Zero()));
  world.add("heavy", std::make_unique<Tether>(heavy, Position::Zero()));
  // A wall clock that moves 4 ms on every reading: the physics takes half of the wall time.
  ros::WallTime wall(1000.0);
  Scheduler scheduler(world, options.interpolation_delay,
                      [&wall]
                      {
                        wall += ros::WallDuration(0.004);
                        return wall;
                      });
  RecordingHooks hooks_light(world.tether(0)), hooks_heavy(world.tether(1));
  scheduler.add(options, hooks_light, "light");
  scheduler.add(options, hooks_heavy, "heavy");
  for (double now = 10.0; now < 12.0; now += 0.005)
  {
    scheduler.tick(ros::Time(now));
  }
  EXPECT_NEAR(scheduler.governor(0).physicsLoad() + scheduler.governor(1).physicsLoad(), 0.5, 0.01);
  EXPECT_GT(scheduler.governor(1).physicsLoad(), 0.3);
  EXPECT_LT(scheduler.governor(0).physicsLoad(), 0.15);
  EXPECT_EQ(world.tether(0).params().iterations, 2);
  EXPECT_LT(world.tether(1).params().iterations, 40);
  EXPECT_EQ(scheduler.governor(1).degraded().rfind("iterations ", 0), 0u) << scheduler.governor(1).degraded();
  EXPECT_EQ(scheduler.governor(0).degraded(), "");
}

TEST(LoadGovernor, GivesUpOneNotchPerSecondAndUndoesItWhenTheLoadFalls)
{
  NodeOptions options;  // cpu_budget 0.8, min_iterations 2
  Tether tether(quietParams(), Position::Zero());
  LoadGovernor iterations(options, 10, "t");
  options.overload_policy = "reduce_markers";
  LoadGovernor markers(options, 10, "t");
  ros::WallTime wall(100.0);
  const auto second = [&](double load, LoadGovernor& governor)
  {
    for (int i = 0; i < 10; ++i)
    {
      governor.update(0.1 * load, wall, tether);
      wall += ros::WallDuration(0.1);
    }
    governor.update(0.0, wall, tether);
  };
  second(0.9, iterations);
  EXPECT_NEAR(iterations.physicsLoad(), 0.9, 1e-9);
  EXPECT_EQ(tether.params().iterations, 7);  // 10 * 3/4
  EXPECT_EQ(iterations.degraded(), "iterations 7 of 10");
  second(0.9, iterations);
  EXPECT_EQ(tether.params().iterations, 5);
  second(0.5, iterations);  // within the budget, above half of it: kept
  EXPECT_EQ(tether.params().iterations, 5);
  second(0.1, iterations);
  EXPECT_EQ(tether.params().iterations, 7);  // 5 * 4/3 + 1
  EXPECT_EQ(iterations.degraded(), "iterations 7 of 10");
  second(0.1, iterations);
  EXPECT_EQ(tether.params().iterations, 10);
  EXPECT_EQ(iterations.degraded(), "");

  second(0.9, markers);
  second(0.9, markers);
  EXPECT_DOUBLE_EQ(markers.markerRate(), 7.5);
  EXPECT_EQ(markers.degraded(), "markers at 7.50 Hz");
  EXPECT_EQ(tether.params().iterations, 10) << "reduce_markers keeps the iterations";
  markers.reconfigured(10);
  EXPECT_DOUBLE_EQ(markers.markerRate(), 30.0);
  EXPECT_EQ(markers.degraded(), "");
}

TEST(StateBuilder, StampsThePhysicsTimeAndMeasuresTheWinchSpeedBetweenStates)
{
  TetherParams params = quietParams();
  params.winch_mode = WinchMode::kSpeed;
  params.winch_speed = 0.5;
  Tether tether(params, Position::Zero(), 5.0);
  StateBuilder builder("world");
  tether.advanceTo(6.0);
  EXPECT_EQ(builder.state(tether, 0).winch_speed, 0.0) << "no speed from a single state";
  tether.advanceTo(7.0);
  const TetherState& state = builder.state(tether, 2);
  EXPECT_NEAR(state.header.stamp.toSec(), tether.time(), 1e-6);
  EXPECT_NEAR(state.winch_speed, 0.5, 0.05);
  EXPECT_EQ(state.resets, 2u);
  const auto wrench = builder.wrench(tether, Eigen::Vector3d::Zero());
  EXPECT_EQ(wrench.header.stamp, state.header.stamp);
  builder.restart(tether);
  tether.advanceTo(8.0);
  EXPECT_EQ(builder.state(tether, 3).winch_speed, 0.0) << "measured afresh after a reset";
}

}  // namespace
}  // namespace rov_tether::ros_layer
