#include "rov_tether/ros/pose_input.hpp"

#include <ros/console.h>
#include <tf2_eigen/tf2_eigen.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <regex>

namespace rov_tether::ros_layer
{

std::string checkPose(const geometry_msgs::Pose& pose)
{
  const auto& p = pose.position;
  const auto& q = pose.orientation;
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
  {
    char text[160];
    std::snprintf(text, sizeof(text), "position (x, y, z) = (%g, %g, %g) is not finite", p.x, p.y, p.z);
    return text;
  }
  if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z) || !std::isfinite(q.w))
  {
    char text[160];
    std::snprintf(text, sizeof(text), "orientation (x, y, z, w) = (%g, %g, %g, %g) is not finite", q.x, q.y, q.z, q.w);
    return text;
  }
  const double norm = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  if (std::abs(norm - 1.0) > 1e-3)
  {
    char text[80];
    std::snprintf(text, sizeof(text), "quaternion is not normalised (|q| = %.6f)", norm);
    return text;
  }
  return "";
}

std::string warningKind(const std::string& why)
{
  // A number (sign, digits, point, exponent), nan or inf.
  static const std::regex number("[-+]?(nan|inf|[0-9]*\\.?[0-9]+([eE][-+]?[0-9]+)?)");
  return std::regex_replace(why, number, "#");
}

Eigen::Isometry3d toIsometry(const geometry_msgs::Pose& pose)
{
  const auto& p = pose.position;
  const auto& q = pose.orientation;
  return Eigen::Translation3d(p.x, p.y, p.z) * Eigen::Quaterniond(q.w, q.x, q.y, q.z);
}

PoseInput::PoseInput(const NodeOptions& options, tf2_ros::Buffer& tf, Tether& tether, const std::string& label,
                     ros::CallbackQueueInterface* input_queue)
    : options_(options), tf_(tf), tether_(tether), label_(label.empty() ? "" : " " + label), topic_(options.pose_topic)
{
  hand_over_.reserve(kMaxHandOver);
  taking_.reserve(kMaxHandOver);
  waiting_for_tf_.reserve(kMaxWaitingForTf + 1);
  if (options_.pose_source == "topic")
  {
    filter_ = std::make_unique<Filter>(tf_, options_.world_frame, kMaxWaitingForTf, input_queue);
    filter_->registerCallback(&PoseInput::onTransformable, this);
    filter_->registerFailureCallback([this](const geometry_msgs::PoseStamped::ConstPtr& msg,
                                            tf2_ros::filter_failure_reasons::FilterFailureReason reason)
                                     { onFilterFailure(msg, reason); });
  }
}

void PoseInput::subscribe(ros::NodeHandle& nh)
{
  if (options_.pose_source != "topic")
  {
    return;
  }
  // The callback only checks and hands over, on the input's own thread: a deep queue never fills. Any type
  // is subscribed (PoseStamped or Odometry, told apart by the publisher's type).
  subscriber_ = nh.subscribe<topic_tools::ShapeShifter>(options_.pose_topic, kMaxHandOver,
                                                        [this](const topic_tools::ShapeShifter::ConstPtr& msg)
                                                        { receiveAny(msg, ros::Time::now()); });
  topic_ = subscriber_.getTopic();
  static_broadcaster_ = std::make_unique<tf2_ros::StaticTransformBroadcaster>();
}

std::string PoseInput::noTransformAdvice(const std::string& frame) const
{
  return "poses on " + topic_ + " are in '" + frame + "': publish the transform " + options_.world_frame + " -> " +
         frame + ", or set world_frame to '" + frame + "' (tether.launch world_frame:=" + frame + ")";
}

