#pragma once
// A log throttle that belongs to one object. ROS_WARN_THROTTLE's belongs to the line of code: with several tethers in
// one node, one tether's message would hide every other tether's for the period.
#include <ros/time.h>

namespace rov_tether
{

/// due(now) is true at most once per `period` seconds of the clock it is given (ros::Time: simulated time under
/// use_sim_time, as roscpp's throttles), and at once if that clock went back (a replay started over).
class LogThrottle
{
 public:
  explicit LogThrottle(double period) : period_(period) {}
  bool due(const ros::Time& now)
  {
    const bool is_due = !logged_ || now < last_ || (now - last_).toSec() >= period_;
    last_ = is_due ? now : last_;
    logged_ = logged_ || is_due;
    return is_due;
  }
  /// Due with ros::Time::now().
  bool due() { return due(ros::Time::now()); }

 private:
  double period_;
  ros::Time last_;       ///< When it was last due.
  bool logged_ = false;  ///< It has been due (a clock at 0, before /clock, is due once).
};

}  // namespace rov_tether
