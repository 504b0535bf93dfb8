// Golden output of the node's pipeline, without a master: a recorded dive (test/data/straight_excursion.bag)
// is fed in the node's order (poses as they arrive, a 200 Hz physics tick on the bag's clock, ~state and
// ~wrench on the physics-time grid) with config/default.yaml and config/node.yaml, and every published
// message is serialised and hashed. rosbag play's timing is not repeatable; this replay is, so it pins what
// the node computes from a given input. Hash in test/golden/node_replay.txt (see golden.hpp).
#include <geometry_msgs/PoseStamped.h>
#include <ros/serialization.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>
#include <vector>

#include "../golden.hpp"
#include "rov_tether/ros/converters.hpp"
#include "rov_tether/ros/param_loader.hpp"
#include "rov_tether/scenario_runner.hpp"
#include "rov_tether/scenario_yaml.hpp"

namespace rov_tether::test
{
namespace
{

/// The node's order of work (TetherNode::onPose, onTimer, publishState) for one tether with a topic pose
/// source, written out here until the node's pieces can run without a master.
class NodePipeline
{
 public:
  NodePipeline(const TetherParams& params, const ros_layer::NodeOptions& options)
      : options_(options), sim_(params, options.spool_position)
  {
  }

  void onPose(const geometry_msgs::PoseStamped& msg, const ros::Time& now)
  {
    const auto& p = msg.pose.position;
    const auto& q = msg.pose.orientation;
    if (!std::isfinite(p.x + p.y + p.z + q.x + q.y + q.z + q.w) ||
        std::abs(std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w) - 1.0) > 1e-3)
    {
      return;
    }
    const ros::Time stamp = msg.header.stamp.isZero() ? now : msg.header.stamp;
    const Eigen::Isometry3d pose = Eigen::Translation3d(p.x, p.y, p.z) * Eigen::Quaterniond(q.w, q.x, q.y, q.z);
    if (sim_.addVehicleSample(stamp.toSec(), pose * options_.attachment_offset).ok)
    {
      last_vehicle_ = pose;
    }
  }

  template <typename Publish>
  void onTick(const ros::Time& now, Publish&& publish)
  {
    const double dt = sim_.params().time_step;
    if (!started_)
    {
      started_ = true;
      sim_.reset(std::floor((now.toSec() - options_.interpolation_delay) / dt) * dt);
    }
    const double target = now.toSec() - options_.interpolation_delay;
    const double period = 1.0 / options_.state_rate;
    if (next_state_ <= 0.0 || next_state_ < target - 1.0)
    {
      next_state_ = std::ceil(std::max(sim_.time(), target - 1.0) / period) * period;
    }
    for (;;)
    {
      const bool due = next_state_ <= target;
      sim_.advanceTo(due ? next_state_ : target);
      if (!due)
      {
        break;
      }
      sim_.computeSegmentTensions(tensions_);
      const double time = sim_.time();
      const double elapsed = time - last_state_;
      const double deployed = sim_.deployedLength();
      const double speed = last_state_ > 0.0 && elapsed > 0.0 ? (deployed - last_deployed_) / elapsed : 0.0;
      last_deployed_ = deployed;
      last_state_ = time;
      const ros::Time stamp(std::max(time, 0.0));
      TetherState state;
      ros_layer::toStateMessage(sim_, tensions_, stamp, options_.world_frame, speed, 0, &state);
      publish(state, ros_layer::toWrench(sim_, last_vehicle_.translation(), stamp, options_.world_frame));
      next_state_ += period;
    }
  }

 private:
  ros_layer::NodeOptions options_;
  Tether sim_;
  bool started_ = false;
  double next_state_ = 0.0;
  double last_state_ = 0.0;
  double last_deployed_ = 0.0;
  Eigen::Isometry3d last_vehicle_ = Eigen::Isometry3d::Identity();
  std::vector<double> tensions_;
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
  ros_layer::NodeOptions options;  // the defaults are config/node.yaml's
  NodePipeline pipeline(params, options);

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
  // The physics tick at 200 Hz on the bag's clock; poses received up to a tick are delivered before it.
  const ros::Duration tick(1.0 / options.physics_rate);
  std::size_t next = 0;
  for (ros::Time now = poses.front().first + tick; now <= poses.back().first + ros::Duration(1.0); now += tick)
  {
    for (; next < poses.size() && poses[next].first <= now; ++next)
    {
      pipeline.onPose(poses[next].second, poses[next].first);
    }
    pipeline.onTick(now, publish);
  }
  EXPECT_GT(states, 1000u);  // 30 Hz over 50 s
  GoldenFile golden("node_replay.txt");
  golden.check("straight_excursion/state_and_wrench", hash);
}

}  // namespace
}  // namespace rov_tether::test