bool PoseInput::worldFrameInUse() const
{
  std::string parent;
  if (tf_._getParent(options_.world_frame, ros::Time(0), parent))
  {
    return true;  // someone places it
  }
  // Children of world_frame other than the node's own frames (the spool outlet and the cable end, of any
  // tether: "name/tether_spool"; and every dynamic vehicle's rov_frame, which the node publishes from the first
  // tick with vehicle_start) mean someone else works in it.
  const auto own = [this](const std::string& child)
  {
    const auto& vehicles = options_.node_vehicle_frames;
    if ((options_.vehicle_model == "dynamic" && child == options_.rov_frame) ||
        std::find(vehicles.begin(), vehicles.end(), child) != vehicles.end())
    {
      return true;
    }
    for (const std::string* suffix : {&options_.spool_outlet_frame, &options_.cable_end_frame})
    {
      if (!suffix->empty() && child.size() >= suffix->size() &&
          child.compare(child.size() - suffix->size(), suffix->size(), *suffix) == 0)
      {
        return true;
      }
    }
    return false;
  };
  std::vector<std::string> frames;
  tf_._getFrameStrings(frames);
  for (const std::string& child : frames)
  {
    if (tf_._getParent(child, ros::Time(0), parent) && parent == options_.world_frame && !own(child))
    {
      return true;
    }
  }
  return false;
}

bool PoseInput::adoptFrame(const std::string& frame)
{
  if (!options_.world_frame_from_pose || !adopted_frame_.empty() || frame.empty() || accepted_ > 0)
  {
    return false;  // only for the first poses: once poses were taken, one in another frame is refused, not adopted
  }
  if (worldFrameInUse() || tf_.canTransform(options_.world_frame, frame, ros::Time(0)))
  {
    return false;  // someone else uses world_frame in tf (or it is already joined to the frame): wait for tf
  }
  geometry_msgs::TransformStamped identity;
  identity.header.frame_id = frame;  // stamp 0: a static transform holds at every time
  identity.child_frame_id = options_.world_frame;
  identity.transform.rotation.w = 1.0;
  if (!tf_.setTransform(identity, "tether_node", true))
  {
    return false;
  }
  if (static_broadcaster_)
  {
    static_broadcaster_->sendTransform(identity);
  }
  adopted_frame_ = frame;
  ROS_INFO(
      "tether_node%s: poses on %s are in '%s', which tf cannot join to world_frame '%s' (nobody else uses it): "
      "taking %s as %s (the identity %s -> %s, published on /tf_static). To use another world, set "
      "world_frame or publish %s -> %s; world_frame_from_pose: false turns this off",
      label_.c_str(), topic_.c_str(), frame.c_str(), options_.world_frame.c_str(), options_.world_frame.c_str(),
      frame.c_str(), frame.c_str(), options_.world_frame.c_str(), options_.world_frame.c_str(), frame.c_str());
  return true;
}

void PoseInput::checkAdoption()
{
  // world_frame was taken as the poses' frame when tf had nothing to join them (a node started before the
  // localisation): if tf now has that frame under world_frame from someone else, the node's identity closes a loop
  // and the cable sits off by their transform. That cannot be undone here (a static transform stays): say so, once.
  if (adopted_frame_.empty() || adoption_conflict_said_)
  {
    return;
  }
  // Up the adopted frame's parents (world_frame -> map -> odom with odom adopted is a loop too), a few at most.
  std::string frame = adopted_frame_, parent;
  bool loop = false;
  for (int up = 0; up < 16 && !loop && tf_._getParent(frame, ros::Time(0), parent); ++up)
  {
    loop = parent == options_.world_frame;
    frame = parent;
  }
  if (!loop)
  {
    return;
  }
  adoption_conflict_said_ = true;
  ROS_ERROR(
      "tether_node%s: tf now joins %s to %s from elsewhere, but world_frame was taken as %s at the first pose, when "
      "tf had no transform for it, and the node publishes the identity %s -> %s: a loop, and the cable is off by that "
      "transform. Restart tether_node once the transform is published (or start it after the localisation), or set "
      "world_frame_from_pose: false",
      label_.c_str(), options_.world_frame.c_str(), adopted_frame_.c_str(), adopted_frame_.c_str(),
      adopted_frame_.c_str(), options_.world_frame.c_str());
}

void PoseInput::refuse(const std::string& why)
{
  ++rejected_;
  warnEach("rejected", why);
}

