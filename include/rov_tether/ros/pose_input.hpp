#pragma once

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/callback_queue_interface.h>
#include <ros/node_handle.h>
#include <ros/subscriber.h>
#include <ros/time.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/message_filter.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <topic_tools/shape_shifter.h>

#include <Eigen/Geometry>
#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "rov_tether/core/tether.hpp"
#include "rov_tether/ros/log_throttle.hpp"
#include "rov_tether/ros/param_loader.hpp"
#include "rov_tether/ros/vehicle_history.hpp"

namespace rov_tether::ros_layer
{

/// Why a pose's numbers are refused ("" when they are fine): a non-finite position or orientation, or a
/// quaternion whose norm is off 1 by more than 1e-3.
std::string checkPose(const geometry_msgs::Pose& pose);

/// The kind of a warning `why` (its text with each number, nan and inf as one '#'), which PoseInput throttles: one
/// reason arriving with other values each time is one kind, not a new warning each.
std::string warningKind(const std::string& why);

/// The pose as a rigid transform (the quaternion taken as given; checkPose it first).
Eigen::Isometry3d toIsometry(const geometry_msgs::Pose& pose);

/**
 * One tether's vehicle (and spool) input: the `rov_pose` subscription or, with `pose_source: tf`, the
 * lookup of world_frame -> rov_frame; and `spool_frame` when the spool moves.
 *
 * Poses are received on the input's own callback queue (its own thread in the node), so a slow physics
 * tick never holds them up: receive() checks a pose's numbers (finite, normalised) and hands it to the
 * physics thread, after waiting, when it is stamped in another frame, in a tf2_ros::MessageFilter until tf
 * can transform it at its stamp. On the physics thread, poll() takes what was handed over: brings each
 * pose into world_frame, moves it to the attachment point (attachment_offset in the vehicle frame) and
 * hands it to Tether::addVehicleSample. A pose still waiting for tf when the physics reaches its stamp is
 * refused: the physics' delay behind ROS time is the slack tf has. Every refused pose is counted and
 * logged (throttled) with the reason; more than kMaxHandOver poses waiting for the physics are dropped
 * and counted. Needs no ROS master except for subscribe().
 *
 * With world_frame_from_pose, a pose whose frame tf cannot connect to world_frame by the time the physics
 * reaches it, while nobody else uses world_frame in tf (no parent, no children but the node's own
 * spool_outlet_frame and cable_end_frame), makes world_frame
 * the pose's frame: the identity pose frame -> world_frame goes into the buffer (and /tf_static once
 * subscribed), INFO, and the pose is taken. A pose in map or odom (mavros) thus works out of the box.
 */
class PoseInput
{
 public:
  /// Poses that may wait for the physics thread; more are dropped and counted (1 kHz for 4 s).
  static constexpr std::size_t kMaxHandOver = 4096;
  /// Poses that may wait in the MessageFilter for their transform (1 kHz for 1 s).
  static constexpr std::uint32_t kMaxWaitingForTf = 1000;

  /// `tf` is shared by every tether of the process and must outlive this; so must `tether`. `label`
  /// names the tether in log messages ("" alone). The MessageFilter delivers on `input_queue` (the
  /// thread that calls the tf buffer's setTransform when null).
  PoseInput(const NodeOptions& options, tf2_ros::Buffer& tf, Tether& tether, const std::string& label = "",
            ros::CallbackQueueInterface* input_queue = nullptr);

  /// Subscribes to pose_topic (relative to `nh`, whose callback queue should be the input queue) when
  /// pose_source is "topic", whatever its type; messages go to receiveAny() at ros::Time::now().
  void subscribe(ros::NodeHandle& nh);
  /// Where poses go instead of Tether::addVehicleSample (a dynamic vehicle: VehicleIo::takePose): the vehicle
  /// origin's pose in world_frame at time t [s]; a refusal is counted and logged as the tether's would be.
  using VehicleSink = std::function<Status(double t, const Eigen::Isometry3d& vehicle)>;
  void setVehicleSink(VehicleSink sink) { sink_ = std::move(sink); }

  /// The subscribed topic's resolved name; pose_topic before subscribe().
  const std::string& topic() const { return topic_; }
  /// The frame world_frame was taken as (world_frame_from_pose); "" while it is its own.
  const std::string& adoptedFrame() const { return adopted_frame_; }

