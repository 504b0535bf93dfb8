#pragma once

#include <image_transport/image_transport.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/Header.h>
#include <tf2_ros/buffer.h>

#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rov_tether/TetherCoverage.h"
#include "rov_tether/camera/camera_scene.hpp"
#include "rov_tether/camera/tether_renderer.hpp"
#include "rov_tether/ros/camera_config.hpp"
#include "rov_tether/ros/camera_model_worker.hpp"
#include "rov_tether/ros/frame_schedule.hpp"
#include "rov_tether/ros/render_budget.hpp"

namespace rov_tether::ros_layer
{

/**
 * One camera of tether_node: ~<name>/mask (mono8), ~<name>/depth (32FC1 [m]), ~<name>/overlay (the
 * incoming image with the tether drawn, with image_topic) through image_transport, and ~<name>/coverage
 * (TetherCoverage), each stamped with the image's stamp (or, at `rate`, a time of its grid) in the
 * camera's frame. The tether is drawn as it was at the stamp (CameraScene's shapes, interpolated) and
 * the camera where tf puts its frame at the stamp. Frames wait until the physics has passed their stamp
 * (it runs interpolation_delay behind ROS time). Nothing is subscribed or computed while nobody
 * subscribes to an output. Every frame that cannot be drawn is counted and warned about, throttled per
 * camera and per reason (one camera's warnings never hide another's). An image stamped further ahead of
 * ROS time than `max_future` is dropped as it arrives; an image waits only for its own stamp, so a bad
 * stamp never holds up the good images behind it. A frame predicted to take longer to draw than
 * `render_budget` (RenderBudget) is skipped and said, so the node never stalls on one camera. A CameraInfo with new
 * intrinsics is built on a thread of its own (CameraModelWorker: seconds for a distorted camera), its frames
 * meanwhile not drawn and said; the physics goes on. Fixed intrinsics are built in the constructor, at start.
 */
class TetherCamera
{
 public:
  /// Advertises under private_nh/<name>/; topics are resolved in `nh`. `tf` must outlive this.
  /// `max_future` [s]: images stamped further ahead of ROS time are dropped (the node's max_pose_future);
  /// `max_wait` [s]: an image waits for the physics this long after its stamp at most (the physics waits for poses
  /// up to stale_pose_timeout behind ROS time, plus interpolation_delay: CameraSet::maxWait);
  /// `render_budget` [s]: the longest a frame may take to draw (the node's max_lag).
  TetherCamera(const CameraConfig& config, ros::NodeHandle& nh, ros::NodeHandle& private_nh, const tf2_ros::Buffer& tf,
               const std::string& world_frame, double max_future, double max_wait, double render_budget);

  /// Someone subscribes to one of its outputs.
  bool active() const;
  /// Draws and publishes every frame whose stamp the scene's shapes now cover.
  void process(camera::CameraScene& scene);
  /// Frames that could not be drawn (no intrinsics, no tf, stamp outside the shapes, queue full, size).
  std::uint64_t dropped() const { return dropped_; }
  const std::string& name() const { return config_.name; }

  /// At most this many images wait for the physics to reach their stamp (a bound on memory: 10 s at 30 Hz; the
  /// wait itself is bounded by max_wait).
  static constexpr std::size_t kMaxQueued = 300;

 private:
  void onConnection();
  void onInfo(const sensor_msgs::CameraInfoConstPtr& info);
  /// Takes the model of the last CameraInfo's intrinsics when its build (on worker_'s thread) has finished.
  void takeBuiltModel();
  /// A CameraInfo, or the build of its intrinsics, refused: no model, warned (throttled) with why.
  void refuseInfo(const std::string& why);
  void onImage(const sensor_msgs::ImageConstPtr& image);
  /// Renders at `stamp` and publishes; `image` (may be null) gets the overlay. False when it cannot.
  bool renderAt(const ros::Time& stamp, camera::CameraScene& scene, const sensor_msgs::ImageConstPtr& image);
  /// Publishes what the last render drew to the topics someone listens to: mask, depth, coverage, and the
  /// overlay on `image` when given.
  void publishRendered(const std_msgs::Header& header, const camera::RenderStats& stats,
                       const sensor_msgs::ImageConstPtr& image);
  /// Counts a frame not drawn and warns, at most every 5 s for this camera and this `reason` (a short key).
  void drop(const std::string& reason, const std::string& why);
  /// True when this camera's warning about `reason` is due (none in the last 5 s of wall time).
  bool warningDue(const std::string& reason);

  CameraConfig config_;
  ros::NodeHandle nh_;
  const tf2_ros::Buffer& tf_;
  std::string world_frame_;
  double max_future_;  ///< [s]
  double max_wait_;    ///< [s]
  RenderBudget budget_;
  std::map<std::string, ros::WallTime> last_warning_;  ///< This camera's last warning per reason.
  image_transport::ImageTransport transport_;
  image_transport::Publisher mask_pub_, depth_pub_, overlay_pub_;
  ros::Publisher coverage_pub_;
  ros::Subscriber info_sub_;
  image_transport::Subscriber image_sub_;
  bool subscribed_ = false;
  std::unique_ptr<camera::CameraModel> model_;
  std::string info_error_;  ///< Why the last CameraInfo was refused ("" when it was taken).
  /// Builds the models of a CameraInfo's new intrinsics off the callback thread (declared after model_: it is
  /// destroyed first, waiting for a build in progress).
  CameraModelWorker worker_;
  /// The last intrinsics whose build failed: the same CameraInfo again is refused without building it again.
  std::optional<camera::CameraIntrinsics> unbuildable_;
  camera::TetherRenderer renderer_;
  std::vector<camera::Tube> tubes_;
  std::deque<sensor_msgs::ImageConstPtr> queue_;
  FrameSchedule schedule_;  ///< Rate mode: the frames' times.
  std::uint64_t dropped_ = 0;
  sensor_msgs::Image mask_msg_, depth_msg_;
  std::vector<int> mask_msg_pixels_, depth_msg_pixels_;  ///< The tether pixels each message holds.
  TetherCoverage coverage_msg_;
};

/**
 * tether_node's cameras (the private list `cameras`): the CameraScene of the process's World and one
 * TetherCamera each. After every physics tick it records the tethers' shapes, while any camera has a
 * subscriber, and lets each camera draw what is due.
 */
class CameraSet
{
 public:
  /// The cameras as read (loadCameraConfigs, into the WorldSpec). Throws std::runtime_error naming a camera
  /// that cannot be set up. `world` and `tf` must outlive this.
  CameraSet(const std::vector<CameraConfig>& cameras, ros::NodeHandle& nh, ros::NodeHandle& private_nh,
            const tf2_ros::Buffer& tf, const World& world, const std::string& world_frame, double max_future,
            double max_wait, double render_budget);
  /// How long an image may wait for the physics [s]: the longest the physics waits for poses behind ROS time
  /// (stale_pose_timeout), plus interpolation_delay and half a second for the ticks.
  static double maxWait(double stale_pose_timeout, double interpolation_delay)
  {
    return stale_pose_timeout + interpolation_delay + 0.5;
  }
  void afterTick();
  std::size_t size() const { return cameras_.size(); }

 private:
  camera::CameraScene scene_;
  std::vector<std::unique_ptr<TetherCamera>> cameras_;
};

}  // namespace rov_tether::ros_layer
