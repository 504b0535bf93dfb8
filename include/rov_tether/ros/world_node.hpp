#pragma once

#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <ros/spinner.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <memory>
#include <vector>

#include "rov_tether/core/world.hpp"
#include "rov_tether/ros/scheduler.hpp"
#include "rov_tether/ros/tether_camera.hpp"
#include "rov_tether/ros/tether_node.hpp"
#include "rov_tether/ros/world_report.hpp"
#include "rov_tether/scenario/world_spec.hpp"

namespace rov_tether::ros_layer
{

/**
 * tether_node's process: one World of one tether (parameters in ~) or of several (a private list
 * `tethers: [a, b, ...]`, each configured under ~a/, ~b/, ... on top of the parameters they share in ~).
 * It owns the one tf buffer and listener every tether's pose input reads, the Scheduler and the one
 * timer that steps the world at physics_rate on ROS time; each tether keeps its own topics, services,
 * parameters, diagnostics and dynamic_reconfigure server (TetherNode). Vehicle poses (and the tf
 * MessageFilter's callbacks) come on a callback queue of their own, served by a thread of its own, so
 * a slow physics tick (one heavy tether) never stalls them. With a private list `cameras`, its CameraSet
 * draws every tether in each camera after every tick. The private list `obstacles` puts obstacles in the
 * world (ObstacleScene: those with a tf frame follow it, ~obstacles draws them), `tether_contact` switches
 * contact between tethers, and TopologyReport publishes ~topology and feeds every tether's diagnostics.
 * A tether whose `spool_on` names another (a TMS: the spool on that tether's dynamic vehicle) has its spool
 * mounted on that vehicle (World::mountSpool) in the tick it starts at vehicle_start.
 */
class WorldNode
{
 public:
  /// Loads every tether's parameters first; throws std::runtime_error naming a bad parameter before
  /// anything is advertised or subscribed.
  WorldNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh);
  /// Stops the input thread before the tethers it feeds go.
  ~WorldNode();

  std::size_t size() const { return tethers_.size(); }

 private:
  void onTimer(const ros::TimerEvent& event);
  /// Mounts each spool still waiting whose carrier's dynamic vehicle has started (after the tick that started it).
  void mountStartedCarriers();

  ros::NodeHandle nh_;
  ros::NodeHandle private_nh_;
  tf2_ros::Buffer tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;  ///< Created once the parameters loaded.
  WorldSpec world_spec_;                                     ///< The world as described (its tethers' spool mounts).
  World world_;
  std::vector<std::size_t> unmounted_;  ///< Tethers (world_spec_ order) whose carrier has not started yet.
  std::unique_ptr<Scheduler> scheduler_;
  std::unique_ptr<TopologyReport> topology_;
  std::unique_ptr<ObstacleScene> obstacles_;
  ros::CallbackQueue input_queue_;  ///< Vehicle poses and the tf MessageFilter's callbacks.
  std::vector<std::unique_ptr<TetherNode>> tethers_;
  std::unique_ptr<CameraSet> cameras_;  ///< The private list `cameras`; none without it.
  ros::Timer timer_;
  std::unique_ptr<ros::AsyncSpinner> input_spinner_;  ///< The input queue's one thread; stopped first.
};

}  // namespace rov_tether::ros_layer
