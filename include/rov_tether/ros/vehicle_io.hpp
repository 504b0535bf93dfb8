#pragma once
// The ROS side of a dynamic vehicle (vehicle_model: dynamic): ~cmd_wrench in, ~odom and tf out, the vehicle's
// start; and the conversions it uses (odometry, the vehicle's box in rviz), testable without a master.

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/WrenchStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/callback_queue_interface.h>
#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <ros/subscriber.h>
#include <ros/time.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/Marker.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <mutex>
#include <string>

#include "rov_tether/core/tether.hpp"
#include "rov_tether/core/vehicle_body.hpp"
#include "rov_tether/core/vehicle_controller.hpp"
#include "rov_tether/ros/log_throttle.hpp"
#include "rov_tether/ros/param_loader.hpp"
#include "rov_tether/ros/vehicle_history.hpp"

namespace rov_tether::ros_layer
{

/// The body's state as nav_msgs/Odometry (REP 105): the pose of `vehicle_frame` in `world_frame`, the twist
/// (VehicleBody::velocity(), over the ground) in the body frame, child_frame_id = `vehicle_frame`. Covariances
/// zero: the state is exact.
nav_msgs::Odometry toOdometry(const VehicleBody& body, const ros::Time& stamp, const std::string& world_frame,
                              const std::string& vehicle_frame);

/// The same pose as the tf transform world_frame -> vehicle_frame.
geometry_msgs::TransformStamped toVehicleTransform(const VehicleBody& body, const ros::Time& stamp,
                                                   const std::string& world_frame, const std::string& vehicle_frame);

/// The vehicle drawn as a box of `size` [m] (length x, width y, height z, centred on the vehicle origin) at
/// `pose` (world frame): a CUBE, namespace "vehicle", id 0, half transparent so the attachment point inside
/// shows; DELETE while `present` is false (no vehicle yet).
void toVehicleMarker(const Eigen::Isometry3d& pose, const Eigen::Vector3d& size, bool present, const ros::Time& stamp,
                     const std::string& frame_id, visualization_msgs::Marker* marker);

/// A start pose [x, y, z, yaw] [m, rad] as a transform (upright, turned by yaw about z).
Eigen::Isometry3d startPose(const Eigen::Vector4d& xyz_yaw);

/**
 * The latest body-frame wrench command (~cmd_wrench) and its age. A command is fresh for `timeout` [s] of
 * ROS time after it arrived; then the thrust is zero (stale) until the next one. Non-finite commands are
 * refused and the one held stays. Not thread-safe (VehicleIo guards it). No master needed.
 */
class WrenchCommand
{
 public:
  explicit WrenchCommand(double timeout) : timeout_(timeout) {}

  /// Takes `command` [N, N m], body frame, arrived at `arrival`. Returns "" or why it was refused.
  std::string accept(const geometry_msgs::Wrench& command, const ros::Time& arrival);
  /// Counts a command refused before its numbers were read; returns `why`.
  std::string refuse(const std::string& why);
  /// Whether a command arrived no more than the timeout before `now`.
  bool fresh(const ros::Time& now) const;
  /// The thrust at `now`: the command while fresh, else zero. Sets `went_stale` true on the first call that
  /// finds a command stale (once per stale period: a new command starts a new one) and counts it.
  Wrench thrustAt(const ros::Time& now, bool* went_stale);
  /// Age of the command at `now` [s]; infinite before the first.
  double age(const ros::Time& now) const;
  /// Forgets a command that arrived after `clock`, as before the first: after the clock went back to `clock` its
  /// arrival lies ahead and it would count as fresh. One that arrived on the new clock stays. The counts stay.
  void forgetArrivedAfter(const ros::Time& clock)
  {
    if (arrival_ > clock)
    {
      command_ = Wrench::Zero();
      arrival_ = ros::Time();
      stale_said_ = false;
    }
  }

  std::uint64_t accepted() const { return accepted_; }
  std::uint64_t refused() const { return refused_; }
  /// Times a command went stale (the thrust fell to zero for want of a fresh one).
  std::uint64_t stalePeriods() const { return stale_periods_; }

