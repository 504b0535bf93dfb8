#include "rov_tether/ros/world_report.hpp"

#include <ros/console.h>
#include <tf2_eigen/tf2_eigen.h>

#include <cmath>

#include "rov_tether/ros/converters.hpp"
#include "rov_tether/ros/markers.hpp"

namespace rov_tether::ros_layer
{

ObstacleFrames::ObstacleFrames(const std::string& world_frame, World& world, tf2_ros::Buffer& tf)
    : world_frame_(world_frame), world_(world), tf_(tf)
{
  for (std::size_t i = 0; i < world_.obstacleCount(); ++i)
  {
    const Obstacle& obstacle = world_.obstacle(i);
    if (!obstacle.spec().frame.empty() && obstacle.spec().frame != world_frame)
    {
      framed_.push_back(i);
      local_.push_back(obstacle.pose());  // built from its position and orientation: in its frame
      missing_.emplace_back(kMissingFramePeriod);
    }
  }
}

bool ObstacleFrames::follow(const ros::Time& now, std::vector<std::string>* warnings)
{
  bool moved = false;
  for (std::size_t k = 0; k < framed_.size(); ++k)
  {
    const std::size_t i = framed_[k];
    const std::string& frame = world_.obstacle(i).spec().frame;
    Eigen::Isometry3d frame_in_world;
    try
    {
      frame_in_world = tf2::transformToEigen(tf_.lookupTransform(world_frame_, frame, ros::Time(0)));
    }
    catch (const tf2::TransformException& e)
    {
      if (missing_[k].due(now))
      {
        warnings->push_back("obstacle '" + world_.obstacle(i).name() + "' keeps its last pose: no transform " +
                            world_frame_ + " -> " + frame + ": " + e.what());
      }
      continue;
    }
    const Eigen::Isometry3d pose = frame_in_world * local_[k];
    if (!pose.isApprox(world_.obstacle(i).pose(), 1e-12))
    {
      world_.setObstaclePose(i, pose.translation(), Eigen::Quaterniond(pose.linear()));
      moved = true;
    }
  }
  return moved;
}

ObstacleScene::ObstacleScene(ros::NodeHandle& private_nh, const std::string& world_frame, double marker_rate,
                             World& world, tf2_ros::Buffer& tf)
    : world_frame_(world_frame), marker_period_(1.0 / marker_rate), world_(world), frames_(world_frame, world, tf)
{
  marker_pub_ = private_nh.advertise<visualization_msgs::MarkerArray>("obstacles", 1, /*latch=*/true);
  publish(ros::Time::now());
}

void ObstacleScene::update(const ros::Time& now)
{
  warnings_.clear();
  moved_ = frames_.follow(now, &warnings_) || moved_;
  for (const std::string& warning : warnings_)
  {
    ROS_WARN("tether_node: %s", warning.c_str());
  }
  if (moved_ && marker_pub_.getNumSubscribers() > 0 && (now - last_publish_ >= marker_period_ || now < last_publish_))
  {
    publish(now);
  }
}

void ObstacleScene::publish(const ros::Time& now)
{
  toObstacleMarkers(world_, ros::Time(), world_frame_, &markers_);  // stamp 0: rviz draws it at any time (latched)
  marker_pub_.publish(markers_);
  last_publish_ = now;
  moved_ = false;
}

TopologyReport::TopologyReport(ros::NodeHandle& private_nh, const World& world, const std::string& world_frame,
                               double state_rate)
    : world_(world), world_frame_(world_frame), period_(1.0 / state_rate)
{
  pub_ = private_nh.advertise<Topology>("topology", 10);
}

const std::vector<TopologyEntry>& TopologyReport::current()
{
  const double now = world_.time();
  if (now != computed_time_)
  {
    world_.topology(entries_);
    computed_time_ = now;
  }
  return entries_;
}

void TopologyReport::publish()
{
  const double t = world_.time();
  if (next_ == 0.0 || t < next_ - period_)  // not set, or the clock went back (a reset)
  {
    next_ = t;
  }
  if (t < next_ || pub_.getNumSubscribers() == 0)
  {
    return;
  }
  next_ = (std::floor(t / period_ + 1e-9) + 1.0) * period_;
  toTopologyMessage(world_, current(), ros::Time(std::max(t, 0.0)), world_frame_, &msg_);
  pub_.publish(msg_);
}

}  // namespace rov_tether::ros_layer