  /// Any thread: a pose message that arrived at `now`. Refused (counted) when its numbers are bad or its
  /// stamp is more than max_pose_future ahead of `now`; else
  /// handed to the physics thread, in another frame once tf can transform it (a zero stamp means `now`).
  void receive(const geometry_msgs::PoseStamped::ConstPtr& msg, const ros::Time& now);
  /// Any thread: a message of any type on pose_topic that arrived at `now`: a geometry_msgs/PoseStamped,
  /// or a nav_msgs/Odometry (robot_localization, mavros odom: its header and pose.pose; the twist and the
  /// covariances are not used), goes to receive(); any other type is refused, counted, and named.
  void receiveAny(const topic_tools::ShapeShifter::ConstPtr& msg, const ros::Time& now);
  /// Physics thread, once per tick at `now` (after the tick's clock policy, so a pose of a clock that
  /// went back meets a tether already reset): takes every pose handed over, refuses the poses still
  /// waiting for tf whose stamp the physics has passed, and polls tf for the spool (spool_frame) and,
  /// with pose_source tf, the vehicle (a static transform, stamp 0, is taken as a pose at `now`).
  void poll(const ros::Time& now);
  /// After the tether was reset on the tick at ROS time `now`: forgets the poses' timing and history, so the next
  /// pose is taken, and refuses (counts) the poses still waiting that arrived after `now`: they came on a
  /// clock that has since gone back (a bag that loops), and would stop every pose of the new time line. (Not
  /// after the time it restarted at: a clock gone back restarts at its first pose, and its later ones up to
  /// `now` are its own.)
  void reset(const ros::Time& now);
  /// After a reset someone asked for at ROS time `cut` (~reset), not one a clock jump forced: refuses
  /// (counts, warns) every pose stamped before `cut`, taken later or not, so a pose of the vehicle before
  /// the reset (still queued, or delivered late) does not lay the fresh cable out to where it was.
  void refuseStampedBefore(const ros::Time& cut) { reset_cut_ = cut; }
  /// Where to cut for a reset asked for at ROS time `now` (before reset()): `now`, or just after the latest
  /// stamp of a pose received so far when that is later. A publisher on a simulated clock runs ahead of the
  /// node's: its poses received before the reset, stamped after the node's `now`, show the vehicle before it.
  ros::Time resetCut(const ros::Time& now) const;

  /// Poses refused (bad numbers, frames tf cannot transform in time, refused by the core).
  std::uint64_t rejected() const { return rejected_; }
  /// Of rejected(): poses stamped further ahead of ROS time than max_pose_future.
  std::uint64_t future() const { return future_; }
  /// Poses dropped because more than kMaxHandOver waited for the physics.
  std::uint64_t dropped() const { return dropped_; }
  /// Poses taken into the tether.
  std::uint64_t accepted() const { return accepted_; }
  /// Of accepted(): poses that came, as the one before did, later after their predecessor's stamp than
  /// stale_pose_timeout lets the physics wait, and found it past the one before: the cable end held and caught up
  /// faster than the vehicle moved (one late pose after an outage is not counted: the stale-pose warning says it).
  std::uint64_t late() const { return late_; }
  /// The last accepted vehicle pose in world_frame (the vehicle origin, not the attachment).
  const Eigen::Isometry3d& lastVehicle() const { return last_vehicle_; }
  /// The vehicle pose in world_frame at time t [s], interpolated between the poses taken; t must not
  /// decrease between calls (the physics' time). Identity before the first pose.
  Eigen::Isometry3d vehicleAt(double t) { return history_.at(t); }
  /// When the last pose was accepted (ROS time of the tick that took it); zero before the first.
  const ros::Time& lastPoseTime() const { return last_pose_time_; }
  /// ROS time the earliest pose waiting for the physics arrived; zero when none waits.
  ros::Time earliestArrival() const;
  /// Stamp of the last pose taken [s]; NaN before the first (the physics need not wait for poses).
  double latestStamp() const;
  /// How far behind ROS time the physics must run for the poses to bracket it [s]: the largest gap, over
  /// the last kGaps poses taken, between a pose being taken (the tick that took it) and the stamp of
  /// the pose before it. 0 before two poses.
  double neededDelay() const;

 private:
  using Filter = tf2_ros::MessageFilter<geometry_msgs::PoseStamped>;
  static constexpr std::size_t kGaps = 16;

  /// A pose handed to the physics thread: the message and when it arrived.
  struct HandOver
  {
    geometry_msgs::PoseStamped::ConstPtr msg;
    ros::Time arrival;
  };

