// tether_node's pieces without a master: PoseInput (checks, frames, attachment, counting), Scheduler
// (clock policy, state grids, skips, a World of several tethers), LoadGovernor and StateBuilder.
#include <geometry_msgs/TwistStamped.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <tf2_ros/buffer.h>
#include <topic_tools/shape_shifter.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "../test_helpers.hpp"
#include "log_collector.hpp"
#include "rov_tether/core/world.hpp"
#include "rov_tether/ros/frame_schedule.hpp"
#include "rov_tether/ros/load_governor.hpp"
#include "rov_tether/ros/pose_input.hpp"
#include "rov_tether/ros/render_budget.hpp"
#include "rov_tether/ros/scheduler.hpp"
#include "rov_tether/ros/tether_publisher.hpp"

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

geometry_msgs::PoseStamped::ConstPtr shared(const geometry_msgs::PoseStamped& msg)
{
  return boost::make_shared<geometry_msgs::PoseStamped>(msg);
}

TEST(PoseInput, RefusesNonFiniteAndUnnormalisedPosesAndCountsThem)
{
  Tether tether(quietParams(), Position::Zero());
  tf2_ros::Buffer tf;
  PoseInput input(NodeOptions(), tf, tether);

  auto nan = poseMsg(std::nan(""), 0.0, -1.0, 1.0);
  EXPECT_EQ(checkPose(nan.pose), "position (x, y, z) = (nan, 0, -1) is not finite");  // which part, and its values
  auto turned = poseMsg(1.0, 0.0, -1.0, 1.0);
  turned.pose.orientation.z = std::numeric_limits<double>::infinity();
  EXPECT_EQ(checkPose(turned.pose), "orientation (x, y, z, w) = (0, 0, inf, 1) is not finite");
  // One reason with other values each time is one kind of warning, throttled together (once a second): the
  // values in checkPose's message (signs, points, exponents, nan and inf) each count as one number.
  EXPECT_EQ(warningKind("position (x, y, z) = (nan, 0.5, -1) is not finite"),
            warningKind("position (x, y, z) = (-nan, 12.25, 1e+06) is not finite"));
  EXPECT_EQ(warningKind("position (x, y, z) = (nan, 0.5, -1) is not finite"),
            "position (x, y, z) = (#, #, #) is not finite");
  EXPECT_NE(warningKind(checkPose(nan.pose)), warningKind(checkPose(turned.pose)));
  input.receive(shared(nan), ros::Time(1.0));
  auto unnormalised = poseMsg(1.0, 0.0, -1.0, 1.0);
  unnormalised.pose.orientation.w = 1.01;
  EXPECT_NE(checkPose(unnormalised.pose).find("not normalised"), std::string::npos);
  input.receive(shared(unnormalised), ros::Time(1.0));
  EXPECT_EQ(input.rejected(), 2u) << "refused as they arrive, before the physics sees them";
  input.poll(ros::Time(1.0));
  EXPECT_TRUE(input.lastPoseTime().isZero());
  EXPECT_EQ(input.accepted(), 0u);

  input.receive(shared(poseMsg(1.0, 0.0, -1.0, 2.0)), ros::Time(2.0));
  EXPECT_TRUE(input.lastPoseTime().isZero()) << "taken by the physics thread's poll, not on arrival";
  input.poll(ros::Time(2.005));
  EXPECT_EQ(input.lastPoseTime(), ros::Time(2.005));
  EXPECT_EQ(input.accepted(), 1u);
  // Older than the last sample: the core refuses it, the input counts it.
  input.receive(shared(poseMsg(1.5, 0.0, -1.0, 1.5)), ros::Time(2.1));
  input.poll(ros::Time(2.1));
  EXPECT_EQ(input.rejected(), 3u);
  EXPECT_NEAR(input.lastVehicle().translation().x(), 1.0, 1e-12);
  EXPECT_EQ(input.dropped(), 0u);
}

// A slow physics tick must not lose poses: they wait for the physics thread, up to kMaxHandOver (1 kHz
// for 4 s); beyond that the newest are dropped and counted, never silently.
TEST(PoseInput, PosesWaitForAStalledPhysicsAndOverflowIsCounted)
{
  TetherParams params = quietParams();
  Tether tether(params, Position::Zero(), 10.0);
  tf2_ros::Buffer tf;
  PoseInput input(NodeOptions(), tf, tether);
  // 1 kHz for 100 ms while the physics thread does not poll: all 100 wait, none is lost.
  for (int k = 0; k < 100; ++k)
  {
    input.receive(shared(poseMsg(1.0 + 1e-4 * k, 0.0, -1.0, 10.0 + 1e-3 * k)), ros::Time(10.0 + 1e-3 * k));
  }
  input.poll(ros::Time(10.1));
  EXPECT_EQ(input.accepted(), 100u);
  EXPECT_EQ(input.dropped(), 0u);
  // A stall longer than the hand-over holds: the excess is counted as dropped.
  for (std::size_t k = 0; k < PoseInput::kMaxHandOver + 10; ++k)
  {
    const double t = 10.1 + 1e-3 * static_cast<double>(k);
    input.receive(shared(poseMsg(1.0, 0.0, -1.0, t)), ros::Time(t));
  }
  EXPECT_EQ(input.dropped(), 10u);
  EXPECT_EQ(input.rejected(), 0u);
}

TEST(PoseInput, TransformsOtherFramesThroughTheSharedBufferAndAppliesTheAttachmentOffset)
{
  NodeOptions options;
  options.attachment_offset = Eigen::Vector3d(-0.5, 0.0, 0.0);  // 0.5 m behind the vehicle
  TetherParams params = quietParams();
  params.winch_mode = WinchMode::kStrain;
  Tether tether(params, Position::Zero(), 9.9);
  tf2_ros::Buffer tf;
  // The boat frame is 1 m along x and turned 90 degrees about z.
  const Eigen::Isometry3d boat =
      Eigen::Translation3d(1.0, 0.0, 0.0) * Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ());
  ASSERT_TRUE(tf.setTransform(transform("world", "boat", 10.0, boat), "test", true));
  PoseInput input(options, tf, tether);

  // 2 m ahead in the boat frame is world (1, 2, -1); the vehicle faces world y, so the attachment
  // 0.5 m behind it is world (1, 1.5, -1).
  input.receive(shared(poseMsg(2.0, 0.0, -1.0, 10.0, "boat")), ros::Time(10.0));
  input.poll(ros::Time(10.0));
  ASSERT_EQ(input.accepted(), 1u);
  EXPECT_TRUE(input.lastVehicle().translation().isApprox(Eigen::Vector3d(1.0, 2.0, -1.0), 1e-9));
  ASSERT_TRUE(test::succeeded(tether.advanceTo(10.0 + params.time_step)));
  ASSERT_TRUE(tether.vehicleAttached());
  const Position end = tether.particle(tether.deployedParticleCount() - 1);
  EXPECT_TRUE(end.isApprox(Position(1.0, 1.5, -1.0), 1e-6)) << end.transpose();

  // A frame tf does not know waits for its transform, and is refused once the physics passes its stamp.
  input.receive(shared(poseMsg(2.0, 0.0, -1.0, 10.1, "nowhere")), ros::Time(10.1));
  input.poll(ros::Time(10.1));
  EXPECT_EQ(input.rejected(), 0u) << "still waiting: the physics is at " << tether.time() << " s";
  ASSERT_TRUE(test::succeeded(tether.advanceTo(10.11)));
  input.poll(ros::Time(10.2));
  EXPECT_EQ(input.rejected(), 1u) << "an unknown frame is refused and counted";
  // A known frame, older than the tf buffer's 10 s: refused at once.
  ASSERT_TRUE(tf.setTransform(transform("world", "odom", 30.0, Eigen::Isometry3d::Identity()), "test"));
  input.receive(shared(poseMsg(2.0, 0.0, -1.0, 15.0, "odom")), ros::Time(30.0));
  EXPECT_EQ(input.rejected(), 2u);
}

TEST(PoseInput, PollsTheVehicleAndTheSpoolFromTfStaticTransformsIncluded)
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
  ASSERT_TRUE(test::succeeded(tether.advanceTo(1.0 + tether.params().time_step)));
  EXPECT_TRUE(tether.particle(0).isApprox(Position(0.0, 0.5, 0.0))) << "the spool follows spool_frame";
  input.poll(ros::Time(1.2));  // the same transform again: not a new pose
  EXPECT_EQ(input.lastPoseTime(), ros::Time(1.1));
  EXPECT_EQ(input.rejected(), 0u);

  // A vehicle frame published as a static transform (stamp 0) holds at every time: taken at each poll.
  Tether still(quietParams(), Position::Zero());
  tf2_ros::Buffer static_tf;
  PoseInput static_input(options, static_tf, still);
  ASSERT_TRUE(static_tf.setTransform(transform("world", "rov", 0.0, rov), "test", true));
  static_input.poll(ros::Time(5.0));
  static_input.poll(ros::Time(5.005));
  EXPECT_EQ(static_input.accepted(), 2u);
  EXPECT_EQ(static_input.lastPoseTime(), ros::Time(5.005));
  ASSERT_TRUE(test::succeeded(still.advanceTo(5.0 + still.params().time_step)));
  ASSERT_TRUE(still.vehicleAttached());
  EXPECT_TRUE(still.particle(still.deployedParticleCount() - 1).isApprox(Position(2.0, 0.0, -1.0)));
}

/// Records what the scheduler asks of a tether.
class RecordingHooks : public TetherHooks
{
 public:
  explicit RecordingHooks(const Tether& tether) : tether_(tether) {}
  void publishState() override { state_times.push_back(tether_.time()); }
  void beforeAdvance(const ros::Time&) override { ++before; }
  void afterAdvance(const ros::Time&) override { ++after; }
  void restarted(const ros::Time&) override { ++restarts; }
  bool watchesSteps() const override { return watch_steps; }
  void stepped(double /*delay*/) override { step_times.push_back(tether_.time()); }

