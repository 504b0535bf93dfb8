#pragma once

#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <ros/time.h>
#include <tf2_ros/buffer.h>
#include <visualization_msgs/MarkerArray.h>

#include <memory>
#include <string>
#include <vector>

#include "rov_tether/Topology.h"
#include "rov_tether/core/obstacle.hpp"
#include "rov_tether/core/world.hpp"
#include "rov_tether/ros/log_throttle.hpp"
#include "rov_tether/ros/obstacle_config.hpp"

namespace rov_tether::ros_layer
{

/**
 * The obstacles of a World that move with a tf frame (a `frame` other than world_frame): each follows its frame's
 * latest transform from world_frame, as the spool frame does. One whose frame tf does not know keeps its last pose
 * and is warned of, naming the obstacle and the frame, at most once per kMissingFramePeriod of its own
 * (LogThrottle): a ROS_WARN_THROTTLE's throttle belongs to its line, so the first obstacle's warning hid every
 * other's for the period. No ROS communication: ObstacleScene logs what follow() says.
 */
class ObstacleFrames
{
 public:
  static constexpr double kMissingFramePeriod = 5.0;  ///< [s] of ROS time, per obstacle.

  /// The obstacles of `world` with frames (buildWorld placed them, each at its `position` and `orientation`: in its
  /// `frame` until that frame is first seen); `world` and `tf` must outlive this.
  ObstacleFrames(const std::string& world_frame, World& world, tf2_ros::Buffer& tf);

  /// Puts each at its frame's latest transform (ROS time `now` for the throttles); true when one moved. Appends to
  /// `warnings` each missing frame's warning that is due.
  bool follow(const ros::Time& now, std::vector<std::string>* warnings);

 private:
  std::string world_frame_;
  World& world_;
  tf2_ros::Buffer& tf_;
  std::vector<std::size_t> framed_;       ///< Obstacles that move with a tf frame.
  std::vector<Eigen::Isometry3d> local_;  ///< Their pose in their frame, as framed_.
  std::vector<LogThrottle> missing_;      ///< Each one's missing-frame warning, as framed_.
};

/**
 * tether_node's obstacles once they are in its World: those with a tf `frame` follow it (ObstacleFrames: each
 * tick, its latest transform from world_frame; a frame tf does not know is a warning naming the obstacle and the
 * frame, throttled per obstacle, and the obstacle stays where it was), and the latched
 * ~obstacles (visualization_msgs/MarkerArray, toObstacleMarkers) is published at start and again when an
 * obstacle moved, at most at `marker_rate` and only while someone subscribes (a new subscriber first gets
 * the latched one, then the current one on the next tick).
 */
class ObstacleScene
{
 public:
  /// The obstacles of `world` (buildWorld placed them, each at its `position` and `orientation`: in its
  /// `frame` until that frame is first seen); `world` and `tf` must outlive this.
  ObstacleScene(ros::NodeHandle& private_nh, const std::string& world_frame, double marker_rate, World& world,
                tf2_ros::Buffer& tf);

  /// Before a physics tick at ROS time `now`: moves the obstacles with frames, republishes when due.
  void update(const ros::Time& now);

 private:
  void publish(const ros::Time& now);

  std::string world_frame_;
  ros::Duration marker_period_;
  World& world_;
  ObstacleFrames frames_;
  std::vector<std::string> warnings_;  ///< frames_' warnings of a tick (reused).
  ros::Publisher marker_pub_;
  visualization_msgs::MarkerArray markers_;
  bool moved_ = false;  ///< An obstacle moved since ~obstacles was last published.
  ros::Time last_publish_;
};

/**
 * The World's topology report (World::topology), computed only when someone needs it and at most once per
 * physics time: ~topology (rov_tether/Topology) while someone subscribes, at `state_rate` on the physics'
 * time grid, and each tether's /diagnostics (wrap, link and snag warnings) when they are due.
 */
class TopologyReport
{
 public:
  /// `world` must outlive this.
  TopologyReport(ros::NodeHandle& private_nh, const World& world, const std::string& world_frame, double state_rate);

  /// The topology at the world's current time.
  const std::vector<TopologyEntry>& current();
  const World& world() const { return world_; }
  /// After a physics tick: ~topology when due and someone subscribes.
  void publish();

 private:
  const World& world_;
  std::string world_frame_;
  double period_;                ///< 1 / state_rate [s].
  double next_ = 0.0;            ///< Physics time ~topology is due next [s]; 0: not set.
  double computed_time_ = -1.0;  ///< Physics time of entries_ [s]; -1: none yet.
  std::vector<TopologyEntry> entries_;
  ros::Publisher pub_;
  Topology msg_;
};

}  // namespace rov_tether::ros_layer