 private:
  double timeout_;
  Wrench command_ = Wrench::Zero();
  ros::Time arrival_;        ///< Zero before the first command.
  bool stale_said_ = false;  ///< The current stale period was reported.
  std::uint64_t accepted_ = 0;
  std::uint64_t refused_ = 0;
  std::uint64_t stale_periods_ = 0;
};

/**
 * One tether's dynamic vehicle on ROS (TetherNode owns it with vehicle_model: dynamic): starts the tether's
 * VehicleBody (Tether::attachVehicleBody) at vehicle_start, or without it at the first pose taken from the
 * pose input, at rest, and again after every reset; before each physics tick sets the thrust: a fresh
 * ~cmd_wrench wins (WrenchCommand); without one, when poses came after the start, the built-in
 * VehicleController's thrust towards them (the poses are setpoints, interpolated at the physics time, as a
 * kinematic vehicle's end is); else zero (a command gone stale is warned once per stale period). With each
 * ~state it publishes ~odom (when subscribed) and tf world_frame -> rov_frame (always), stamped with the
 * physics time.
 */
class VehicleIo
{
 public:
  /// `tether` must outlive this. `label`: " name" among several tethers, "" alone (log messages).
  VehicleIo(const TetherSetup& setup, Tether& tether, const std::string& label);

  /// Subscribes ~cmd_wrench under `private_nh` on `input_queue` (the input thread), advertises ~odom and /tf.
  void advertise(const ros::NodeHandle& private_nh, ros::CallbackQueueInterface* input_queue);
  /// Physics thread: a pose taken from the pose input at time t [s] (PoseInput's sink). Starts the vehicle
  /// when it waits for its first pose; later poses are the controller's setpoints.
  Status takePose(double t, const Eigen::Isometry3d& vehicle);
  /// Physics thread, before the physics advances at ROS time `now`: starts the vehicle at vehicle_start
  /// when due, then sets its thrust.
  void beforeAdvance(const ros::Time& now);
  /// With each ~state: ~odom and tf at the tether's physics time.
  void publishState();
  /// After the tether was reset at ROS time `clock` (which ends the dynamic vehicle): it starts again
  /// (beforeAdvance, takePose), with no setpoint, the controller's integrals at zero and no command from before the
  /// clock went back.
  void restarted(const ros::Time& clock);
  /// The body's pose in the world frame; identity before the start.
  Eigen::Isometry3d pose() const;
  /// The /diagnostics values of the vehicle: commands taken, refused, stale periods, setpoints, what drives it,
  /// and the ticks with the thrust held at thrust_limit (WARN when there were some since the last report).
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);

  /// Any thread: a command message that arrived at `now` (the ~cmd_wrench callback).
  void receive(const geometry_msgs::WrenchStamped& msg, const ros::Time& now);

 private:
  /// Attaches the body at `pose` at rest; logs why not.
  bool start(const Eigen::Isometry3d& pose);
  /// The controller's thrust towards the setpoint at the tether's time (zero when refused, logged).
  Wrench controlledThrust();
  /// Physics thread: counts and warns (throttled) when the last step held the thrust at thrust_limit.
  void noteSaturation();

  NodeOptions options_;
  VehicleParams vehicle_params_;
  Tether& tether_;
  std::string label_;
  bool start_due_ = true;   ///< The vehicle waits to be started (at the start, after a reset).
  std::string water_said_;  ///< The vehicle's other water, as said at a start ("" before any).
  std::mutex command_mutex_;
  WrenchCommand command_;
  Wrench thrust_ = Wrench::Zero();  ///< The command applied on the last tick (before saturation) [N, N m].
  VehicleController controller_;
  VehicleHistory setpoints_;  ///< Poses taken after the start (world frame, vehicle origin).
  std::uint64_t setpoint_count_ = 0;
  double last_control_time_ = 0.0;  ///< Tether time of the controller's last update [s]; NaN: none since it took over.
  const char* driver_ = "none";     ///< What set the last thrust: "cmd_wrench", "controller" or "none".
  /// Physics thread: the ticks whose last step held the thrust at thrust_limit on some axis (under command_mutex_),
  /// and how many of them the last /diagnostics report had seen (its thread).
  std::uint64_t saturated_ticks_ = 0;
  std::uint64_t saturated_reported_ = 0;
  /// This vehicle's own log throttles (ROS_WARN_THROTTLE's belongs to the line: one tether's would hide another's):
  /// a command in another frame, another refused command (both under command_mutex_), a start refused, the thrust
  /// held at its limit, the controller refused, the level hold updated too rarely to settle, the thrust refused.
  LogThrottle frame_log_{1.0}, command_log_{1.0}, start_log_{5.0}, saturation_log_{5.0}, controller_log_{1.0},
      level_step_log_{10.0}, thrust_log_{1.0};
  ros::Subscriber command_sub_;
  ros::Publisher odom_pub_;
  ros::Publisher tf_pub_;
  tf2_msgs::TFMessage transforms_;
};

}  // namespace rov_tether::ros_layer
