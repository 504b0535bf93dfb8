#pragma once
// Waiting in rostests: on a condition, with a wall-clock timeout, never a fixed sleep.
#include <ros/ros.h>

#include <functional>

namespace rov_tether::test
{

/// Spins (ros::spinOnce) until `done` or the wall timeout [s]; returns whether `done` became true.
/// `poll` [s] is the polling interval, not a synchronisation.
inline bool waitFor(const std::function<bool()>& done, double timeout, double poll = 0.0005)
{
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
  while (ros::ok() && ros::WallTime::now() < deadline)
  {
    ros::spinOnce();
    if (done())
    {
      return true;
    }
    ros::WallDuration(poll).sleep();
  }
  return false;
}

}  // namespace rov_tether::test