void PoseInput::warnEach(const char* what, const std::string& why)
{
  const std::string kind = what + warningKind(why);
  const double now = ros::WallTime::now().toSec();
  {
    std::lock_guard<std::mutex> lock(warn_mutex_);
    auto it = std::find_if(warned_.begin(), warned_.end(), [&](const auto& w) { return w.first == kind; });
    if (it != warned_.end() && now - it->second < 1.0)
    {
      return;
    }
    if (it == warned_.end())
    {
      if (warned_.size() >= 64)
      {
        warned_.clear();  // kinds with names in them (frames, types) could be many: forget, and warn again
      }
      warned_.emplace_back(kind, now);
    }
    else
    {
      it->second = now;
    }
  }
  ROS_WARN("rov_pose %s%s: %s", what, label_.c_str(), why.c_str());
}

void PoseInput::noteOnce(const std::string& key, const std::string& text)
{
  {
    std::lock_guard<std::mutex> lock(warn_mutex_);
    if (std::find(noted_.begin(), noted_.end(), key) != noted_.end())
    {
      return;
    }
    noted_.push_back(key);
  }
  ROS_INFO("tether_node%s: %s", label_.c_str(), text.c_str());
}

void PoseInput::receiveAny(const topic_tools::ShapeShifter::ConstPtr& msg, const ros::Time& now)
{
  const std::string& type = msg->getDataType();
  try
  {
    if (type == ros::message_traits::datatype<geometry_msgs::PoseStamped>())
    {
      receive(msg->instantiate<geometry_msgs::PoseStamped>(), now);
      return;
    }
    if (type == ros::message_traits::datatype<nav_msgs::Odometry>())
    {
      const auto odometry = msg->instantiate<nav_msgs::Odometry>();
      auto pose = boost::make_shared<geometry_msgs::PoseStamped>();
      pose->header = odometry->header;  // the pose is in header.frame_id; child_frame_id is the vehicle's
      pose->pose = odometry->pose.pose;
      if (!odometry->child_frame_id.empty() && odometry->child_frame_id != options_.rov_frame)
      {
        noteOnce("child " + odometry->child_frame_id,
                 "Odometry on " + topic_ + " is of '" + odometry->child_frame_id + "', not rov_frame '" +
                     options_.rov_frame +
                     "': its pose is taken as rov_frame's (attachment_offset is in that frame, "
                     "and the node's frames are named rov_frame); set rov_frame to '" +
                     odometry->child_frame_id + "' if that is the vehicle's body frame");
      }
      receive(pose, now);
      return;
    }
  }
  catch (const std::exception& e)  // a message that does not deserialise as its type says
  {
    refuse("a " + type + " on " + topic_ + " could not be read: " + e.what());
    return;
  }
  refuse("a " + type + " on " + topic_ +
         ": expected geometry_msgs/PoseStamped or nav_msgs/Odometry (remap pose_topic to the vehicle's pose)");
}

void PoseInput::refuseFuture(double ahead)
{
  ++future_;
  char text[200];
  std::snprintf(text, sizeof(text),
                "stamped %.3f s ahead of ROS time, beyond max_pose_future %.3f s (is the publisher's clock ahead, "
                "or use_sim_time set without a /clock?)",
                ahead, options_.max_pose_future);
  refuse(text);
}

void PoseInput::receive(const geometry_msgs::PoseStamped::ConstPtr& msg, const ros::Time& now)
{
  const std::string problem = checkPose(msg->pose);
  if (!problem.empty())
  {
    refuse(problem);
    return;
  }
  geometry_msgs::PoseStamped::ConstPtr pose = msg;
  if (msg->header.stamp.isZero())
  {
    auto stamped = boost::make_shared<geometry_msgs::PoseStamped>(*msg);
    stamped->header.stamp = now;  // a zero stamp means "now"
    pose = stamped;
    noteOnce("zero stamp",
             "a pose on " + topic_ + " has a zero stamp: taken as stamped when it arrived (its ROS time)");
  }
  const double ahead = (pose->header.stamp - now).toSec();
  if (ahead > options_.max_pose_future)
  {
    refuseFuture(ahead);
    return;
  }
  const std::string& frame = pose->header.frame_id;
  if (frame.empty())
  {
    noteOnce("empty frame",
             "a pose on " + topic_ + " has an empty frame_id: taken in world_frame '" + options_.world_frame + "'");
  }
  if (frame.empty() || frame == options_.world_frame || !filter_)
  {
    handOver(pose, now);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    waiting_for_tf_.push_back(HandOver{pose, now});
    latest_received_ = std::max(latest_received_, pose->header.stamp);
  }
  filter_->add(pose);
}

