#include "rov_tether/ros/vehicle_history.hpp"

namespace rov_tether::ros_layer
{

void VehicleHistory::add(double t, const Eigen::Isometry3d& pose)
{
  if (!poses_.empty() && poses_.back().time == t)
  {
    poses_.back().pose = pose;
    return;
  }
  poses_.push_back(Timed{t, pose});
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
  if (poses_.size() == 1 || t <= a.time)
  {
    return a.pose;
  }
  const Timed& b = poses_[1];
  const double alpha = (t - a.time) / (b.time - a.time);
  const Eigen::Quaterniond qa(a.pose.rotation());
  const Eigen::Quaterniond qb(b.pose.rotation());
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.linear() = qa.slerp(alpha, qb).toRotationMatrix();
  result.translation() = a.pose.translation() + alpha * (b.pose.translation() - a.pose.translation());
  return result;
}

}  // namespace rov_tether::ros_layer
