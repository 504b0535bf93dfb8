#include "rov_tether/ros/pose_input.hpp"

#include <ros/console.h>
#include <tf2_eigen/tf2_eigen.h>

#include <cmath>
#include <cstdio>

namespace rov_tether::ros_layer
{

std::string checkPose(const geometry_msgs::Pose& pose)
{
  const auto& p = pose.position;
  const auto& q = pose.orientation;
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(q.x) || !std::isfinite(q.y) ||
      !std::isfinite(q.z) || !std::isfinite(q.w))
  {
    return "position or orientation is not finite";
  }
  const double norm = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  if (std::abs(norm - 1.0) > 1e-3)
  {
    char text[80];
    std::snprintf(text, sizeof(text), "quaternion is not normalised (|q| = %.6f)", norm);
    return text;
  }
  return "";
}

Eigen::Isometry3d toIsometry(const geometry_msgs::Pose& pose)
{
  const auto& p = pose.position;
  const auto& q = pose.orientation;
  return Eigen::Translation3d(p.x, p.y, p.z) * Eigen::Quaterniond(q.w, q.x, q.y, q.z);
}

PoseInput::PoseInput(const NodeOptions& options, const tf2_ros::Buffer& tf, Tether& tether, const std::string& label)
    : options_(options), tf_(tf), tether_(tether), label_(label.empty() ? "" : " " + label)
{
}

void PoseInput::subscribe(ros::NodeHandle& nh, BeforeAdd before_add)
{
  if (options_.pose_source != "topic")
  {
    return;
  }
  // Deep enough for poses at 1 kHz between two physics ticks.
  subscriber_ = nh.subscribe<geometry_msgs::PoseStamped>(
      options_.pose_topic, 100,
      [this, before_add = std::move(before_add)](const geometry_msgs::PoseStamped::ConstPtr& msg)
      { onMessage(*msg, ros::Time::now(), before_add); });
}

bool PoseInput::onMessage(const geometry_msgs::PoseStamped& msg, const ros::Time& now, const BeforeAdd& before_add)
{
  const std::string problem = checkPose(msg.pose);
  if (!problem.empty())
  {
    ++rejected_;
    ROS_WARN_THROTTLE(1.0, "rov_pose rejected%s: %s", label_.c_str(), problem.c_str());
    return false;
  }
  if (before_add)
  {
    before_add(now);
  }
  const ros::Time stamp = msg.header.stamp.isZero() ? now : msg.header.stamp;
  Eigen::Isometry3d pose = toIsometry(msg.pose);
  const std::string& frame = msg.header.frame_id;
  if (!frame.empty() && frame != options_.world_frame)
  {
    Eigen::Isometry3d frame_in_world;
    if (!lookup(frame, stamp, &frame_in_world))
    {
      ++rejected_;
      return false;
    }
    pose = frame_in_world * pose;
  }
  return addVehicle(pose, stamp, now);
}

void PoseInput::poll(const ros::Time& now)
{
  Eigen::Isometry3d pose;
  if (!options_.spool_frame.empty() && lookup(options_.spool_frame, ros::Time(0), &pose))
  {
    tether_.setSpoolPosition(pose.translation());
  }
  ros::Time stamp;
  if (options_.pose_source == "tf" && lookup(options_.rov_frame, ros::Time(0), &pose, &stamp) &&
      stamp > last_pose_stamp_)
  {
    addVehicle(pose, stamp, now);
  }
}

bool PoseInput::lookup(const std::string& frame, const ros::Time& time, Eigen::Isometry3d* pose, ros::Time* stamp)
{
  try
  {
    const auto transform = tf_.lookupTransform(options_.world_frame, frame, time);
    *pose = tf2::transformToEigen(transform);
    if (stamp != nullptr)
    {
      *stamp = transform.header.stamp;
    }
    return true;
  }
  catch (const tf2::TransformException& e)
  {
    ROS_WARN_THROTTLE(1.0, "tether_node%s: no transform %s -> %s: %s", label_.c_str(), options_.world_frame.c_str(),
                      frame.c_str(), e.what());
    return false;
  }
}

bool PoseInput::addVehicle(const Eigen::Isometry3d& vehicle, const ros::Time& stamp, const ros::Time& now)
{
  const Position attachment = vehicle * options_.attachment_offset;
  const Status status = tether_.addVehicleSample(stamp.toSec(), attachment);
  if (!status.ok)
  {
    ++rejected_;
    ROS_WARN_THROTTLE(1.0, "rov_pose rejected%s: %s", label_.c_str(), status.message.c_str());
    return false;
  }
  last_vehicle_ = vehicle;
  last_pose_time_ = now;
  last_pose_stamp_ = stamp;
  return true;
}

}  // namespace rov_tether::ros_layer