void PoseInput::handOver(const geometry_msgs::PoseStamped::ConstPtr& msg, const ros::Time& arrival)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (hand_over_.size() >= kMaxHandOver)
  {
    ++dropped_;
    if (drop_log_.due())
    {
      ROS_WARN("rov_pose dropped%s: %zu poses already wait for the physics (it is stalled)", label_.c_str(),
               hand_over_.size());
    }
    return;
  }
  hand_over_.push_back(HandOver{msg, arrival});
  latest_received_ = std::max(latest_received_, msg->header.stamp);
}

ros::Time PoseInput::stopWaiting(const geometry_msgs::PoseStamped* msg)
{
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = std::find_if(waiting_for_tf_.begin(), waiting_for_tf_.end(),
                               [msg](const HandOver& w) { return w.msg.get() == msg; });
  if (it == waiting_for_tf_.end())
  {
    return ros::Time();
  }
  const ros::Time arrival = it->arrival;
  waiting_for_tf_.erase(it);
  return arrival;
}

void PoseInput::onTransformable(const geometry_msgs::PoseStamped::ConstPtr& msg)
{
  const ros::Time arrival = stopWaiting(msg.get());
  if (!arrival.isZero())
  {
    handOver(msg, arrival);
  }
}

void PoseInput::onFilterFailure(const geometry_msgs::PoseStamped::ConstPtr& msg,
                                tf2_ros::filter_failure_reasons::FilterFailureReason reason)
{
  if (stopWaiting(msg.get()).isZero())
  {
    return;  // already refused as too late
  }
  refuse("no transform " + options_.world_frame + " -> " + msg->header.frame_id + " at " +
         std::to_string(msg->header.stamp.toSec()) + " s (" +
         (reason == tf2_ros::filter_failure_reasons::OutTheBack ? "older than the tf buffer" : "dropped by tf") +
         "); " + noTransformAdvice(msg->header.frame_id));
}

void PoseInput::expireWaiting(const ros::Time& now)
{
  std::vector<HandOver> passed_poses;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const double physics = tether_.time();
    const auto passed = [physics](const HandOver& w) { return w.msg->header.stamp.toSec() < physics; };
    for (auto it = waiting_for_tf_.begin(); it != waiting_for_tf_.end();)
    {
      if (passed(*it))
      {
        passed_poses.push_back(*it);
        it = waiting_for_tf_.erase(it);
      }
      else
      {
        ++it;
      }
    }
  }
  if (passed_poses.empty())
  {
    return;
  }
  // Nobody else uses world_frame: it is taken as the poses' frame, and the poses that waited are taken.
  if (adoptFrame(passed_poses.front().msg->header.frame_id))
  {
    for (const HandOver& pose : passed_poses)
    {
      take(pose, now);
    }
    return;
  }
  rejected_ += passed_poses.size();
  const std::string& late = passed_poses.front().msg->header.frame_id;
  if (expired_log_.due())
  {
    ROS_WARN(
        "rov_pose rejected%s: no transform %s -> %s at its stamp before the physics reached it (the physics runs "
        "interpolation_delay behind ROS time: that is tf's slack); %s",
        label_.c_str(), options_.world_frame.c_str(), late.c_str(), noTransformAdvice(late).c_str());
  }
}

