#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <geometry_msgs/PoseStamped.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <Eigen/Geometry>
#include <boost/thread/recursive_mutex.hpp>
#include <memory>
#include <mutex>
#include <optional>

#include "rov_tether/GetTension.h"
#include "rov_tether/SetWinch.h"
#include "rov_tether/TetherConfig.h"
#include "rov_tether/TetherState.h"
#include "rov_tether/ros/converters.hpp"
#include "rov_tether/ros/param_loader.hpp"
#include "rov_tether/tether.hpp"

namespace rov_tether::ros_layer
{

/**
 * tether_node: owns a Tether and wires it to ROS. Vehicle poses come from `rov_pose` or tf;
 * a timer advances the physics at physics_rate on ROS time (use_sim_time works; time going backwards
 * resets the tether); ~state, ~wrench, ~markers (only with subscribers) and /diagnostics are published;
 * ~get_tension, ~set_winch and ~reset are served; dynamic_reconfigure changes take effect between steps.
 */
class TetherNode
{
 public:
  /// Loads parameters from the private namespace; throws std::runtime_error naming a bad parameter
  /// before anything is advertised or subscribed. With several tethers in one process, `shared` holds
  /// the parameters common to all (applied first) and `name` labels this one's diagnostics.
  TetherNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh,
             const XmlRpc::XmlRpcValue& shared = XmlRpc::XmlRpcValue(), const std::string& name = "");

 private:
  void onPose(const geometry_msgs::PoseStamped::ConstPtr& msg);
  void onTimer(const ros::TimerEvent& event);
  bool onGetTension(GetTension::Request& request, GetTension::Response& response);
  bool onSetWinch(SetWinch::Request& request, SetWinch::Response& response);
  bool onReset(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);
  void onReconfigure(TetherConfig& config, uint32_t level);
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);

  /// Turns a vehicle pose (world frame) into an attachment sample; logs (throttled) and drops bad ones.
  void addVehiclePose(const Eigen::Isometry3d& vehicle, const ros::Time& stamp);
  /// Looks up world_frame -> frame at `time` (0: latest), with the transform's stamp when asked; false
  /// (and a throttled warning) when it is not available.
  bool lookup(const std::string& frame, const ros::Time& time, Eigen::Isometry3d* pose, ros::Time* stamp = nullptr);
  void resetTether(const ros::Time& now, const std::string& why);
  void applyPendingParams();
  /// Warns when the parameters make the method unstable (lumped_mass above its critical step).
  void warnAboutStability() const;
  /// Publishes ~state and ~wrench for the physics' current time.
  void publishState();
  /// Publishes ~markers at marker_rate when someone subscribes.
  void publishMarkers(const ros::Time& now);
  /// The physics time for ROS time `now`: interpolation_delay behind, on the grid of time_step [s].
  double alignedPhysicsTime(const ros::Time& now) const;
  /// Once a second of wall time: when the physics used more than cpu_budget of it, applies
  /// overload_policy one notch (and reports it); when it used less than half, undoes one notch.
  void manageLoad(double physics_wall, const ros::WallTime& wall_now);

  ros::NodeHandle nh_;
  ros::NodeHandle private_nh_;
  NodeOptions options_;
  std::unique_ptr<Tether> sim_;

  tf2_ros::Buffer tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;  ///< Created after the parameters loaded.
  ros::Subscriber pose_sub_;
  ros::Publisher state_pub_;
  ros::Publisher marker_pub_;
  ros::Publisher wrench_pub_;
  ros::ServiceServer get_tension_srv_;
  ros::ServiceServer set_winch_srv_;
  ros::ServiceServer reset_srv_;
  ros::Timer timer_;
  std::unique_ptr<diagnostic_updater::Updater> diagnostics_;
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<TetherConfig>> reconfigure_server_;

  std::mutex pending_mutex_;
  std::optional<TetherParams> pending_params_;  ///< Written by dynamic_reconfigure, applied between steps.

  bool started_ = false;
  ros::Time last_time_;
  ros::Time last_pose_time_;         ///< ROS time the last accepted pose arrived.
  ros::Time last_pose_stamp_;        ///< Stamp of the last accepted pose.
  double next_state_physics_ = 0.0;  ///< Physics time at which ~state is due next [s]; 0: not set.
  double last_state_physics_ = 0.0;  ///< Physics time of the last ~state [s].
  ros::Time next_marker_time_;       ///< When ~markers are due next (with subscribers).
  Eigen::Isometry3d last_vehicle_ = Eigen::Isometry3d::Identity();
  double last_deployed_ = 0.0;
  double winch_speed_ = 0.0;
  double step_seconds_ = 0.0;      ///< Smoothed wall time per internal step [s].
  double real_time_factor_ = 0.0;  ///< Smoothed simulated / wall time of the physics.
  std::uint32_t resets_ = 0;
  std::uint64_t rejected_poses_ = 0;
  std::uint64_t reported_jumps_ = 0;     ///< Vehicle jumps already logged.
  std::uint64_t reported_failures_ = 0;  ///< Simulation failures (blow-ups) already logged.
  ros::Time last_failure_time_;          ///< When the last failure was seen; diagnostics show ERROR for a while.
  std::string name_;                     ///< This tether's name among several ("" alone).
  int configured_iterations_ = 0;        ///< Iterations as configured, before any overload reduction.
  double marker_rate_ = 0.0;             ///< Marker rate in use (overload_policy reduce_markers lowers it) [Hz].
  ros::WallTime load_window_start_;      ///< Start of the current one-second load window.
  double load_window_physics_ = 0.0;     ///< Wall time spent in physics in that window [s].
  double physics_load_ = 0.0;            ///< Fraction of wall time spent in physics, last window [-].
  std::string degraded_;                 ///< What overload_policy has given up, "" when nothing.
  std::uint64_t skips_ = 0;              ///< Times the physics fell more than max_lag behind and skipped.
  ros::Time last_skip_time_;
  std::vector<double> tensions_;
  TetherState state_msg_;
  visualization_msgs::MarkerArray markers_;
};

}  // namespace rov_tether::ros_layer