  /// Input side: queues a checked pose for the physics thread (counts it dropped when full).
  void handOver(const geometry_msgs::PoseStamped::ConstPtr& msg, const ros::Time& arrival);
  /// MessageFilter callbacks (input thread): the pose can be transformed now, or never.
  void onTransformable(const geometry_msgs::PoseStamped::ConstPtr& msg);
  void onFilterFailure(const geometry_msgs::PoseStamped::ConstPtr& msg,
                       tf2_ros::filter_failure_reasons::FilterFailureReason reason);
  /// Removes `msg` from the poses waiting for tf; returns its arrival time, or zero when it was not there
  /// (already refused as too late).
  ros::Time stopWaiting(const geometry_msgs::PoseStamped* msg);
  /// Physics side: refuses the poses waiting for tf whose stamp the physics has passed (or, when it takes
  /// world_frame as their frame, takes them at `now`).
  void expireWaiting(const ros::Time& now);
  /// Physics side: one handed-over pose into the tether.
  void take(const HandOver& pose, const ros::Time& now);
  /// world_frame -> frame at `time` (0: latest) with the transform's stamp; false and a warning when tf cannot
  /// tell, throttled by `log` (one a use: a missing spool frame, looked up every tick, does not hide the vehicle's).
  bool lookup(const std::string& frame, const ros::Time& time, LogThrottle& log, Eigen::Isometry3d* pose,
              ros::Time* stamp = nullptr);
  /// The vehicle at `vehicle` (world frame) at `stamp` into the tether; counts and logs a refusal.
  bool addVehicle(const Eigen::Isometry3d& vehicle, const ros::Time& stamp, const ros::Time& now);
  /// The vehicle into the sink (a dynamic vehicle's setpoints) at `stamp`, in the order the core keeps for its
  /// samples (VehicleTrack::order): an older stamp refused, the same stamp replacing the last and said.
  Status sinkPose(const Eigen::Isometry3d& vehicle, const Position& attachment, const ros::Time& stamp);
  void refuse(const std::string& why);
  /// Warns of `why` at most once a second for each kind of reason (warningKind: its text without its numbers), so
  /// that one problem arriving often does not hide another.
  void warnEach(const char* what, const std::string& why);
  /// Says once, at INFO, how a pose the node takes was read (`key` the case, `text` what it did).
  void noteOnce(const std::string& key, const std::string& text);
  /// Refuses (counts) a pose stamped `ahead` [s] of ROS time, beyond max_pose_future.
  void refuseFuture(double ahead);
  /// What to do about a pose in `frame` that tf cannot bring into world_frame (for the warnings).
  std::string noTransformAdvice(const std::string& frame) const;
  /// Physics side: when world_frame_from_pose allows it, takes world_frame as `frame` (see the class
  /// comment); true when it did.
  bool adoptFrame(const std::string& frame);
  /// Physics side: logs an error (once) when tf has, from elsewhere, the adopted frame under world_frame.
  void checkAdoption();
  /// Whether tf holds world_frame with a parent, or with children other than the node's own frames.
  bool worldFrameInUse() const;

  NodeOptions options_;
  tf2_ros::Buffer& tf_;
  Tether& tether_;
  std::string label_;                    ///< " name" for log messages, "" alone.
  std::string topic_;                    ///< The pose topic as resolved (for the warnings).
  std::string adopted_frame_;            ///< The pose frame world_frame was taken as; "" none.
  bool adoption_conflict_said_ = false;  ///< checkAdoption's error was logged.
  ros::Subscriber subscriber_;
  std::unique_ptr<tf2_ros::StaticTransformBroadcaster> static_broadcaster_;  ///< Made by subscribe().
  std::unique_ptr<Filter> filter_;  ///< Poses in other frames wait here for their transform.
  VehicleSink sink_;                ///< Empty: poses go to the tether.

  mutable std::mutex mutex_;              ///< Guards the two lists below (input and physics threads).
  std::vector<HandOver> hand_over_;       ///< Received, for the physics thread (capacity kMaxHandOver).
  std::vector<HandOver> waiting_for_tf_;  ///< In the MessageFilter, with their arrival times.
  ros::Time latest_received_;             ///< The latest stamp of the poses received since the last reset.
  std::vector<HandOver> taking_;          ///< Physics thread: the poses being taken (swapped with hand_over_).

  std::mutex warn_mutex_;                               ///< Guards the two below (input and physics threads).
  std::vector<std::pair<std::string, double>> warned_;  ///< Each reason's kind and when it was last warned [s, wall].
  std::vector<std::string> noted_;                      ///< The cases noteOnce has said.
  std::atomic<std::uint64_t> rejected_{0};
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<std::uint64_t> future_{0};
  std::uint64_t accepted_ = 0;
  std::uint64_t late_ = 0;
  bool last_gap_over_ = false;  ///< The last pose came more than stale_pose_timeout after its predecessor's stamp.
  ros::Time last_pose_time_;    ///< ROS time the last accepted pose was taken.
  ros::Time last_pose_stamp_;   ///< Stamp of the last accepted pose.
  ros::Time reset_cut_;         ///< Poses stamped before it are from before a requested reset (zero: none).
  /// pose_source tf: the stamp of the last vehicle transform taken or refused. tf keeps handing out the latest
  /// transform every tick until a newer one comes: it is one pose, counted once.
  ros::Time tf_handled_;
  Eigen::Isometry3d last_vehicle_ = Eigen::Isometry3d::Identity();
  VehicleHistory history_;
  std::array<double, kGaps> gaps_{};  ///< Ring of the last gaps (see neededDelay) [s].
  std::size_t gap_count_ = 0;
  /// This tether's own log throttles, once a second each (ROS_WARN_THROTTLE's belongs to the line: one tether's
  /// would hide another's): poses dropped, expired waiting for tf, the spool frame, no transform to the spool frame,
  /// to rov_frame (pose_source tf) and to a pose's frame, poses from before a reset, poses from before the clock went
  /// back.
  LogThrottle drop_log_{1.0}, expired_log_{1.0}, spool_log_{1.0}, spool_transform_log_{1.0},
      vehicle_transform_log_{1.0}, frame_transform_log_{1.0}, before_reset_log_{1.0}, clock_back_log_{1.0};
};

}  // namespace rov_tether::ros_layer
