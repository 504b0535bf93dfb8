#include "rov_tether/ros/vehicle_history.hpp"

namespace rov_tether::ros_layer
{

void VehicleHistory::add(double t, const Eigen::Isometry3d& pose)
{
  const Timed timed{t, pose.translation(), Eigen::Quaterniond(pose.rotation())};
  if (!poses_.empty() && poses_.back().time == t)
  {
    poses_.back() = timed;
    return;
  }
  poses_.push_back(timed);
}

Eigen::Isometry3d VehicleHistory::at(double t)
{
  if (poses_.empty())
  {
    return Eigen::Isometry3d::Identity();
  }
  // Times only move forwards: what lies before the pose just before t is not needed again.
  while (poses_.size() >= 2 && poses_[1].time <= t)
  {
    poses_.pop_front();
  }
  const Timed& a = poses_.front();
  const bool between = poses_.size() >= 2 && t > a.time;
  const double alpha = between ? (t - a.time) / (poses_[1].time - a.time) : 0.0;
  const Timed& b = between ? poses_[1] : a;
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.linear() = a.orientation.slerp(alpha, b.orientation).toRotationMatrix();
  result.translation() = a.position + alpha * (b.position - a.position);
  return result;
}

}  // namespace rov_tether::ros_layer
