#pragma once

#include <geometry_msgs/PoseStamped.h>
#include <ros/node_handle.h>
#include <ros/subscriber.h>
#include <ros/time.h>
#include <tf2_ros/buffer.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <string>

#include "rov_tether/ros/param_loader.hpp"
#include "rov_tether/tether.hpp"

namespace rov_tether::ros_layer
{

/// Why a pose's numbers are refused ("" when they are fine): a non-finite position or orientation, or a
/// quaternion whose norm is off 1 by more than 1e-3.
std::string checkPose(const geometry_msgs::Pose& pose);

/// The pose as a rigid transform (the quaternion taken as given; checkPose it first).
Eigen::Isometry3d toIsometry(const geometry_msgs::Pose& pose);

/**
 * One tether's vehicle (and spool) input: the `rov_pose` subscription or, with `pose_source: tf`, the
 * lookup of world_frame -> rov_frame; and `spool_frame` when the spool moves. A pose is checked (finite,
 * normalised), brought into world_frame through the process's one tf buffer, moved to the attachment
 * point (attachment_offset in the vehicle frame) and handed to Tether::addVehicleSample. Every refused
 * pose is counted and logged (throttled) with the reason. Needs no ROS master except for subscribe().
 */
class PoseInput
{
 public:
  /// Runs before an accepted message's pose is added, with the time it arrived: the node's clock policy
  /// (a clock that went backwards resets the tether first).
  using BeforeAdd = std::function<void(const ros::Time& now)>;

  /// `tf` is shared by every tether of the process and must outlive this; so must `tether`. `label`
  /// names the tether in log messages ("" alone).
  PoseInput(const NodeOptions& options, const tf2_ros::Buffer& tf, Tether& tether, const std::string& label = "");

  /// Subscribes to pose_topic (relative to `nh`) when pose_source is "topic"; messages go to onMessage at
  /// ros::Time::now().
  void subscribe(ros::NodeHandle& nh, BeforeAdd before_add);
  /// The subscribed topic's resolved name, "" without a subscription.
  std::string topic() const { return subscriber_.getTopic(); }

  /// A pose message that arrived at `now`: checked, transformed and added (a zero stamp means `now`).
  /// `before_add` (may be empty) runs once the numbers are checked. Returns whether it was accepted.
  bool onMessage(const geometry_msgs::PoseStamped& msg, const ros::Time& now, const BeforeAdd& before_add = {});
  /// Once per physics tick at `now`: the spool from spool_frame (when set) and, with pose_source tf, the
  /// vehicle from rov_frame when tf has a newer transform than the last one taken.
  void poll(const ros::Time& now);
  /// Forgets the last pose's stamp after the tether was reset, so the next tf pose is taken.
  void reset() { last_pose_stamp_ = ros::Time(); }

  std::uint64_t rejected() const { return rejected_; }
  /// The last accepted vehicle pose in world_frame (the vehicle origin, not the attachment).
  const Eigen::Isometry3d& lastVehicle() const { return last_vehicle_; }
  /// When the last pose was accepted (ROS time of arrival); zero before the first.
  const ros::Time& lastPoseTime() const { return last_pose_time_; }

 private:
  /// world_frame -> frame at `time` (0: latest) with the transform's stamp; false and a throttled
  /// warning when tf cannot tell.
  bool lookup(const std::string& frame, const ros::Time& time, Eigen::Isometry3d* pose, ros::Time* stamp = nullptr);
  /// The vehicle at `vehicle` (world frame) at `stamp` into the tether; counts and logs a refusal.
  bool addVehicle(const Eigen::Isometry3d& vehicle, const ros::Time& stamp, const ros::Time& now);

  NodeOptions options_;
  const tf2_ros::Buffer& tf_;
  Tether& tether_;
  std::string label_;  ///< " name" for log messages, "" alone.
  ros::Subscriber subscriber_;
  std::uint64_t rejected_ = 0;
  ros::Time last_pose_time_;   ///< ROS time the last accepted pose arrived.
  ros::Time last_pose_stamp_;  ///< Stamp of the last accepted pose.
  Eigen::Isometry3d last_vehicle_ = Eigen::Isometry3d::Identity();
};

}  // namespace rov_tether::ros_layer
