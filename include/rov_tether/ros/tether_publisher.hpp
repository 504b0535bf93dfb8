#pragma once

#include <geometry_msgs/WrenchStamped.h>
#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <ros/time.h>
#include <visualization_msgs/MarkerArray.h>

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "rov_tether/TetherState.h"
#include "rov_tether/ros/converters.hpp"
#include "rov_tether/ros/param_loader.hpp"
#include "rov_tether/tether.hpp"

namespace rov_tether::ros_layer
{

/**
 * Builds ~state and ~wrench for a tether at its current physics time (stamped with it), measuring the
 * winch speed between two states. Needs no ROS master.
 */
class StateBuilder
{
 public:
  explicit StateBuilder(const std::string& frame_id) : frame_id_(frame_id) {}

  /// The state of `tether` now; `resets` is reported in the message. Reuses its storage.
  const TetherState& state(const Tether& tether, std::uint32_t resets);
  /// The pull on the vehicle at the same time, torque about `vehicle_origin` (call after state()).
  geometry_msgs::WrenchStamped wrench(const Tether& tether, const Eigen::Vector3d& vehicle_origin) const;
  /// After a reset of the tether: the winch speed is measured afresh.
  void restart(const Tether& tether);

 private:
  std::string frame_id_;
  double last_state_physics_ = 0.0;  ///< Physics time of the last state [s].
  double last_deployed_ = 0.0;
  ros::Time stamp_;
  std::vector<double> tensions_;
  TetherState msg_;
};

/**
 * One tether's topics: ~state and ~wrench (on its state grid, see Scheduler), ~markers at a rate (only
 * computed while someone subscribes).
 */
class TetherPublisher
{
 public:
  /// Advertises under `private_nh`.
  TetherPublisher(ros::NodeHandle& private_nh, const NodeOptions& options);

  /// Publishes ~state and ~wrench for the tether's current physics time.
  void publishState(const Tether& tether, std::uint32_t resets, const Eigen::Vector3d& vehicle_origin);
  /// Publishes ~markers when due at `rate` [Hz] and someone subscribes.
  void publishMarkers(const Tether& tether, const ros::Time& now, double rate);
  /// After a reset of the tether.
  void restart(const Tether& tether);

 private:
  NodeOptions options_;
  StateBuilder builder_;
  ros::Publisher state_pub_;
  ros::Publisher wrench_pub_;
  ros::Publisher marker_pub_;
  ros::Time next_marker_time_;  ///< When ~markers are due next (with subscribers).
  std::vector<double> tensions_;
  visualization_msgs::MarkerArray markers_;
};

}  // namespace rov_tether::ros_layer