void PoseInput::poll(const ros::Time& now)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    taking_.swap(hand_over_);
  }
  // In stamp order: the MessageFilter releases the poses a new transform makes ready in no set order.
  // Stable: of two with the same stamp, the later to arrive replaces the other (VehicleTrack::add).
  std::stable_sort(taking_.begin(), taking_.end(),
                   [](const HandOver& a, const HandOver& b) { return a.msg->header.stamp < b.msg->header.stamp; });
  for (const HandOver& pose : taking_)
  {
    take(pose, now);
  }
  taking_.clear();
  expireWaiting(now);
  checkAdoption();

  Eigen::Isometry3d pose;
  if (!options_.spool_frame.empty() && lookup(options_.spool_frame, ros::Time(0), spool_transform_log_, &pose))
  {
    const Status status = tether_.setSpoolPosition(pose.translation());
    if (!status.ok)
    {
      // The spool stays where it was; tf gave a position that is not finite or beyond +-1e6 m.
      if (spool_log_.due())
      {
        ROS_WARN("spool_frame %s%s: %s", options_.spool_frame.c_str(), label_.c_str(), status.message.c_str());
      }
    }
  }
  ros::Time stamp;
  if (options_.pose_source == "tf" && lookup(options_.rov_frame, ros::Time(0), vehicle_transform_log_, &pose, &stamp))
  {
    // A static transform (stamp 0) holds at every time: it is taken now, as a pose that does not move.
    if (stamp.isZero())
    {
      stamp = now;
    }
    // Each transform once: tf hands out the latest until a newer one comes, and a refused one would be counted
    // (and said) again every tick.
    if (stamp > last_pose_stamp_ && stamp != tf_handled_)
    {
      tf_handled_ = stamp;
      if ((stamp - now).toSec() > options_.max_pose_future)
      {
        refuseFuture((stamp - now).toSec());
      }
      else
      {
        addVehicle(pose, stamp, now);
      }
    }
  }
}

void PoseInput::take(const HandOver& pose, const ros::Time& now)
{
  const geometry_msgs::PoseStamped& msg = *pose.msg;
  Eigen::Isometry3d vehicle = toIsometry(msg.pose);
  const std::string& frame = msg.header.frame_id;
  if (!frame.empty() && frame != options_.world_frame)
  {
    Eigen::Isometry3d frame_in_world;
    if (!lookup(frame, msg.header.stamp, frame_transform_log_, &frame_in_world))
    {
      ++rejected_;
      return;
    }
    vehicle = frame_in_world * vehicle;
  }
  addVehicle(vehicle, msg.header.stamp, now);
}

bool PoseInput::lookup(const std::string& frame, const ros::Time& time, LogThrottle& log, Eigen::Isometry3d* pose,
                       ros::Time* stamp)
{
  try
  {
    const auto transform = tf_.lookupTransform(options_.world_frame, frame, time);
    *pose = tf2::transformToEigen(transform);
    if (stamp != nullptr)
    {
      *stamp = transform.header.stamp;
    }
    return true;
  }
  catch (const tf2::TransformException& e)
  {
    if (log.due())
    {
      ROS_WARN("tether_node%s: no transform %s -> %s: %s", label_.c_str(), options_.world_frame.c_str(), frame.c_str(),
               e.what());
    }
    return false;
  }
}

bool PoseInput::addVehicle(const Eigen::Isometry3d& vehicle, const ros::Time& stamp, const ros::Time& now)
{
  if (stamp < reset_cut_)
  {
    ++rejected_;
    if (before_reset_log_.due())
    {
      ROS_WARN(
          "rov_pose rejected%s: a pose stamped %.3f s, %.3f s before the reset (it shows the vehicle "
          "before it)",
          label_.c_str(), stamp.toSec(), (reset_cut_ - stamp).toSec());
    }
    return false;
  }
  const Position attachment = vehicle * options_.attachment_offset;
  // The physics went on past the last pose with the vehicle held there (poses that stopped): the core moves the end
  // on from there and then (VehicleTrack::add), and the vehicle drawn and pulled follows it, not the poses' line.
  const double physics = tether_.time();
  const bool held =
      !sink_ && !last_pose_stamp_.isZero() && physics > last_pose_stamp_.toSec() && physics < stamp.toSec();
  Status status = sink_ ? sinkPose(vehicle, attachment, stamp) : tether_.addVehicleSample(stamp.toSec(), attachment);
  if (!status.ok)
  {
    refuse(status.message);
    return false;
  }
  if (!status.message.empty())
  {
    warnEach("taken", status.message);  // taken, with something the core did about it (a duplicate stamp)
  }
  // This pose and the one before each came later after the stamp of their predecessor than the physics waits for a
  // pose (stale_pose_timeout behind ROS time), and the physics had passed the last stamp: the end held there, and
  // now catches up faster than the vehicle moved. Twice in a row: poses that come this late as a rule (latency
  // plus period), not one outage, after which the end goes on from where it held as it should (docs/node.md).
  const double after_last = last_pose_stamp_.isZero() ? 0.0 : (now - last_pose_stamp_).toSec();
  const bool over = !last_pose_stamp_.isZero() && after_last > options_.stale_pose_timeout;
  if (!sink_ && over && last_gap_over_ && physics > last_pose_stamp_.toSec())
  {
    ++late_;
    char text[400];
    std::snprintf(text, sizeof(text),
                  "a pose stamped %.3f s came %.3f s after the stamp of the one before (%.3f s), as the one before "
                  "did: the physics, which waits for poses at most stale_pose_timeout behind ROS time (%.3f s here), "
                  "had passed that one by %.3f s and held the cable end there, which now catches up faster than the "
                  "vehicle moved. Poses this late: raise stale_pose_timeout above %.3f s",
                  stamp.toSec(), after_last, last_pose_stamp_.toSec(), options_.stale_pose_timeout,
                  physics - last_pose_stamp_.toSec(), after_last);
    warnEach("taken late", text);
  }
  last_gap_over_ = over;
  if (!last_pose_stamp_.isZero())
  {
    gaps_[gap_count_ % kGaps] = after_last;
    ++gap_count_;
  }
  ++accepted_;
  if (held)
  {
    history_.add(physics, last_vehicle_);
  }
  history_.add(stamp.toSec(), vehicle);
  last_vehicle_ = vehicle;
  last_pose_time_ = now;
  last_pose_stamp_ = stamp;
  return true;
}

