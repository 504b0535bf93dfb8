#pragma once

#include <ros/time.h>

#include <string>

#include "rov_tether/core/tether.hpp"
#include "rov_tether/ros/log_throttle.hpp"
#include "rov_tether/ros/param_loader.hpp"

namespace rov_tether::ros_layer
{

/**
 * One tether's overload_policy. It is fed the wall time the tether's physics took on every tick and the
 * wall time its ~markers took (what reduce_markers can change); once a second of wall time it compares
 * their share of that second with cpu_budget. Above it, it gives up one notch (reduce_iterations:
 * iterations * 3/4, not below min_iterations; reduce_markers: half the marker rate, not below 1 Hz, and
 * only while the markers cost something: nobody subscribing, they cost nothing to give up) and warns;
 * below half of it, it undoes one notch. What it has given up is degraded(); whether the load is still
 * over the budget after that is overloaded() (both shown by the diagnostics). Needs no ROS master.
 */
class LoadGovernor
{
 public:
  /// `configured_iterations` are the tether's iterations before any reduction; `label` names the tether
  /// in log messages ("" alone).
  LoadGovernor(const NodeOptions& options, int configured_iterations, const std::string& label = "");

  /// Adds `physics_wall` [s] spent on the tether up to `wall_now`; at the end of a one-second window,
  /// applies the policy to `tether` (its iterations) or to markerRate().
  void update(double physics_wall, const ros::WallTime& wall_now, Tether& tether);
  /// Adds `marker_wall` [s] spent building and publishing the tether's ~markers (counted in the window
  /// that the next update() closes).
  void addMarkerTime(double marker_wall) { window_markers_ += marker_wall; }
  /// A new configuration (dynamic_reconfigure) with these iterations ends any reduction, markers included.
  void reconfigured(int iterations);

  /// Marker rate in use [Hz]: marker_rate, or less under reduce_markers.
  double markerRate() const { return marker_rate_; }
  /// What the policy has given up ("iterations 6 of 100", "markers at 7.50 Hz"), "" when nothing.
  const std::string& degraded() const { return degraded_; }
  /// Share of wall time the physics used in the last complete window [-].
  double physicsLoad() const { return physics_load_; }
  /// Share of wall time the ~markers used in the last complete window [-].
  double markerLoad() const { return marker_load_; }
  /// True when the last complete window was over cpu_budget (whatever was given up).
  bool overloaded() const { return physics_load_ + marker_load_ > options_.cpu_budget; }
  const std::string& policy() const { return options_.overload_policy; }

 private:
  void degrade(Tether& tether);
  void recover(Tether& tether);

  NodeOptions options_;
  std::string label_;
  int configured_iterations_;
  double marker_rate_;
  ros::WallTime window_start_;   ///< Start of the current one-second window.
  double window_physics_ = 0.0;  ///< Wall time spent in physics in that window [s].
  double window_markers_ = 0.0;  ///< Wall time spent on ~markers in that window [s].
  double physics_load_ = 0.0;    ///< Fraction of wall time spent in physics, last window [-].
  double marker_load_ = 0.0;     ///< Fraction of wall time spent on ~markers, last window [-].
  std::string degraded_;
  /// This tether's own log throttles (ROS_WARN_THROTTLE's belongs to the line: one tether's would hide another's):
  /// the load, a refused reduction and a refused restoration of the iterations.
  LogThrottle load_log_{5.0}, reduce_log_{5.0}, restore_log_{5.0};
};

}  // namespace rov_tether::ros_layer
