#include "rov_tether/ros/tether_camera.hpp"

#include <cv_bridge/cv_bridge.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_eigen/tf2_eigen.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace rov_tether::ros_layer
{

TetherCamera::TetherCamera(const CameraConfig& config, ros::NodeHandle& nh, ros::NodeHandle& private_nh,
                           const tf2_ros::Buffer& tf, const std::string& world_frame, double max_future,
                           double max_wait, double render_budget)
    : config_(config),
      nh_(nh),
      tf_(tf),
      world_frame_(world_frame),
      max_future_(max_future),
      max_wait_(max_wait),
      budget_(render_budget),
      transport_(private_nh),
      schedule_(config.rate)
{
  if (config_.info_topic.empty())
  {
    const std::string error = buildCameraModel(config_.intrinsics, &model_);  // names D when it folds
    if (!error.empty())
    {
      throw std::invalid_argument(error);
    }
  }
  const auto connect = [this](const image_transport::SingleSubscriberPublisher&) { onConnection(); };
  const std::string base = config_.name + "/";
  mask_pub_ = transport_.advertise(base + "mask", 2, connect, connect);
  depth_pub_ = transport_.advertise(base + "depth", 2, connect, connect);
  if (!config_.image_topic.empty())
  {
    overlay_pub_ = transport_.advertise(base + "overlay", 2, connect, connect);
  }
  const auto connect_coverage = [this](const ros::SingleSubscriberPublisher&) { onConnection(); };
  coverage_pub_ = private_nh.advertise<TetherCoverage>(base + "coverage", 10, connect_coverage, connect_coverage);
  ROS_INFO("tether_node: camera %s in frame %s, %s, %s", config_.name.c_str(), config_.frame.c_str(),
           config_.info_topic.empty()
               ? (std::to_string(config_.intrinsics.width) + "x" + std::to_string(config_.intrinsics.height)).c_str()
               : ("intrinsics from " + nh_.resolveName(config_.info_topic)).c_str(),
           config_.image_topic.empty() ? ("at " + std::to_string(config_.rate) + " Hz").c_str()
                                       : ("at the stamps of " + nh_.resolveName(config_.image_topic)).c_str());
}

bool TetherCamera::active() const
{
  return mask_pub_.getNumSubscribers() > 0 || depth_pub_.getNumSubscribers() > 0 ||
         (overlay_pub_ && overlay_pub_.getNumSubscribers() > 0) || coverage_pub_.getNumSubscribers() > 0;
}

void TetherCamera::onConnection()
{
  const bool active_now = active();
  if (active_now && !subscribed_)
  {
    if (!config_.info_topic.empty())
    {
      info_sub_ = nh_.subscribe(config_.info_topic, 2, &TetherCamera::onInfo, this);
    }
    if (!config_.image_topic.empty())
    {
      image_transport::ImageTransport it(nh_);
      image_sub_ = it.subscribe(config_.image_topic, 5, &TetherCamera::onImage, this);
    }
    schedule_.reset();
  }
  else if (!active_now && subscribed_)
  {
    info_sub_.shutdown();
    image_sub_.shutdown();
    queue_.clear();
  }
  subscribed_ = active_now;
}

void TetherCamera::onInfo(const sensor_msgs::CameraInfoConstPtr& info)
{
  camera::CameraIntrinsics intrinsics;
  const std::string error = intrinsicsFromCameraInfo(*info, &intrinsics);
  if (!error.empty())
  {
    worker_.cancel();  // a build of earlier intrinsics is not this CameraInfo's either
    refuseInfo(error);
    return;
  }
  takeBuiltModel();
  if (model_ ? model_->intrinsics() == intrinsics : worker_.requested() == intrinsics || unbuildable_ == intrinsics)
  {
    return;  // the same intrinsics again: built, being built, or refused by their build (seconds each time)
  }
  // Built off this thread (seconds for a distorted camera, which held the physics here); anything building throws
  // (std::bad_alloc too) refuses this CameraInfo when the build is taken, and never ends the node. The old model
  // goes first, so the two never take memory together.
  model_.reset();
  worker_.request(intrinsics);
  info_error_.clear();
  last_warning_.erase("building");  // each new build is said once
}

void TetherCamera::takeBuiltModel()
{
  std::optional<CameraModelWorker::Built> built = worker_.take();
  if (!built)
  {
    return;
  }
  if (!built->error.empty())
  {
    unbuildable_ = built->intrinsics;
    refuseInfo(built->error);
    return;
  }
  model_ = std::move(built->model);
  info_error_.clear();
}

void TetherCamera::refuseInfo(const std::string& why)
{
  model_.reset();
  info_error_ = why;
  // Its own key: the frames dropped for want of a model warn under "info", with their count.
  if (warningDue("info_refused"))
  {
    ROS_WARN("tether_node: camera %s: CameraInfo on %s refused: %s", config_.name.c_str(), info_sub_.getTopic().c_str(),
             why.c_str());
  }
}

void TetherCamera::onImage(const sensor_msgs::ImageConstPtr& image)
{
  const double ahead = (image->header.stamp - ros::Time::now()).toSec();
  if (ahead > max_future_)
  {
    char why[160];
    std::snprintf(why, sizeof(why), "image stamped %.3f s ahead of ROS time, beyond max_pose_future %.3f s", ahead,
                  max_future_);
    drop("future", why);
    return;
  }
  // The physics runs up to stale_pose_timeout behind ROS time while it waits for poses (1 Hz fixes, a pause): the
  // images wait as long (30 of them, a second at 30 Hz, dropped the one due next, so none was drawn).
  const ros::Time now = ros::Time::now();
  while (!queue_.empty() && (now - queue_.front()->header.stamp).toSec() > max_wait_)
  {
    char why[200];
    std::snprintf(why, sizeof(why),
                  "an image waited %.2f s for the physics, more than %.2f s (stale_pose_timeout + "
                  "interpolation_delay + 0.5 s): are the poses, the clock or the physics stalled?",
                  (now - queue_.front()->header.stamp).toSec(), max_wait_);
    queue_.pop_front();
    drop("queue", why);
  }
  if (queue_.size() >= kMaxQueued)
  {
    queue_.pop_front();
    drop("queue_full", "more than " + std::to_string(kMaxQueued) + " images wait for the physics");
  }
  queue_.push_back(image);
}

bool TetherCamera::warningDue(const std::string& reason)
{
  const ros::WallTime now = ros::WallTime::now();
  const auto last = last_warning_.find(reason);
  if (last != last_warning_.end() && (now - last->second).toSec() < 5.0)
  {
    return false;
  }
  last_warning_[reason] = now;
  return true;
}

void TetherCamera::drop(const std::string& reason, const std::string& why)
{
  ++dropped_;
  if (warningDue(reason))
  {
    ROS_WARN("tether_node: camera %s: frame not drawn (%llu so far): %s", config_.name.c_str(),
             static_cast<unsigned long long>(dropped_), why.c_str());
  }
}

void TetherCamera::process(camera::CameraScene& scene)
{
  if (!subscribed_ || scene.empty())
  {
    return;
  }
  takeBuiltModel();
  if (config_.image_topic.empty())
  {
    // Frames on a grid of physics time: k / rate.
    const double was = schedule_.next();
    FrameSchedule::Start start = FrameSchedule::Start::kKept;
    const std::vector<double> times = schedule_.due(scene.oldest(), scene.newest(), &start);
    if (start == FrameSchedule::Start::kRestarted && warningDue("schedule"))
    {
      ROS_WARN(
          "tether_node: camera %s: its frame schedule restarted at %.3f s: its next frame at %.3f s lay outside "
          "the tether shapes kept (%.3f-%.3f s), the clock jumped (a bag played in a loop?)",
          config_.name.c_str(), times.empty() ? schedule_.next() : times.front(), was, scene.oldest(), scene.newest());
    }
    for (const double t : times)
    {
      renderAt(ros::Time(t), scene, nullptr);
    }
    return;
  }
  // Each image waits for its own stamp only: one stamped ahead never holds up those behind it.
  for (auto it = queue_.begin(); it != queue_.end();)
  {
    if ((*it)->header.stamp.toSec() <= scene.newest() + 1e-9)
    {
      const sensor_msgs::ImageConstPtr image = *it;
      it = queue_.erase(it);
      renderAt(image->header.stamp, scene, image);
    }
    else
    {
      ++it;
    }
  }
}

bool TetherCamera::renderAt(const ros::Time& stamp, camera::CameraScene& scene, const sensor_msgs::ImageConstPtr& image)
{
  if (!model_ && worker_.pending())
  {
    const camera::CameraIntrinsics& next = *worker_.requested();
    drop("building", "the camera of the last CameraInfo (" + std::to_string(next.width) + "x" +
                         std::to_string(next.height) + ") is being built: a distorted camera takes seconds");
    return false;
  }
  if (!model_)
  {
    drop("info", info_error_.empty() ? "no CameraInfo yet on " + nh_.resolveName(config_.info_topic)
                                     : "the last CameraInfo was refused: " + info_error_);
    return false;
  }
  if (image &&
      (static_cast<int>(image->width) != model_->width() || static_cast<int>(image->height) != model_->height()))
  {
    drop("size", "image " + std::to_string(image->width) + "x" + std::to_string(image->height) +
                     " but intrinsics for " + std::to_string(model_->width()) + "x" + std::to_string(model_->height()));
    return false;
  }
  if (!scene.tubesAt(stamp.toSec(), tubes_))
  {
    drop("past", "stamp " + std::to_string(stamp.toSec()) + " s is older than the tether shapes kept (from " +
                     std::to_string(scene.oldest()) + " s)");
    return false;
  }
  Eigen::Isometry3d pose;
  try
  {
    pose = tf2::transformToEigen(tf_.lookupTransform(world_frame_, config_.frame, stamp));
  }
  catch (const tf2::TransformException& e)
  {
    drop("tf", std::string("no transform ") + world_frame_ + " -> " + config_.frame + ": " + e.what());
    return false;
  }
  const double pixels = static_cast<double>(model_->width()) * model_->height();
  if (!budget_.allows(pixels, ros::WallTime::now().toSec()))
  {
    drop("budget", budget_.why(model_->width(), model_->height()));
    return false;
  }
  const ros::WallTime start = ros::WallTime::now();
  const camera::RenderStats stats = renderer_.render(*model_, pose, tubes_, scene.occluders());
  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = config_.frame;
  publishRendered(header, stats, image);
  const double took = (ros::WallTime::now() - start).toSec();
  budget_.measured(pixels, took);
  if (took > budget_.budget() && warningDue("slow"))
  {
    ROS_WARN(
        "tether_node: camera %s: a %dx%d frame took %.2f s to draw, more than its budget of %.2f s (max_lag): "
        "frames as large are skipped, and one is drawn to measure again after %.0f s of skipping",
        config_.name.c_str(), model_->width(), model_->height(), took, budget_.budget(), budget_.retry());
  }
  return true;
}

void TetherCamera::publishRendered(const std_msgs::Header& header, const camera::RenderStats& stats,
                                   const sensor_msgs::ImageConstPtr& image)
{
  if (mask_pub_.getNumSubscribers() > 0)
  {
    updateImageMessage(renderer_.mask(), renderer_.pixels(), &mask_msg_pixels_, header, &mask_msg_);
    mask_pub_.publish(mask_msg_);
  }
  if (depth_pub_.getNumSubscribers() > 0)
  {
    updateImageMessage(renderer_.depth(), renderer_.pixels(), &depth_msg_pixels_, header, &depth_msg_);
    depth_pub_.publish(depth_msg_);
  }
  if (coverage_pub_.getNumSubscribers() > 0)
  {
    coverage_msg_.header = header;
    coverage_msg_.coverage = static_cast<float>(stats.coverage);
    coverage_msg_.pixels = static_cast<std::uint32_t>(stats.pixels);
    coverage_msg_.nearest_depth = static_cast<float>(stats.nearest_depth);
    coverage_pub_.publish(coverage_msg_);
  }
  if (image && overlay_pub_.getNumSubscribers() > 0)
  {
    try
    {
      cv_bridge::CvImagePtr overlay = cv_bridge::toCvCopy(image, sensor_msgs::image_encodings::BGR8);
      camera::drawOverlay(overlay->image, renderer_.pixels());
      overlay_pub_.publish(overlay->toImageMsg());
    }
    catch (const cv_bridge::Exception& e)
    {
      drop("encoding", "overlay: cannot convert the image's encoding '" + image->encoding + "' to bgr8: " + e.what());
    }
  }
}

CameraSet::CameraSet(const std::vector<CameraConfig>& cameras, ros::NodeHandle& nh, ros::NodeHandle& private_nh,
                     const tf2_ros::Buffer& tf, const World& world, const std::string& world_frame, double max_future,
                     double max_wait, double render_budget)
    : scene_(world)
{
  for (const auto& config : cameras)
  {
    try
    {
      cameras_.push_back(
          std::make_unique<TetherCamera>(config, nh, private_nh, tf, world_frame, max_future, max_wait, render_budget));
    }
    catch (const std::invalid_argument& e)
    {
      throw std::runtime_error("parameter cameras: camera '" + config.name + "': " + e.what());
    }
  }
}

void CameraSet::afterTick()
{
  bool any = false;
  for (const auto& camera : cameras_)
  {
    any = any || camera->active();
  }
  if (!any)
  {
    scene_.clear();
    return;
  }
  scene_.record();
  for (const auto& camera : cameras_)
  {
    camera->process(scene_);
  }
}

}  // namespace rov_tether::ros_layer