Status PoseInput::sinkPose(const Eigen::Isometry3d& vehicle, const Position& attachment, const ros::Time& stamp)
{
  // The core's rule for the order of samples, kept here for the sink, which takes setpoints as they come.
  const Status order = last_pose_stamp_.isZero()
                           ? Status::success()
                           : VehicleTrack::order(stamp.toSec(), last_pose_stamp_.toSec(),
                                                 (attachment - last_vehicle_ * options_.attachment_offset).norm());
  if (!order.ok)
  {
    return order;
  }
  Status status = sink_(stamp.toSec(), vehicle);
  if (status.ok && !order.message.empty())
  {
    status.message = order.message + (status.message.empty() ? "" : "; " + status.message);
  }
  return status;
}

void PoseInput::reset(const ros::Time& now)
{
  last_pose_stamp_ = ros::Time();
  gap_count_ = 0;
  history_.clear();
  reset_cut_ = ros::Time();  // a clock gone back starts a new time line; ~reset sets its own cut after this
  tf_handled_ = ros::Time();
  last_gap_over_ = false;
  std::size_t refused = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto later = [&now](const HandOver& pose) { return pose.arrival > now; };
    for (auto* list : {&hand_over_, &waiting_for_tf_})
    {
      const auto keep = std::remove_if(list->begin(), list->end(), later);
      refused += static_cast<std::size_t>(list->end() - keep);
      list->erase(keep, list->end());
    }
    latest_received_ = ros::Time();  // of the poses kept, which the tether will still take
    for (const auto* list : {&hand_over_, &waiting_for_tf_})
    {
      for (const HandOver& pose : *list)
      {
        latest_received_ = std::max(latest_received_, pose.msg->header.stamp);
      }
    }
  }
  if (refused > 0)
  {
    rejected_ += refused;
    if (clock_back_log_.due())
    {
      ROS_WARN("rov_pose rejected%s: %zu poses that arrived before the clock went back", label_.c_str(), refused);
    }
  }
}

ros::Time PoseInput::resetCut(const ros::Time& now) const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return latest_received_ < now ? now : latest_received_ + ros::Duration(0, 1);
}

ros::Time PoseInput::earliestArrival() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  ros::Time earliest;
  for (const HandOver& pose : hand_over_)
  {
    earliest = earliest.isZero() || pose.arrival < earliest ? pose.arrival : earliest;
  }
  return earliest;
}

double PoseInput::latestStamp() const
{
  return last_pose_stamp_.isZero() ? std::numeric_limits<double>::quiet_NaN() : last_pose_stamp_.toSec();
}

double PoseInput::neededDelay() const
{
  const std::size_t n = std::min(gap_count_, kGaps);
  return n == 0 ? 0.0 : *std::max_element(gaps_.begin(), gaps_.begin() + static_cast<std::ptrdiff_t>(n));
}

}  // namespace rov_tether::ros_layer
