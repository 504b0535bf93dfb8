// Golden output of the node's pipeline, without a master: a recorded dive (test/data/straight_excursion.bag)
// is fed through the node's own classes (PoseInput for the poses as they arrive, the Scheduler's 200 Hz
// physics tick on the bag's clock stepping a World of one tether, StateBuilder for ~state and ~wrench on
// the physics-time grid) with config/default.yaml and config/node.yaml, and every published message is
// serialised and hashed. rosbag play's timing is not repeatable; this replay is, so it pins what
// the node computes from a given input. Hash in test/golden/node_replay.txt (see golden.hpp).
#include <geometry_msgs/PoseStamped.h>
#include <ros/serialization.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <tf2_ros/buffer.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "../golden.hpp"
#include "rov_tether/core/world.hpp"
#include "rov_tether/ros/param_loader.hpp"
#include "rov_tether/ros/pose_input.hpp"
#include "rov_tether/ros/scheduler.hpp"
#include "rov_tether/ros/tether_publisher.hpp"
#include "rov_tether/scenario/scenario_yaml.hpp"
#include "yaml_xmlrpc.hpp"

namespace rov_tether::test
{
namespace
{

/// What TetherNode does for a tether when the Scheduler calls it, without the ROS wiring: the node's
/// own PoseInput polls before the physics, its StateBuilder builds ~state and ~wrench when due.
class ReplayTether : public ros_layer::TetherHooks
{
 public:
  using Publish = std::function<void(const TetherState&, const geometry_msgs::WrenchStamped&)>;

  ReplayTether(Tether& tether, ros_layer::PoseInput& input, const ros_layer::Scheduler& scheduler,
               const ros_layer::NodeOptions& options, Publish publish)
      : tether_(tether),
        input_(input),
        scheduler_(scheduler),
        builder_(options.world_frame, options.rov_frame, options.attachment_offset),
        publish_(publish)
  {
  }

  void beforeAdvance(const ros::Time& now) override { input_.poll(now); }
  void publishState() override
  {
    const TetherState& state = builder_.state(tether_, scheduler_.schedule(0).resets);
    publish_(state, builder_.wrench(tether_, input_.vehicleAt(tether_.time())));
  }
  void restarted(const ros::Time& now) override
  {
    input_.reset(now);
    builder_.restart(tether_);
  }
  PoseTiming poseTiming() const override { return PoseTiming{input_.latestStamp(), input_.neededDelay()}; }
  ros::Time earliestArrival() const override { return input_.earliestArrival(); }

 private:
  Tether& tether_;
  ros_layer::PoseInput& input_;
  const ros_layer::Scheduler& scheduler_;
  ros_layer::StateBuilder builder_;
  Publish publish_;
};

template <typename Message>
std::uint64_t hashMessage(const Message& message, std::uint64_t hash)
{
  const std::uint32_t size = ros::serialization::serializationLength(message);
  std::vector<std::uint8_t> buffer(size);
  ros::serialization::OStream stream(buffer.data(), size);
  ros::serialization::serialize(stream, message);
  return fnv1a(std::string(buffer.begin(), buffer.end()), hash);
}

TEST(Golden, NodePipelineReplaysARecordedDive)
{
  const std::string source(ROV_TETHER_SOURCE_DIR);
  TetherParams params;
  ASSERT_EQ(loadParamsFile(source + "/config/default.yaml", &params), "");
  ros_layer::NodeOptions options;
  ASSERT_EQ(ros_layer::loadNodeOptions(loadYaml("config/node.yaml"), &options), "");  // as tether.launch does

  rosbag::Bag bag(source + "/test/data/straight_excursion.bag");
  rosbag::View view(bag, rosbag::TopicQuery("/rov_pose"));
  std::vector<std::pair<ros::Time, geometry_msgs::PoseStamped>> poses;
  for (const rosbag::MessageInstance& m : view)
  {
    poses.emplace_back(m.getTime(), *m.instantiate<geometry_msgs::PoseStamped>());
  }
  ASSERT_GT(poses.size(), 100u);

  std::uint64_t hash = 0xcbf29ce484222325ULL;
  std::size_t states = 0;
  auto publish = [&](const TetherState& state, const geometry_msgs::WrenchStamped& wrench)
  {
    hash = hashMessage(state, hash);
    hash = hashMessage(wrench, hash);
    ++states;
  };
  // The node's own pieces for one tether: its world, pose input (tf is not needed: the poses are in the
  // world frame), scheduler and state builder. The wall clock is the bag's: the physics takes no wall
  // time, so the load governor never degrades and the replay is the same on any machine.
  World world;
  ASSERT_TRUE(world.add("tether", std::make_unique<Tether>(params, options.spool_position)).ok);
  Tether& tether = world.tether(0);
  tf2_ros::Buffer tf;
  ros_layer::PoseInput input(options, tf, tether);
  ros::Time now;
  ros_layer::Scheduler scheduler(world, options.interpolation_delay,
                                 [&now] { return ros::WallTime(now.sec, now.nsec); });
  ReplayTether hooks(tether, input, scheduler, options, publish);
  scheduler.add(options, hooks);
  // The physics tick at 200 Hz on the bag's clock; poses received up to a tick are delivered before it.
  const ros::Duration tick(1.0 / options.physics_rate);
  std::size_t next = 0;
  for (now = poses.front().first + tick; now <= poses.back().first + ros::Duration(1.0); now += tick)
  {
    for (; next < poses.size() && poses[next].first <= now; ++next)
    {
      input.receive(boost::make_shared<geometry_msgs::PoseStamped>(poses[next].second), poses[next].first);
    }
    scheduler.tick(now);
  }
  EXPECT_EQ(input.rejected(), 0u);  // a clean recording: every pose is taken
  EXPECT_EQ(input.dropped(), 0u);
  EXPECT_EQ(input.accepted(), poses.size());
  EXPECT_DOUBLE_EQ(scheduler.delay(), options.interpolation_delay) << "20 Hz poses need no more delay";
  EXPECT_EQ(scheduler.schedule(0).resets, 0u);
  EXPECT_EQ(scheduler.schedule(0).skips, 0u);
  EXPECT_EQ(scheduler.governor(0).degraded(), "");
  // After the last pose the physics waits for the next one (up to stale_pose_timeout, 2 s, longer than
  // the replay goes on): it ends at the last pose's stamp.
  EXPECT_NEAR(tether.time(), poses.back().second.header.stamp.toSec(), tether.params().time_step);
  // One ~state per point of the state grid from the first tick's physics time (interpolation_delay
  // behind it) to the last pose: state_rate x the span, within the one point either end may add.
  const double span =
      (poses.back().first - (poses.front().first + tick) + ros::Duration(options.interpolation_delay)).toSec();
  EXPECT_NEAR(static_cast<double>(states), options.state_rate * span, 2.0);
  GoldenFile golden("node_replay.txt");
  golden.check("straight_excursion/state_and_wrench", hash);
  golden.expectAllChecked();
}

}  // namespace
}  // namespace rov_tether::test