  std::vector<double> state_times;
  std::vector<double> step_times;  ///< The tether's time at each stepped() call.
  bool watch_steps = false;
  int before = 0, after = 0, restarts = 0;

 private:
  const Tether& tether_;
};

struct OneTether
{
  explicit OneTether(const NodeOptions& options = NodeOptions(), TetherParams params = quietParams())
  {
    const Status added = world.add("t", std::make_unique<Tether>(params, Position::Zero()));
    if (!added.ok)
    {
      throw std::logic_error("world.add: " + added.message);  // a constructor cannot ASSERT; gtest reports it
    }
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

// A clock starting at 0 (a simulator's, a bag's from its start) puts the physics interpolation_delay (0.1 s)
// behind it, at negative times. Their states were published with the stamp clamped to 0: several ~state and tf at
// stamp 0 (tf's TF_REPEATED_DATA). Now nothing is published before time 0, and the states after it keep the grid,
// each time once.
TEST(Scheduler, NothingIsPublishedBeforeTimeZero)
{
  OneTether t;
  for (double now = 0.0033; now < 0.4; now += 0.005)
  {
    t.scheduler.tick(ros::Time(now));
  }
  ASSERT_LT(t.world.tether(0).time(), 0.3);
  ASSERT_GE(t.hooks->state_times.size(), 5u);  // 0 to about 0.29 s on the 1/30 s grid
  for (std::size_t k = 0; k < t.hooks->state_times.size(); ++k)
  {
    EXPECT_GE(t.hooks->state_times[k], 0.0) << k;
    if (k > 0)
    {
      EXPECT_GT(t.hooks->state_times[k], t.hooks->state_times[k - 1]) << k;
    }
  }
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
  EXPECT_EQ(t.hooks->before, t.hooks->after);
}

// Item 12 of issue 26: an 8000 x 8000 camera image took the node 7.58 s to render, and the next tick took
// the ROS time that had passed meanwhile for a clock jump: "time jumped forwards by 7.58 s: resetting the
// tether". ROS time that passed with the wall clock is the node's own stall: the physics skips ahead
// (max_lag) with the cable held, no reset. A clock that leaps while the wall clock does not is a jump.
TEST(Scheduler, TheNodesOwnStallIsNoClockJump)
{
  OneTether t;
  t.wall = ros::WallTime(1000.0);
  t.scheduler.tick(ros::Time(50.0));
  t.wall += ros::WallDuration(0.005);
  t.scheduler.tick(ros::Time(50.005));
  t.wall += ros::WallDuration(7.58);  // the node rendered for 7.58 s; ROS time went on with the wall
  t.scheduler.tick(ros::Time(57.585));
  EXPECT_EQ(t.scheduler.schedule(0).resets, 0u) << "a stall is no clock jump";
  EXPECT_EQ(t.scheduler.schedule(0).skips, 1u) << "7.58 s behind, more than max_lag: skipped ahead, counted";
  EXPECT_NEAR(t.world.tether(0).time(), 57.485, 0.005 + 1e-9);  // on the 5 ms step grid
  t.wall += ros::WallDuration(0.005);
  t.scheduler.tick(ros::Time(117.59));  // ROS time leaps 60 s in 5 ms of wall time: a jump
  EXPECT_EQ(t.scheduler.schedule(0).resets, 1u);
}

// Item 12 of issue 26, the camera's part: the 8000 x 8000 frame took 7.58 s, at the rate of about
// 0.12 us a pixel. Once a camera has measured its cost, a frame predicted beyond the budget (max_lag,
// 1 s) is skipped with a reason that names its size; a 320 x 240 frame (9 ms at that rate) is drawn.
TEST(RenderBudget, AFrameTooBigForItsBudgetIsSkippedAndSaid)
{
  RenderBudget budget(1.0);
  EXPECT_TRUE(budget.allows(8000.0 * 8000.0, 0.0)) << "the first frame measures the cost";
  budget.measured(8000.0 * 8000.0, 7.58);
  EXPECT_FALSE(budget.allows(8000.0 * 8000.0, 0.1));
  const std::string why = budget.why(8000, 8000);
  EXPECT_NE(why.find("8000x8000"), std::string::npos) << why;
  EXPECT_NE(why.find("7.58 s"), std::string::npos) << why;
  EXPECT_NE(why.find("skipped"), std::string::npos) << why;
  EXPECT_TRUE(budget.allows(320.0 * 240.0, 0.2));
  budget.measured(320.0 * 240.0, 0.004);  // the small frame measures the cost again
  EXPECT_TRUE(budget.allows(1000.0 * 1000.0, 0.3)) << "52 ms at 52 ns a pixel";
}

// A cost measured while the machine was busy does not skip a camera for good (a review of issue 26's item 12:
// nothing drawn, nothing measured again). A camera of fixed size whose one frame took 7.58 s skips its
// frames for RenderBudget::kFirstRetry, then draws one to measure again; still too slow, it waits twice as
// long before the next try (so a frame that is really too big stalls the node ever more rarely, at most once
// in kLastRetry); once a frame measures within the budget (the machine is idle again), every frame is drawn.
TEST(RenderBudget, ACameraSkippingFramesMeasuresAgainEverOnceInAWhile)
{
  const double pixels = 8000.0 * 8000.0, first = RenderBudget::kFirstRetry;
  RenderBudget budget(1.0);
  ASSERT_TRUE(budget.allows(pixels, 0.0));
  budget.measured(pixels, 7.58);  // a busy machine
  EXPECT_FALSE(budget.allows(pixels, 8.0));
  EXPECT_FALSE(budget.allows(pixels, 8.0 + 0.99 * first));
  EXPECT_TRUE(budget.allows(pixels, 8.0 + first)) << "drawn again to measure, after kFirstRetry of skipping";
  budget.measured(pixels, 7.58);  // still too slow: the next try comes after twice as long
  EXPECT_FALSE(budget.allows(pixels, 30.0));
  EXPECT_FALSE(budget.allows(pixels, 30.0 + 1.99 * first));
  EXPECT_TRUE(budget.allows(pixels, 30.0 + 2.0 * first));
  budget.measured(pixels, 0.5);  // the machine is idle again: within the budget
  EXPECT_TRUE(budget.allows(pixels, 60.0));
  EXPECT_TRUE(budget.allows(pixels, 60.1));
  // The wait never grows beyond kLastRetry.
  for (int k = 0; k < 20; ++k)
  {
    budget.measured(pixels, 7.58);
    budget.allows(pixels, 1e4 * (k + 1));  // the first skip of a run of skips
  }
  EXPECT_EQ(budget.retry(), RenderBudget::kLastRetry);
}

// Review of the camera node, item 2: a camera at a fixed rate went silent after physics time went back
// (a bag played in a loop): its schedule started again only when its next frame time fell below the oldest
// shape kept, but after a jump back the shapes start over at the new time, far below it, and the camera
// waited for the physics to come back there (100 s here). Now the schedule starts again, said as
// kRestarted, once its next time lies more than one period past the newest shape. A 10 Hz camera, the
// physics ticking at 100 Hz and 1 s of shapes kept, as in the node.
TEST(FrameSchedule, AFixedRateCameraStartsAgainWhenPhysicsTimeGoesBack)
{
  FrameSchedule schedule(10.0);
  std::vector<double> frames;
  int first = 0, restarted = 0;
  const auto tick = [&](double oldest, double newest)
  {
    FrameSchedule::Start start = FrameSchedule::Start::kKept;
    for (const double t : schedule.due(oldest, newest, &start))
    {
      frames.push_back(t);
    }
    first += start == FrameSchedule::Start::kFirst;
    restarted += start == FrameSchedule::Start::kRestarted;
  };
  const auto run = [&](double from, double to)
  {
    for (int k = 0; from + 0.01 * k <= to + 1e-9; ++k)
    {
      const double t = from + 0.01 * k;
      tick(std::max(from, t - 1.0), t);
    }
  };
  run(150.0, 152.0);
  ASSERT_EQ(frames.size(), 21u) << "150.0, 150.1, ..., 152.0";
  EXPECT_EQ(first, 1);
  EXPECT_EQ(restarted, 0) << "a schedule going on as the physics goes is kept";
  for (std::size_t k = 0; k < frames.size(); ++k)
  {
    EXPECT_NEAR(frames[k], 150.0 + 0.1 * k, 1e-9);
  }
  // The bag starts over 100 s earlier: the shapes start over at 50 s (ShapeHistory clears when time goes back).
  frames.clear();
  run(50.0, 51.0);
  EXPECT_EQ(restarted, 1);
  ASSERT_EQ(frames.size(), 11u) << "50.0, 50.1, ..., 51.0: the camera does not wait for 152.1 s";
  for (std::size_t k = 0; k < frames.size(); ++k)
  {
    EXPECT_NEAR(frames[k], 50.0 + 0.1 * k, 1e-9);
  }
  // Physics time jumping ahead past the shapes kept starts it again too (as before), at the newest shape.
  frames.clear();
  tick(60.0, 60.0);
  EXPECT_EQ(restarted, 2);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_NEAR(frames[0], 60.0, 1e-9);
  // At ROS times of wall clocks (1.7e9 s), the grid's rounding never reads as a jump.
  FrameSchedule wall(30.0);
  int wall_restarts = 0;
  std::size_t wall_frames = 0;
  for (int k = 0; k < 300; ++k)
  {
    const double t = 1.7e9 + 0.01 * k;
    FrameSchedule::Start start = FrameSchedule::Start::kKept;
    wall_frames += wall.due(t - 1.0, t, &start).size();
    wall_restarts += start == FrameSchedule::Start::kRestarted;
  }
  EXPECT_EQ(wall_restarts, 0);
  EXPECT_NEAR(static_cast<double>(wall_frames), 90.0, 1.0);
}

// A node whose physics cannot hold real time falls more than max_lag behind on every tick (here each
// tick comes 0.2371 s after the last, max_lag 0.1 s): it must keep publishing, at least one ~state a
// skip (docs/node.md, "when the physics cannot keep up"; overload.test). Resumed on the old state
// grid, a skip left the next state point past the tick's target, and nothing was published unless a skip
// happened to land on the grid: 0-2 states in overload.test's 120 s under the sanitizers.
TEST(Scheduler, FallingBehindOnEveryTickStillPublishesAtEachSkip)
{
  NodeOptions options;
  options.max_lag = 0.1;
  OneTether t(options);
  double now = 100.0033;
  t.scheduler.tick(ros::Time(now));
  const std::size_t published = t.hooks->state_times.size();
  const int ticks = 40;
  for (int k = 0; k < ticks; ++k)
  {
    now += 0.2371;
    t.scheduler.tick(ros::Time(now));
    ASSERT_EQ(t.scheduler.schedule(0).skips, static_cast<std::uint64_t>(k + 1));
    // The state published last is the held cable at the skip: the tether's time now.
    ASSERT_FALSE(t.hooks->state_times.empty());
    EXPECT_DOUBLE_EQ(t.hooks->state_times.back(), t.world.tether(0).time());
  }
  EXPECT_GE(t.hooks->state_times.size() - published, static_cast<std::size_t>(ticks));
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
  ASSERT_TRUE(test::succeeded(world.add("fast", std::make_unique<Tether>(fine, Position::Zero()))));
  ASSERT_TRUE(test::succeeded(world.add("slow", std::make_unique<Tether>(coarse, Position::Zero()))));
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
      ASSERT_TRUE(test::succeeded(tether->addVehicleSample(now, Position(x, 0.0, -1.0))));
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

// ~coupling is published after every internal step of its tether: a watched tether is told once per step, at
// the step's end, and the world (two tethers of different steps, in lockstep) moves exactly as unwatched, with
// the same ~state points.
TEST(Scheduler, AWatchedTetherIsToldAfterEachOfItsStepsAndTheWorldMovesAsUnwatched)
{
  NodeOptions options;
  TetherParams fine = quietParams(), coarse = quietParams();
  coarse.time_step = 0.01;
  struct Run
  {
    World world;
    std::unique_ptr<Scheduler> scheduler;
    std::unique_ptr<RecordingHooks> fine_hooks, coarse_hooks;
  };
  auto make = [&](Run& run, bool watch)
  {
    ASSERT_TRUE(test::succeeded(run.world.add("fine", std::make_unique<Tether>(fine, Position::Zero()))));
    ASSERT_TRUE(test::succeeded(run.world.add("coarse", std::make_unique<Tether>(coarse, Position::Zero()))));
    run.scheduler = std::make_unique<Scheduler>(run.world, options.interpolation_delay, [] { return ros::WallTime(); });
    run.fine_hooks = std::make_unique<RecordingHooks>(run.world.tether(0));
    run.coarse_hooks = std::make_unique<RecordingHooks>(run.world.tether(1));
    run.coarse_hooks->watch_steps = watch;
    run.scheduler->add(options, *run.fine_hooks, "fine");
    run.scheduler->add(options, *run.coarse_hooks, "coarse");
  };
  Run watched, unwatched;
  make(watched, true);
  make(unwatched, false);
  double coarse_start = std::nan("");
  for (double now = 20.0; now < 21.0; now += 0.0137)  // ticks off both step grids
  {
    const double x = 1.0 + 0.5 * (now - 20.0);
    for (Run* run : {&watched, &unwatched})
    {
      for (std::size_t i = 0; i < 2; ++i)
      {
        ASSERT_TRUE(test::succeeded(run->world.tether(i).addVehicleSample(now, Position(x, 0.0, -1.0))));
      }
      run->scheduler->tick(ros::Time(now));
    }
    if (std::isnan(coarse_start))
    {
      coarse_start = watched.world.tether(1).time();  // after the first tick, which starts the tethers
    }
  }
  const std::vector<double>& steps = watched.coarse_hooks->step_times;
  ASSERT_GT(steps.size(), 50u);
  EXPECT_LE(steps.front(), coarse_start + 0.01 + 1e-9) << "from the first step on";
  for (std::size_t k = 1; k < steps.size(); ++k)
  {
    EXPECT_NEAR(steps[k] - steps[k - 1], 0.01, 1e-9) << "at each step's end, none twice, none left out";
  }
  EXPECT_DOUBLE_EQ(steps.back(), watched.world.tether(1).time());
  EXPECT_TRUE(watched.fine_hooks->step_times.empty()) << "an unwatched tether is not told";
  EXPECT_TRUE(unwatched.coarse_hooks->step_times.empty());
  EXPECT_EQ(watched.fine_hooks->state_times, unwatched.fine_hooks->state_times);
  EXPECT_EQ(watched.coarse_hooks->state_times, unwatched.coarse_hooks->state_times);
  EXPECT_EQ(test::positions(watched.world.tether(0)), test::positions(unwatched.world.tether(0)));
  EXPECT_EQ(test::positions(watched.world.tether(1)), test::positions(unwatched.world.tether(1)));
}

/// RecordingHooks whose beforeAdvance (parameters applied, poses polled) takes `cost` [s] on a test's clock.
class CostlyHooks : public RecordingHooks
{
 public:
  CostlyHooks(const Tether& tether, ros::WallTime& wall, double cost) : RecordingHooks(tether), wall_(wall), cost_(cost)
  {
  }
  void beforeAdvance(const ros::Time& now) override
  {
    RecordingHooks::beforeAdvance(now);
    wall_ += ros::WallDuration(cost_);
  }

 private:
  ros::WallTime& wall_;
  double cost_;
};

TEST(Scheduler, ChargesEachTetherItsOwnMeasuredTimeAndOnlyTheOverloadedTetherDegrades)
{
  NodeOptions options;
  options.cpu_budget = 0.3;
  TetherParams light = quietParams(), heavy = quietParams();
  light.iterations = 2;
  heavy.iterations = 40;
  World world;
  ASSERT_TRUE(test::succeeded(world.add("light", std::make_unique<Tether>(light, Position::Zero()))));
  ASSERT_TRUE(test::succeeded(world.add("heavy", std::make_unique<Tether>(heavy, Position::Zero()))));
  // A wall clock on which every reading takes 0.1 ms, the heavy tether's steps 4 ms each whatever its
  // iterations (as on the machine, where `direct` converges in a few Newton iterations, so giving up
  // configured ones saves little), and its hooks' beforeAdvance 4 ms. Ticks 5 ms apart in ROS time, each
  // with one step of each tether.
  ros::WallTime wall(1000.0);
  std::uint64_t heavy_steps_seen = 0;
  Scheduler scheduler(world, options.interpolation_delay,
                      [&]
                      {
                        const std::uint64_t heavy_steps = world.tether(1).stepCount();
                        wall += ros::WallDuration(heavy_steps != heavy_steps_seen ? 0.004 : 0.0001);
                        heavy_steps_seen = heavy_steps;
                        return wall;
                      });
  RecordingHooks hooks_light(world.tether(0));
  CostlyHooks hooks_heavy(world.tether(1), wall, 0.004);
  scheduler.add(options, hooks_light, "light");
  scheduler.add(options, hooks_heavy, "heavy");
  // 15 s: the heavy tether gives up a quarter of its iterations a window (a second of wall time), 40 down to
  // min_iterations (2) in 9 windows, and its steps and hooks still cost 4 ms each.
  for (double now = 10.0; now < 25.0; now += 0.005)
  {
    scheduler.tick(ros::Time(now));
  }
  EXPECT_EQ(world.tether(1).params().iterations, options.min_iterations);
  EXPECT_EQ(scheduler.governor(1).degraded().rfind("iterations ", 0), 0u) << scheduler.governor(1).degraded();
  // Each tether's calls on a tick: beforeAdvance, prepare, its step, and publishState on one tick in 6.7
  // (state_rate 30 Hz); each timed by two readings. A tick reads the clock 14 times (18 with ~state),
  // so it takes 9.4 to 9.8 ms of wall time. The light tether is charged its 3-4 intervals of 0.1 ms and
  // half of what no interval holds (the 6-8 readings that open them and the tick's last: 0.35-0.45 ms),
  // at most 0.85 / 9.4 = 9%; the heavy one at least its step and its hook, 8 + 0.35 of 9.8 ms: 85%.
  // Were the steps not timed (the observer), or the hooks' calls, half of those 4 ms would go to the light
  // one: 2 / 9.8 = 20% more. Shared by configured work instead (particles x iterations, as this scheduler
  // once did), the light tether's share grew to the heavy one's as that gave iterations up.
  const double light_load = scheduler.governor(0).physicsLoad(), heavy_load = scheduler.governor(1).physicsLoad();
  std::printf("[ measured ] physics load: light %.3f (2 iterations), heavy %.3f (%d iterations)\n", light_load,
              heavy_load, world.tether(1).params().iterations);
  EXPECT_GT(heavy_load, 0.85);
  EXPECT_LT(light_load, 0.09 + 1e-9);
  EXPECT_LE(light_load + heavy_load, 1.0);  // nothing charged twice
  EXPECT_EQ(world.tether(0).params().iterations, 2);
  EXPECT_EQ(scheduler.governor(0).degraded(), "");
}

/// One tether as tether_node runs it, without a master: its PoseInput polled before the physics, the
/// Scheduler's 200 Hz tick on an injected clock, and what each ~state would carry recorded.
struct NodeRig : TetherHooks
{
  NodeRig(const TetherParams& params, const NodeOptions& node_options = NodeOptions())
      : options(node_options), scheduler(world, options.interpolation_delay, [] { return ros::WallTime(); })
  {
    const Status added = world.add("t", std::make_unique<Tether>(params, Position::Zero()));
    if (!added.ok)
    {
      throw std::logic_error("world.add: " + added.message);  // a constructor cannot ASSERT; gtest reports it
    }
    input = std::make_unique<PoseInput>(options, tf, world.tether(0));
    scheduler.add(options, *this);
  }
  Tether& tether() { return world.tether(0); }
  void beforeAdvance(const ros::Time& now) override { input->poll(now); }
  void publishState() override
  {
    if (!tether().vehicleAttached())
    {
      return;
    }
    times.push_back(tether().time());
    tensions.push_back(tether().summary().tension_vehicle);
    ends.push_back(tether().particle(tether().deployedParticleCount() - 1));
    vehicles.push_back(input->vehicleAt(tether().time()).translation());  // as ~markers and ~wrench place it
  }
  void restarted(const ros::Time& now) override { input->reset(now); }
  PoseTiming poseTiming() const override { return PoseTiming{input->latestStamp(), input->neededDelay()}; }
  ros::Time earliestArrival() const override { return input->earliestArrival(); }

  NodeOptions options;
  World world;
  tf2_ros::Buffer tf;
  std::unique_ptr<PoseInput> input;
  Scheduler scheduler;
  std::vector<double> times, tensions;
  std::vector<Position> ends, vehicles;
};

/// A vehicle passing the spool at 1.5 m/s for 14 s (then still), its poses at `rate`, each arriving
/// `latency` after its stamp, run through the node's pieces (with `options`) from t = 100 s to 118 s.
std::unique_ptr<NodeRig> passAtRate(double rate, double latency = 0.02, const NodeOptions& options = NodeOptions())
{
  TetherParams params;
  params.cable_length = 30.0;
  params.max_winch_speed = 2.0;  // the winch can follow the vehicle's 1.5 m/s
  auto rig = std::make_unique<NodeRig>(params, options);
  const auto vehicle = [](double t) { return Position(2.0, -10.5 + 1.5 * std::min(t - 100.0, 14.0), -1.0); };
  int next = 0;
  for (int tick = 0; tick <= 18 * 200; ++tick)
  {
    const double now = 100.0 + tick * 0.005;
    for (; 100.0 + next / rate + latency <= now + 1e-9; ++next)
    {
      const double stamp = 100.0 + next / rate;
      const Position p = vehicle(stamp);
      rig->input->receive(shared(poseMsg(p.x(), p.y(), p.z(), stamp)), ros::Time(stamp + latency));
    }
    rig->scheduler.tick(ros::Time(now));
  }
  return rig;
}

// Item 1 of issue 13: 1 Hz poses (USBL) used to leave the cable end holding for 0.9 s and then leaping
// 1.35 m in one step. The physics now runs as far behind ROS time as the poses need to bracket it, and
// never passes the latest pose, so the end moves between fixes as the vehicle did. The bounds:
// - no jump: consecutive fixes 1.5 m apart in 1 s are within max_vehicle_speed x dt + max_vehicle_jump;
// - smooth: between two ~states dt apart the end moves at most 1.5 m/s x dt (the vehicle's speed);
// - no tension from the rate: the vehicle's path is a straight line at a constant speed, and linear
//   interpolation of a straight line is exact whatever the samples, so at 1 and 5 Hz the cable moves as
//   at 50 Hz: the end within rounding (1e-9 m) and the tension at the vehicle within 1e-6 N (the
//   rounding, 1e-15 of the positions, divided by h^2 in the readout: 1e-8 N, with room to spare).
TEST(PoseRates, SparsePosesMoveTheCableEndSmoothlyAndAsDensePosesDo)
{
  const auto reference = passAtRate(50.0);
  for (const double rate : {1.0, 5.0, 50.0})
  {
    const auto run = rate == 50.0 ? passAtRate(50.0) : passAtRate(rate);
    const NodeRig& r = *run;
    EXPECT_EQ(r.world.tether(0).jumpCount(), 0u) << rate << " Hz";
    EXPECT_EQ(r.input->rejected(), 0u) << rate << " Hz";
    ASSERT_GT(r.times.size(), 400u) << rate << " Hz";
    double fastest = 0.0;
    for (std::size_t k = 1; k < r.times.size(); ++k)
    {
      fastest = std::max(fastest, (r.ends[k] - r.ends[k - 1]).norm() / (r.times[k] - r.times[k - 1]));
    }
    double tension_difference = 0.0, end_difference = 0.0, peak = 0.0;
    std::size_t compared = 0;
    for (std::size_t k = 0, j = 0; k < r.times.size(); ++k)
    {
      for (; j < reference->times.size() && reference->times[j] < r.times[k] - 1e-9; ++j)
      {
      }
      if (j < reference->times.size() && std::abs(reference->times[j] - r.times[k]) < 1e-9)
      {
        tension_difference = std::max(tension_difference, std::abs(r.tensions[k] - reference->tensions[j]));
        end_difference = std::max(end_difference, (r.ends[k] - reference->ends[j]).norm());
        peak = std::max(peak, std::abs(reference->tensions[j]));
        ++compared;
      }
    }
    std::printf(
        "[ measured ] %4.0f Hz poses: physics %.3f s behind ROS time, end at most %.4f m/s, %zu states "
        "against 50 Hz: end %.1e m, tension at the vehicle %.1e N apart (peak %.2f N)\n",
        rate, r.scheduler.delay(), fastest, compared, end_difference, tension_difference, peak);
    EXPECT_LE(fastest, 1.5 * (1.0 + 1e-6)) << rate << " Hz";
    EXPECT_GT(compared, 400u) << rate << " Hz";
    EXPECT_LT(end_difference, 1e-9) << rate << " Hz";
    EXPECT_LT(tension_difference, 1e-6) << rate << " Hz";
    // The delay follows the poses: one gap (period + 20 ms latency + up to a 5 ms tick) for 1 Hz, and
    // interpolation_delay when the poses come closer than it.
    EXPECT_LE(r.scheduler.delay(), std::max(0.1, 1.0 / rate + 0.02 + 0.005) + 1e-9) << rate << " Hz";
    EXPECT_GE(r.scheduler.delay(), std::max(0.1, 1.0 / rate + 0.02) - 1e-9) << rate << " Hz";
  }
}

/// A vehicle moving along y at `speed` from t = 100 s, its poses at 20 Hz arriving 20 ms after their stamps, with
/// none from 104 s to 114 s; from then on it is `away` further along than the constant speed puts it (where it went
/// in the gap). Run through the node's pieces to 120 s.
std::unique_ptr<NodeRig> gapInThePoses(double speed, double away)
{
  TetherParams params;
  params.cable_length = 30.0;
  params.max_winch_speed = 2.0;
  auto rig = std::make_unique<NodeRig>(params);
  const auto vehicle = [&](double t)
  { return Position(2.0, -2.0 + speed * (t - 100.0) + (t > 110.0 ? away : 0.0), -1.0); };
  const double latency = 0.02, rate = 20.0;
  int next = 0;
  for (int tick = 0; tick <= 20 * 200; ++tick)
  {
    const double now = 100.0 + tick * 0.005;
    for (; 100.0 + next / rate + latency <= now + 1e-9; ++next)
    {
      const double stamp = 100.0 + next / rate;
      if (stamp > 104.0 + 1e-9 && stamp < 114.0 - 1e-9)
      {
        continue;  // the gap
      }
      const Position p = vehicle(stamp);
      rig->input->receive(shared(poseMsg(p.x(), p.y(), p.z(), stamp)), ros::Time(stamp + latency));
    }
    rig->scheduler.tick(ros::Time(now));
  }
  return rig;
}

// Poses that stop for longer than stale_pose_timeout (2 s): the physics goes on with the vehicle held where it was
// last, up to 2 s behind ROS time. When they come back the end must go from where it was held, over the time the
// physics has left to the new pose's stamp: at least stale_pose_timeout less the latency and a tick (1.975 s). A
// vehicle at 0.3 m/s has gone 3 m in the 10 s gap, so the end moves at most 3 m / 1.975 s, within the 3 m/s that
// is no jump: none is counted and nothing is re-laid. (It went from the pose's own stamp, 10 s before: it had
// used most of that already, and leapt most of the 3 m in one step, 73 kN on the brake's tether in the node.) A
// vehicle that turns up 8 m further than that could not have got there in the time left (3 m/s x 1.975 s + 1 m):
// a jump, counted, and the cable re-laid to it.
TEST(PoseRates, AfterAGapInThePosesTheEndGoesOnFromWhereItWasHeld)
{
  const auto run = gapInThePoses(0.3, 0.0);
  const NodeRig& r = *run;
  double fastest = 0.0, at = 0.0, apart = 0.0;
  for (std::size_t k = 0; k < r.times.size(); ++k)
  {
    apart = std::max(apart, (r.vehicles[k] - r.ends[k]).norm());  // the vehicle drawn where the cable ends
  }
  for (std::size_t k = 1; k < r.times.size(); ++k)
  {
    const double speed = (r.ends[k] - r.ends[k - 1]).norm() / (r.times[k] - r.times[k - 1]);
    if (speed > fastest)
    {
      fastest = speed, at = r.times[k];
    }
  }
  const double least_time = 2.0 - 0.02 - 0.005;
  std::printf(
      "[ measured ] 10 s without poses, then 3 m further on: the end at most %.3f m/s (at %.2f s), %zu "
      "states, %llu jumps, peak tension at the vehicle %.1f N\n",
      fastest, at, r.times.size(), static_cast<unsigned long long>(r.world.tether(0).jumpCount()),
      *std::max_element(r.tensions.begin(), r.tensions.end()));
  ASSERT_GT(r.times.size(), 150u);
  EXPECT_LE(fastest, 3.0 / least_time * (1.0 + 1e-6));
  EXPECT_LT(apart, 1e-9) << "the vehicle ~markers and ~wrench place follows the end (no attachment offset)";
  EXPECT_EQ(r.world.tether(0).jumpCount(), 0u);
  EXPECT_EQ(r.world.tether(0).recoveryCount(), 0u);
  EXPECT_EQ(r.input->rejected(), 0u);
  EXPECT_EQ(r.input->late(), 0u) << "one outage is not poses late as a rule (the stale-pose warning said it)";
  const auto far = gapInThePoses(0.3, 8.0);
  EXPECT_EQ(far->world.tether(0).jumpCount(), 1u);
  EXPECT_EQ(far->world.tether(0).recoveryCount(), 0u);
}

// A bag that loops: its last pose arrives after the last physics tick of its clock (the clock stops with
// the bag), and then the clock goes back to the bag's start. That pose, from the old time line, must not
// be taken after the reset: newer than every pose of the next loop, it would have every one refused. The
// tether restarts at the arrival of the first pose on the new clock, not at the tick that noticed (whose
// time depends on when /clock messages come), so every loop restarts the same.
TEST(PoseInput, APoseLeftFromALoopedBagDoesNotStopTheNextLoop)
{
  NodeRig rig(quietParams());
  std::uint64_t steps_at_first_tick = 0;
  const auto loop = [&](double first_tick)
  {
    for (int k = 0; k <= 400; ++k)  // 20 s of poses at 20 Hz, each before the ticks of the next 50 ms
    {
      const double t = 1000.0 + 0.05 * k;
      rig.input->receive(shared(poseMsg(2.0 + 0.01 * k, 0.0, -1.0, t)), ros::Time(t));
      for (double now = std::max(t + 0.005, first_tick); now <= t + 0.05 + 1e-9 && k < 400; now += 0.005)
      {
        const std::uint64_t before = rig.tether().stepCount();
        rig.scheduler.tick(ros::Time(now));
        steps_at_first_tick =
            k == 0 && now == std::max(t + 0.005, first_tick) ? rig.tether().stepCount() - before : steps_at_first_tick;
      }
    }
  };
  loop(1000.005);  // the clock stops with the bag, before its last pose is taken
  const std::uint64_t taken = rig.input->accepted();
  EXPECT_EQ(taken, 400u);
  loop(1000.03);  // the clock goes back to 1000 s, the first tick at 1000.03: a reset, the dive again
  EXPECT_EQ(rig.scheduler.schedule(0).resets, 1u);
  EXPECT_EQ(rig.input->rejected(), 1u) << "the left-over pose, refused and counted";
  EXPECT_EQ(rig.input->accepted() - taken, 400u) << "every pose of the second loop is taken (but its own last)";
  // Restarted at the first pose's arrival (physics 999.9 s), not at the tick (999.93 s): the first tick
  // then takes the 6 steps to 999.93 s.
  EXPECT_EQ(steps_at_first_tick, 6u);
}

// The same loop with the new clock's first tick 0.12 s in (/clock messages can come sparsely): three poses of the
// new clock wait for it. The tether restarted at the first one's arrival, and the poses that arrived after that
// time were refused as from the old clock: the second and third, valid, with "poses that arrived before the clock
// went back". What arrived after the tick's own time came on the old clock; the rest is the new clock's.
TEST(PoseInput, PosesOfTheNewClockWaitingForItsFirstTickAreTaken)
{
  NodeRig rig(quietParams());
  const auto loop = [&](double first_tick)
  {
    for (int k = 0; k <= 400; ++k)
    {
      const double t = 1000.0 + 0.05 * k;
      rig.input->receive(shared(poseMsg(2.0 + 0.01 * k, 0.0, -1.0, t)), ros::Time(t));
      for (double now = std::max(t + 0.005, first_tick); now <= t + 0.05 + 1e-9 && k < 400; now += 0.005)
      {
        rig.scheduler.tick(ros::Time(now));
      }
    }
  };
  loop(1000.005);
  const std::uint64_t taken = rig.input->accepted();
  ASSERT_EQ(taken, 400u);
  loop(1000.12);  // poses at 1000.00, 1000.05 and 1000.10 s before the first tick
  EXPECT_EQ(rig.scheduler.schedule(0).resets, 1u);
  EXPECT_EQ(rig.input->rejected(), 1u) << "only the left-over pose of the old clock";
  EXPECT_EQ(rig.input->accepted() - taken, 400u) << "every pose of the second loop (but its own last)";
}

// ~reset while poses flow: a pose of the vehicle before the reset can reach the physics after it, still
// queued or delivered late by a busy subscriber thread (it made node.test's startFresh read 5.52 m after a
// reset in a sanitizer build; one stamped ahead of the node's clock failed ResetServiceResets in CI). Taken,
// it lays the fresh cable out to where the vehicle was, 5.5 m out, and the brake winch keeps that length when
// the vehicle shows up at home. Refused (counted), the first pose stamped after the reset attaches the
// vehicle at home, 1.58 m from the spool: the cable is laid out at initial_deployed_length (2 m), which the
// brake keeps while the vehicle pulls nothing.
TEST(PoseInput, APoseFromBeforeARequestedResetDoesNotLayTheCableOut)
{
  NodeRig rig(quietParams());
  double t = 1000.0;
  for (; t < 1002.0; t += 0.05)  // the vehicle 5.5 m out, taken
  {
    rig.input->receive(shared(poseMsg(5.5, 0.0, -0.5, t)), ros::Time(t));
    rig.scheduler.tick(ros::Time(t + 0.01));
  }
  ASSERT_GT(rig.tether().deployedLength(), 5.5);
  const std::uint64_t rejected = rig.input->rejected();
  rig.input->receive(shared(poseMsg(5.5, 0.0, -0.5, t)), ros::Time(t));  // queued: no tick takes it before
  // Queued too, and stamped after the reset: its publisher's clock runs ahead of the node's (node.test's
  // harness publishes the clock and the poses, and the node's ros::Time::now() can lag by a tick or more).
  rig.input->receive(shared(poseMsg(5.5, 0.0, -0.5, t + 0.008)), ros::Time(t));
  const ros::Time reset_at(t + 0.005);
  const ros::Time cut = rig.input->resetCut(reset_at);  // what TetherNode::onReset does
  rig.scheduler.reset(0, reset_at, "reset requested");
  rig.input->refuseStampedBefore(cut);
  rig.input->receive(shared(poseMsg(5.5, 0.0, -0.5, t + 0.004)), ros::Time(t + 0.01));  // delivered late
  for (t += 0.02; t < 1004.0; t += 0.05)                                                // home, stamped after the reset
  {
    rig.input->receive(shared(poseMsg(1.5, 0.0, -0.5, t)), ros::Time(t));
    rig.scheduler.tick(ros::Time(t + 0.01));
  }
  ASSERT_TRUE(rig.tether().vehicleAttached());
  EXPECT_NEAR(rig.tether().deployedLength(), quietParams().initial_deployed_length, 1e-9);
  EXPECT_EQ(rig.input->rejected() - rejected, 3u) << "the two queued poses and the late one, refused and counted";
}

// Item 2 of issue 13: poses stamped in odom, whose world -> odom transform (a drifting localisation)
// comes at 10 Hz, 10 ms late. Looked up at their stamp without waiting, every pose newer than the last
// transform was refused (most of them); now each waits for the transform after it and is taken.
TEST(PoseInput, PosesInOdomWaitForATransformPublishedAt10Hz)
{
  NodeRig rig(quietParams());
  const auto odom = [](double t) { return Eigen::Isometry3d(Eigen::Translation3d(0.2 * (t - 100.0), 1.0, 0.0)); };
  const auto vehicle = [](double t) { return Position(3.0, 0.5 * (t - 100.0), -1.0); };  // in the world
  int next_pose = 0, next_tf = 0;
  for (int tick = 0; tick <= 6 * 200; ++tick)
  {
    const double now = 100.0 + tick * 0.005;
    for (; 100.0 + 0.1 * next_tf + 0.01 <= now + 1e-9; ++next_tf)
    {
      const double stamp = 100.0 + 0.1 * next_tf;
      ASSERT_TRUE(rig.tf.setTransform(transform("world", "odom", stamp, odom(stamp)), "test"));
    }
    for (; 100.0 + 0.02 * next_pose <= now + 1e-9; ++next_pose)
    {
      const double stamp = 100.0 + 0.02 * next_pose;
      const Position in_odom = odom(stamp).inverse() * vehicle(stamp);
      rig.input->receive(shared(poseMsg(in_odom.x(), in_odom.y(), in_odom.z(), stamp, "odom")), ros::Time(stamp));
    }
    rig.scheduler.tick(ros::Time(now));
  }
  const Tether& tether = rig.world.tether(0);
  const Position end = tether.particle(tether.deployedParticleCount() - 1);
  std::printf(
      "[ measured ] odom poses at 50 Hz, world -> odom at 10 Hz: %llu taken, %llu refused, physics %.3f s "
      "behind; end %.1e m from the vehicle\n",
      static_cast<unsigned long long>(rig.input->accepted()), static_cast<unsigned long long>(rig.input->rejected()),
      rig.scheduler.delay(), (end - vehicle(tether.time())).norm());
  EXPECT_EQ(rig.input->rejected(), 0u);
  EXPECT_GE(rig.input->accepted(), 290u);  // 6 s at 50 Hz, but those still waiting for their transform
  // The poses wait up to a transform period (+ its 10 ms): the delay grows to cover it.
  EXPECT_LE(rig.scheduler.delay(), 0.1 + 0.02 + 0.01 + 0.005 + 1e-9);
  EXPECT_LT((end - vehicle(tether.time())).norm(), 1e-9) << "the end is where the vehicle was, in the world";
}

// Item 1 of issue 26: mavros publishes the vehicle in `map`, and nobody publishes `world` (the node's own
// world -> tether_spool gives it children, never a parent). Every pose was refused ("no transform world ->
// map") and the tether never moved. Now world is taken as map: each pose is taken where it says.
void feedPosesIn(NodeRig& rig, const std::string& frame, double seconds)
{
  const auto vehicle = [](double t) { return Position(2.0 + 0.5 * (t - 100.0), 1.0, -1.0); };
  int next_pose = 0;
  for (int tick = 0; tick <= seconds * 200; ++tick)
  {
    const double now = 100.0 + tick * 0.005;
    ASSERT_TRUE(rig.tf.setTransform(transform("world", "tether_spool", now, Eigen::Isometry3d::Identity()), "node"));
    for (; 100.0 + 0.05 * next_pose <= now + 1e-9; ++next_pose)
    {
      const double stamp = 100.0 + 0.05 * next_pose;
      const Position p = vehicle(stamp);
      rig.input->receive(shared(poseMsg(p.x(), p.y(), p.z(), stamp, frame)), ros::Time(stamp));
    }
    rig.scheduler.tick(ros::Time(now));
  }
}

TEST(PoseInput, PosesInMapWhileNobodyElseUsesTheWorldFrameAreTakenAsInTheWorld)
{
  NodeRig rig(quietParams());
  feedPosesIn(rig, "map", 3.0);
  const Tether& tether = rig.world.tether(0);
  EXPECT_EQ(rig.input->adoptedFrame(), "map");
  EXPECT_EQ(rig.input->rejected(), 0u);
  // 3 s at 20 Hz: 61 poses, all but those the physics (a pose period + interpolation_delay behind) has
  // not reached yet.
  EXPECT_GE(rig.input->accepted(), 61u - 4u);
  ASSERT_TRUE(tether.vehicleAttached());
  const Position end = tether.particle(tether.deployedParticleCount() - 1);
  EXPECT_LT((end - Position(2.0 + 0.5 * (tether.time() - 100.0), 1.0, -1.0)).norm(), 1e-9)
      << "the end is where the pose in map says, map being the world";
  std::string parent;
  ASSERT_TRUE(rig.tf._getParent("world", ros::Time(0), parent));
  EXPECT_EQ(parent, "map") << "the identity map -> world is in tf, for every other lookup";
  {
    // The localisation comes up after the node (a helper's start-up order) and publishes world -> map: a loop
    // with the node's identity, which cannot be taken back. It is an error, said once.
    LogCollector log;
    ASSERT_TRUE(rig.tf.setTransform(transform("world", "map", 0.0, Eigen::Isometry3d::Identity()), "loc", true));
    rig.scheduler.tick(ros::Time(103.005));
    rig.scheduler.tick(ros::Time(103.01));
    EXPECT_EQ(log.count(log.errors, "tf now joins world to map from elsewhere"), 1u);
  }
  {
    // The same through another frame: world taken as odom, then world -> earth_map and earth_map -> odom.
    LogCollector log;
    NodeRig odom(quietParams());
    feedPosesIn(odom, "odom", 1.0);
    ASSERT_EQ(odom.input->adoptedFrame(), "odom");
    ASSERT_TRUE(odom.tf.setTransform(transform("world", "earth_map", 0.0, Eigen::Isometry3d::Identity()), "s", true));
    odom.scheduler.tick(ros::Time(101.005));
    EXPECT_EQ(log.count(log.errors, "from elsewhere"), 0u) << "no loop yet";
    ASSERT_TRUE(odom.tf.setTransform(transform("earth_map", "odom", 0.0, Eigen::Isometry3d::Identity()), "l", true));
    odom.scheduler.tick(ros::Time(101.01));
    EXPECT_EQ(log.count(log.errors, "tf now joins world to odom from elsewhere"), 1u);
  }

  // Someone places world (earth -> world): the node waits for world -> map, and refuses poses without it.
  NodeRig placed(quietParams());
  ASSERT_TRUE(placed.tf.setTransform(transform("earth", "world", 0.0, Eigen::Isometry3d::Identity()), "test", true));
  feedPosesIn(placed, "map", 1.0);
  EXPECT_EQ(placed.input->adoptedFrame(), "");
  EXPECT_GT(placed.input->rejected(), 0u);
  EXPECT_EQ(placed.input->accepted(), 0u);

  // Someone works in world (world -> cam_optical, a camera's mount): the same.
  NodeRig used(quietParams());
  ASSERT_TRUE(
      used.tf.setTransform(transform("world", "cam_optical", 0.0, Eigen::Isometry3d::Identity()), "test", true));
  feedPosesIn(used, "map", 1.0);
  EXPECT_EQ(used.input->adoptedFrame(), "");
  EXPECT_EQ(used.input->accepted(), 0u);

  // A dynamic vehicle's rov_frame is the node's own (it publishes world -> rov_frame from the first tick when
  // vehicle_start is given): it was taken as someone else working in world, and no pose in map was ever taken.
  // So is another tether's dynamic vehicle's (node_vehicle_frames, which the world's setup fills in). For a
  // kinematic vehicle the node publishes no rov_frame: someone else does, in world.
  NodeOptions dynamic;
  dynamic.vehicle_model = "dynamic";
  NodeOptions beside_dynamic;  // a kinematic tether beside another tether's dynamic vehicle, in rov_b
  beside_dynamic.node_vehicle_frames = {"rov_b"};
  const std::vector<std::tuple<const char*, NodeOptions, const char*, bool>> cases = {
      {"dynamic", dynamic, "rov", true},
      {"kinematic beside a dynamic vehicle", beside_dynamic, "rov_b", true},
      {"kinematic", NodeOptions(), "rov", false}};
  for (const auto& [what, options, child, own] : cases)
  {
    NodeRig rov(quietParams(), options);
    ASSERT_TRUE(rov.tf.setTransform(transform("world", child, 100.0, Eigen::Isometry3d::Identity()), "node"));
    feedPosesIn(rov, "map", 1.0);
    EXPECT_EQ(rov.input->adoptedFrame(), own ? "map" : "") << what;
    EXPECT_EQ(rov.input->accepted() > 0, own) << what;
  }

  // world_frame_from_pose: false keeps world_frame as it is.
  NodeOptions strict;
  strict.world_frame_from_pose = false;
  NodeRig kept(quietParams(), strict);
  feedPosesIn(kept, "map", 1.0);
  EXPECT_EQ(kept.input->adoptedFrame(), "");
  EXPECT_EQ(kept.input->accepted(), 0u);
}

// A helper sent one pose in a frame nobody has (a typo) after 600 poses in world: the node took world as that
// frame (the identity on /tf_static, for good), and refused the pose anyway. world_frame is taken as the poses'
// frame only for the first poses: once some were taken, a pose in another frame is refused and counted, and the
// poses in world go on.
TEST(PoseInput, AStrayFrameAfterPosesWereTakenIsRefusedNotTakenAsTheWorld)
{
  NodeRig rig(quietParams());
  feedPosesIn(rig, "world", 2.0);
  const std::uint64_t taken = rig.input->accepted();
  ASSERT_GT(taken, 30u);
  rig.input->receive(shared(poseMsg(3.0, 1.0, -1.0, 102.02, "nosuchframe")), ros::Time(102.02));
  for (int tick = 1; tick <= 600; ++tick)  // 3 s: the physics holds for stale_pose_timeout (2 s), then passes it
  {
    rig.scheduler.tick(ros::Time(102.0 + tick * 0.005));
  }
  EXPECT_EQ(rig.input->adoptedFrame(), "");
  EXPECT_EQ(rig.input->rejected(), 1u);
  std::string parent;
  EXPECT_FALSE(rig.tf._getParent("world", ros::Time(0), parent)) << "world has no parent: " << parent;
}

// Four different bad poses 0.3 s apart (a helper: only the first was ever logged, every reason sharing one
// throttled call site): each is warned, for its own reason is throttled on its own (once a second). What the
// node does with a pose it takes is said once: a zero stamp taken as the arrival time, an empty frame_id taken
// as world_frame, and a duplicate stamp replacing the pose before (each time, throttled as a warning's kind).
TEST(PoseInput, EachReasonForARefusalIsWarnedAndEachReadingOfAPoseIsSaid)
{
  LogCollector log;
  NodeRig rig(quietParams());
  double clock = 100.0;  // ROS time
  const auto tick = [&](double until)
  {
    for (; clock <= until + 1e-9; clock += 0.005)
    {
      rig.scheduler.tick(ros::Time(clock));
    }
  };
  rig.input->receive(shared(poseMsg(2.0, 0.0, -1.0, 100.0)), ros::Time(100.0));
  tick(100.3);
  auto future = poseMsg(2.0, 0.0, -1.0, 3700.0);
  rig.input->receive(shared(future), ros::Time(100.3));
  auto zero_quaternion = poseMsg(2.0, 0.0, -1.0, 100.6);
  zero_quaternion.pose.orientation.w = 0.0;
  rig.input->receive(shared(zero_quaternion), ros::Time(100.6));
  rig.input->receive(shared(poseMsg(std::nan(""), 0.0, -1.0, 100.9)), ros::Time(100.9));
  // The same reason again at once (within the second of wall time the throttle counts): counted, not warned again.
  rig.input->receive(shared(poseMsg(std::nan(""), 0.0, -1.0, 100.95)), ros::Time(100.95));
  EXPECT_EQ(log.count(log.warnings, "not finite"), 1u);
  rig.input->receive(shared(poseMsg(2.0, 0.0, -1.0, 99.0)), ros::Time(101.2));  // older than the last
  tick(101.5);
  EXPECT_EQ(rig.input->rejected(), 5u);
  EXPECT_EQ(log.count(log.warnings, "ahead of ROS time"), 1u);
  EXPECT_EQ(log.count(log.warnings, "not normalised"), 1u);
  EXPECT_EQ(log.count(log.warnings, "not finite"), 1u);
  EXPECT_EQ(log.count(log.warnings, "older than the last sample"), 1u);

  auto unstamped = poseMsg(2.1, 0.0, -1.0, 0.0);
  unstamped.header.frame_id = "";
  rig.input->receive(shared(unstamped), ros::Time(101.6));
  rig.input->receive(shared(poseMsg(2.2, 0.0, -1.0, 101.7, "")), ros::Time(101.7));
  rig.input->receive(shared(poseMsg(2.3, 0.0, -1.0, 101.7)), ros::Time(101.75));  // the same stamp again
  tick(102.5);
  EXPECT_EQ(rig.input->rejected(), 5u);
  EXPECT_EQ(log.count(log.notes, "zero stamp"), 1u);
  EXPECT_EQ(log.count(log.notes, "empty frame_id"), 1u);
  EXPECT_EQ(log.count(log.warnings, "again replaced the one before (0.100 m from it)"), 1u);
}

// A dynamic vehicle's poses go to its setpoints (the sink), not through the core's VehicleTrack, which refuses an
// older stamp: the sink took poses stamped 10, 11 and then 5 s, and the controller steered the vehicle back to where
// it was at 5 s, with nothing refused or said. The sink now keeps the core's order: an older stamp is refused and
// counted, the same stamp replaces the last setpoint and says so, as on the kinematic path.
TEST(PoseInput, ADynamicVehiclesSetpointsKeepTheOrderTheCoreKeepsForItsSamples)
{
  LogCollector log;
  Tether tether(quietParams(), Position::Zero());
  tf2_ros::Buffer tf;
  PoseInput input(NodeOptions(), tf, tether);
  std::vector<std::pair<double, double>> taken;  // (time, x) of each setpoint the sink was handed
  input.setVehicleSink(
      [&taken](double t, const Eigen::Isometry3d& vehicle)
      {
        taken.emplace_back(t, vehicle.translation().x());
        return Status::success();
      });
  const auto send = [&input](double x, double stamp, double now)
  {
    input.receive(shared(poseMsg(x, 0.0, -1.0, stamp)), ros::Time(now));
    input.poll(ros::Time(now));
  };
  send(1.0, 10.0, 10.0);
  send(2.0, 11.0, 11.0);
  send(0.5, 5.0, 11.1);   // older than the last: refused, the sink never sees it
  send(2.5, 11.0, 11.2);  // the same stamp again: it replaces the last setpoint, and says so
  ASSERT_EQ(taken.size(), 3u);
  EXPECT_EQ(taken[0], std::make_pair(10.0, 1.0));
  EXPECT_EQ(taken[1], std::make_pair(11.0, 2.0));
  EXPECT_EQ(taken[2], std::make_pair(11.0, 2.5));
  EXPECT_EQ(input.rejected(), 1u);
  EXPECT_EQ(input.accepted(), 3u);
  EXPECT_EQ(log.count(log.warnings, "older than the last sample at 11.000000 s"), 1u);
  EXPECT_EQ(log.count(log.warnings, "again replaced the one before (0.500 m from it)"), 1u);
  EXPECT_NEAR(input.lastVehicle().translation().x(), 2.5, 1e-12);
}

// pose_source tf: tf hands out the latest transform every tick until a newer one comes. One transform stamped
// ahead of max_pose_future was refused (and counted) again at every poll: 200 polls, 200 "rejected poses" in
// /diagnostics. It is one pose, refused once; a newer transform is a new pose.
TEST(PoseInput, ATransformRefusedInTfModeIsCountedOnce)
{
  NodeOptions options;
  options.pose_source = "tf";
  Tether tether(quietParams(), Position::Zero());
  tf2_ros::Buffer tf;
  PoseInput input(options, tf, tether);
  const Eigen::Isometry3d rov(Eigen::Translation3d(2.0, 0.0, -1.0));
  ASSERT_TRUE(tf.setTransform(transform("world", "rov", 15.0, rov), "test"));  // 5 s ahead of ROS time at 10 s
  for (int k = 0; k < 200; ++k)
  {
    input.poll(ros::Time(10.0 + 0.005 * k));
  }
  EXPECT_EQ(input.future(), 1u);
  EXPECT_EQ(input.rejected(), 1u);
  EXPECT_EQ(input.accepted(), 0u);
  ASSERT_TRUE(tf.setTransform(transform("world", "rov", 16.0, rov), "test"));  // still ahead, but a new pose
  input.poll(ros::Time(11.0));
  EXPECT_EQ(input.future(), 2u);
  ASSERT_TRUE(tf.setTransform(transform("world", "rov", 16.5, rov), "test"));  // within max_pose_future of 16 s
  input.poll(ros::Time(16.0));
  input.poll(ros::Time(16.005));
  EXPECT_EQ(input.accepted(), 1u);
  EXPECT_EQ(input.rejected(), 2u);
}

// The node's log throttles are one a kind of problem, so that a problem arriving often does not hide another. The
// three transform lookups shared one: a missing spool_frame, looked up first at every tick, hid a missing rov_frame
// (a typo) for good. Each use of a lookup now has its own.
TEST(PoseInput, AMissingSpoolFrameDoesNotHideAMissingVehicleFrame)
{
  LogCollector log;
  NodeOptions options;
  options.pose_source = "tf";
  options.spool_frame = "ship";
  options.rov_frame = "rvo";
  Tether tether(quietParams(), Position::Zero());
  tf2_ros::Buffer tf;
  PoseInput input(options, tf, tether);
  input.poll(ros::Time(1.0));
  EXPECT_EQ(log.count(log.warnings, "no transform world -> ship"), 1u);
  EXPECT_EQ(log.count(log.warnings, "no transform world -> rvo"), 1u);
}

// The physics waits for poses at most stale_pose_timeout (2 s) behind ROS time. 1 Hz fixes arriving 1.5 s late (a
// USBL) come 2.5 s after the stamp of the one before, longer than that: the physics passed each fix's stamp before
// it came, and the end, held, then caught up faster than the vehicle moved, with nothing said (a reviewer measured
// 2659 N at the vehicle). Such a pose, after one that came as late, is now counted and warned, naming
// stale_pose_timeout; raised to 3 s, the physics waits for every fix and the end never moves faster than the
// vehicle's 1.5 m/s (as in the test above). One outage is not counted (AfterAGapInThePoses... below).
TEST(PoseRates, PosesLaterThanThePhysicsWaitsAreCountedAndSaid)
{
  const auto fastestEnd = [](const NodeRig& r)
  {
    double fastest = 0.0;
    for (std::size_t k = 1; k < r.times.size(); ++k)
    {
      fastest = std::max(fastest, (r.ends[k] - r.ends[k - 1]).norm() / (r.times[k] - r.times[k - 1]));
    }
    return fastest;
  };
  LogCollector log;
  const auto late = passAtRate(1.0, 1.5);
  ASSERT_GT(late->times.size(), 400u);
  EXPECT_GE(late->input->late(), 10u) << "every fix while the vehicle moves";
  EXPECT_GE(log.count(log.warnings, "raise stale_pose_timeout above 2.5"), 1u);
  EXPECT_GT(fastestEnd(*late), 1.5 * 1.1) << "the end caught up faster than the vehicle moved";
  const std::size_t warned = log.warnings.size();

  NodeOptions waits;
  waits.stale_pose_timeout = 3.0;
  const auto waited = passAtRate(1.0, 1.5, waits);
  ASSERT_GT(waited->times.size(), 400u);
  EXPECT_EQ(waited->input->late(), 0u);
  EXPECT_EQ(log.warnings.size(), warned);
  EXPECT_LE(fastestEnd(*waited), 1.5 * (1.0 + 1e-6));
  std::printf(
      "[ measured ] 1 Hz fixes 1.5 s late: %llu of %llu taken late, the end at most %.2f m/s; with "
      "stale_pose_timeout 3 s: %llu late, at most %.4f m/s\n",
      static_cast<unsigned long long>(late->input->late()), static_cast<unsigned long long>(late->input->accepted()),
      fastestEnd(*late), static_cast<unsigned long long>(waited->input->late()), fastestEnd(*waited));
}

// Item 5 of issue 26: one pose stamped an hour ahead (a publisher with a wrong clock) was taken; every real
// pose after it was then refused as "older than the last sample" and the vehicle end stayed frozen for the
// hour. A stamp further ahead of ROS time than max_pose_future (1 s) is refused and counted instead.
TEST(PoseInput, APoseStampedAnHourAheadIsRefusedAndTheRealPosesGoOn)
{
  NodeRig rig(quietParams());
  const auto vehicle = [](double t) { return Position(2.0 + 0.5 * (t - 100.0), 1.0, -1.0); };
  int next_pose = 0;
  for (int tick = 0; tick <= 3 * 200; ++tick)
  {
    const double now = 100.0 + tick * 0.005;
    for (; 100.0 + 0.05 * next_pose <= now + 1e-9; ++next_pose)
    {
      const double stamp = 100.0 + 0.05 * next_pose;
      const Position p = vehicle(stamp);
      rig.input->receive(shared(poseMsg(p.x(), p.y(), p.z(), stamp)), ros::Time(stamp));
      if (next_pose == 20)  // at 101 s, a pose stamped 3701 s
      {
        rig.input->receive(shared(poseMsg(50.0, 0.0, -1.0, stamp + 3600.0)), ros::Time(stamp));
      }
    }
    rig.scheduler.tick(ros::Time(now));
  }
  const Tether& tether = rig.world.tether(0);
  EXPECT_EQ(rig.input->future(), 1u);
  EXPECT_EQ(rig.input->rejected(), 1u) << "only the pose from the future";
  EXPECT_GE(rig.input->accepted(), 61u - 4u);  // 3 s at 20 Hz, but those the physics has not reached
  const Position end = tether.particle(tether.deployedParticleCount() - 1);
  EXPECT_LT((end - vehicle(tether.time())).norm(), 1e-9) << "the end follows the real poses to the last";
  // Within the bound (a clock 0.5 s ahead) a pose is taken: the bound refuses only what a clock skew is not.
  rig.input->receive(shared(poseMsg(3.6, 1.0, -1.0, 103.5)), ros::Time(103.0));
  EXPECT_EQ(rig.input->rejected(), 1u);
}

/// `msg` as the subscriber of pose_topic receives it: serialised, with its publisher's type.
template <class Message>
topic_tools::ShapeShifter::ConstPtr asReceived(const Message& msg)
{
  auto shifter = boost::make_shared<topic_tools::ShapeShifter>();
  shifter->morph(ros::message_traits::md5sum(msg), ros::message_traits::datatype(msg),
                 ros::message_traits::definition(msg), "");
  std::vector<std::uint8_t> buffer(ros::serialization::serializationLength(msg));
  ros::serialization::OStream out(buffer.data(), static_cast<std::uint32_t>(buffer.size()));
  ros::serialization::serialize(out, msg);
  ros::serialization::IStream in(buffer.data(), static_cast<std::uint32_t>(buffer.size()));
  shifter->read(in);
  return shifter;
}

// Item 4 of issue 26: robot_localization-style stacks publish nav_msgs/Odometry, not PoseStamped. The
// subscription takes either (by the publisher's type); Odometry's pose goes through the same checks and
// frames as a PoseStamped; any other type is refused, counted and named.
TEST(PoseInput, OdometryIsTakenAsAPoseAndOtherTypesAreRefused)
{
  NodeOptions options;
  options.attachment_offset = Eigen::Vector3d(-0.5, 0.0, 0.0);
  TetherParams params = quietParams();
  params.winch_mode = WinchMode::kStrain;
  Tether tether(params, Position::Zero(), 9.9);
  tf2_ros::Buffer tf;
  ASSERT_TRUE(tf.setTransform(transform("world", "odom", 0.0, Eigen::Isometry3d(Eigen::Translation3d(1.0, 0.0, 0.0))),
                              "test", true));
  PoseInput input(options, tf, tether);

  nav_msgs::Odometry odometry;
  odometry.header.stamp = ros::Time(10.0);
  odometry.header.frame_id = "odom";
  odometry.child_frame_id = "base_link";
  odometry.pose.pose = poseMsg(2.0, 0.0, -1.0, 10.0).pose;
  odometry.twist.twist.linear.x = 7.0;  // not used: the pose says where the vehicle is
  input.receiveAny(asReceived(odometry), ros::Time(10.0));
  input.poll(ros::Time(10.0));
  ASSERT_EQ(input.accepted(), 1u);
  EXPECT_EQ(input.rejected(), 0u);
  // (2, 0, -1) in odom, which is 1 m along x in the world; the attachment 0.5 m behind the vehicle.
  EXPECT_TRUE(input.lastVehicle().translation().isApprox(Eigen::Vector3d(3.0, 0.0, -1.0), 1e-12));
  ASSERT_TRUE(test::succeeded(tether.advanceTo(10.0 + params.time_step)));
  const Position end = tether.particle(tether.deployedParticleCount() - 1);
  EXPECT_TRUE(end.isApprox(Position(2.5, 0.0, -1.0), 1e-6)) << end.transpose();

  // A PoseStamped on the same subscription is taken as before.
  input.receiveAny(asReceived(poseMsg(2.5, 0.0, -1.0, 10.1)), ros::Time(10.1));
  input.poll(ros::Time(10.1));
  EXPECT_EQ(input.accepted(), 2u);
  // Odometry with bad numbers meets the same checks.
  odometry.header.stamp = ros::Time(10.2);
  odometry.pose.pose.orientation.w = 2.0;
  input.receiveAny(asReceived(odometry), ros::Time(10.2));
  EXPECT_EQ(input.rejected(), 1u);
  // A type that is no pose: refused, counted.
  geometry_msgs::TwistStamped twist;
  twist.header.stamp = ros::Time(10.3);
  input.receiveAny(asReceived(twist), ros::Time(10.3));
  input.poll(ros::Time(10.3));
  EXPECT_EQ(input.rejected(), 2u);
  EXPECT_EQ(input.accepted(), 2u);
}

TEST(LoadGovernor, GivesUpOneNotchPerSecondAndUndoesItWhenTheLoadFalls)
{
  NodeOptions options;  // cpu_budget 0.8, min_iterations 2
  Tether tether(quietParams(), Position::Zero());
  LoadGovernor iterations(options, 10, "t");
  options.overload_policy = "reduce_markers";
  LoadGovernor markers(options, 10, "t");
  ros::WallTime wall(100.0);
  // One second of wall time with the physics taking `load` of it and the markers `marker_load`.
  const auto second = [&](double load, LoadGovernor& governor, double marker_load = 0.0)
  {
    for (int i = 0; i < 10; ++i)
    {
      governor.addMarkerTime(0.1 * marker_load);
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

  second(0.9, markers, 0.1);
  second(0.9, markers, 0.1);
  EXPECT_DOUBLE_EQ(markers.markerRate(), 7.5);
  EXPECT_EQ(markers.degraded(), "markers at 7.5 Hz");
  EXPECT_EQ(tether.params().iterations, 10) << "reduce_markers keeps the iterations";
  markers.reconfigured(10);
  EXPECT_DOUBLE_EQ(markers.markerRate(), 30.0);
  EXPECT_EQ(markers.degraded(), "");

  // The rate as a number reads: from 200 Hz, 100 Hz (it read "100. Hz", cut to four characters).
  options.marker_rate = 200.0;
  LoadGovernor fast(options, 10, "t");
  second(0.9, fast, 0.1);
  EXPECT_EQ(fast.degraded(), "markers at 100 Hz");
}

// reduce_markers gives up what the markers cost, and that relieves the load: markers costing 10 ms each
// at 30 Hz (30% of the wall time) on 10% of physics, with a 20% budget, go to 15 Hz (25%), then to
// 7.5 Hz (17.5%), within the budget, and stay (above half of it). With nobody subscribing the markers
// cost nothing: halving their rate would relieve nothing, so the policy gives nothing up and says the
// budget is not held.
TEST(LoadGovernor, ReduceMarkersRelievesWhatTheMarkersCost)
{
  NodeOptions options;
  options.overload_policy = "reduce_markers";
  options.cpu_budget = 0.2;
  Tether tether(quietParams(), Position::Zero());
  LoadGovernor governor(options, 10, "t");
  ros::WallTime wall(100.0);
  const double per_marker = 0.010;  // [s] to build and serialise one ~markers message
  std::vector<double> loads;
  for (int s = 0; s < 6; ++s)
  {
    // One second: 100 physics ticks of 1 ms each, and the markers' time at the current rate.
    for (int i = 0; i < 100; ++i)
    {
      governor.update(0.001, wall, tether);
      wall += ros::WallDuration(0.01);
    }
    governor.addMarkerTime(per_marker * governor.markerRate());
    governor.update(0.0, wall, tether);
    loads.push_back(governor.physicsLoad() + governor.markerLoad());
  }
  std::printf(
      "[ measured ] reduce_markers, 10 ms per ~markers on 10%% physics, budget 20%%: load %.3f, %.3f, %.3f "
      "... %.3f; markers at %.2f Hz\n",
      loads[0], loads[1], loads[2], loads.back(), governor.markerRate());
  EXPECT_NEAR(loads[0], 0.1 + 0.3, 1e-9);        // at 30 Hz
  EXPECT_NEAR(loads[1], 0.1 + 0.15, 1e-9);       // at 15 Hz
  EXPECT_NEAR(loads.back(), 0.1 + 0.075, 1e-9);  // at 7.5 Hz: relieved
  EXPECT_LE(loads.back(), options.cpu_budget);
  EXPECT_FALSE(governor.overloaded());
  EXPECT_EQ(governor.degraded(), "markers at 7.5 Hz");
  EXPECT_EQ(tether.params().iterations, 10) << "reduce_markers keeps the iterations";

  LoadGovernor unwatched(options, 10, "t");
  for (int s = 0; s < 3; ++s)
  {
    for (int i = 0; i < 100; ++i)
    {
      unwatched.update(0.004, wall, tether);  // 40% of physics, no markers: nobody subscribes
      wall += ros::WallDuration(0.01);
    }
    unwatched.update(0.0, wall, tether);
  }
  EXPECT_DOUBLE_EQ(unwatched.markerRate(), 30.0);
  EXPECT_EQ(unwatched.degraded(), "") << "nothing was given up";
  EXPECT_TRUE(unwatched.overloaded()) << "and the budget is not held: the diagnostics say so";
}

TEST(StateBuilder, StampsThePhysicsTimeAndMeasuresTheWinchSpeedBetweenStates)
{
  TetherParams params = quietParams();
  params.winch_mode = WinchMode::kSpeed;
  params.winch_speed = 0.5;
  Tether tether(params, Position::Zero(), 5.0);
  StateBuilder builder("world");
  ASSERT_TRUE(test::succeeded(tether.advanceTo(6.0)));
  EXPECT_EQ(builder.state(tether, 0).winch_speed, 0.0) << "no speed from a single state";
  ASSERT_TRUE(test::succeeded(tether.advanceTo(7.0)));
  const TetherState& state = builder.state(tether, 2);
  EXPECT_NEAR(state.header.stamp.toSec(), tether.time(), 1e-6);
  EXPECT_NEAR(state.winch_speed, 0.5, 0.05);
  EXPECT_EQ(state.resets, 2u);
  const auto wrench = builder.wrench(tether, Eigen::Isometry3d::Identity());
  EXPECT_EQ(wrench.header.stamp, state.header.stamp);
  builder.restart(tether);
  ASSERT_TRUE(test::succeeded(tether.advanceTo(8.0)));
  EXPECT_EQ(builder.state(tether, 3).winch_speed, 0.0) << "measured afresh after a reset";
}

}  // namespace
}  // namespace rov_tether::ros_layer
