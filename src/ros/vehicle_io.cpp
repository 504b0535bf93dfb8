#include "rov_tether/ros/vehicle_io.hpp"

#include <ros/console.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace rov_tether::ros_layer
{
namespace
{

geometry_msgs::Quaternion toQuaternion(const Eigen::Quaterniond& q)
{
  geometry_msgs::Quaternion out;
  out.x = q.x();
  out.y = q.y();
  out.z = q.z();
  out.w = q.w();
  return out;
}

Wrench toWrenchVector(const geometry_msgs::Wrench& w)
{
  Wrench out;
  out << w.force.x, w.force.y, w.force.z, w.torque.x, w.torque.y, w.torque.z;
  return out;
}

}  // namespace

nav_msgs::Odometry toOdometry(const VehicleBody& body, const ros::Time& stamp, const std::string& world_frame,
                              const std::string& vehicle_frame)
{
  nav_msgs::Odometry odom;
  odom.header.stamp = stamp;
  odom.header.frame_id = world_frame;
  odom.child_frame_id = vehicle_frame;
  odom.pose.pose.position.x = body.position().x();
  odom.pose.pose.position.y = body.position().y();
  odom.pose.pose.position.z = body.position().z();
  odom.pose.pose.orientation = toQuaternion(body.attitude());
  // REP 105: the twist is in child_frame_id, the body frame; VehicleBody's nu is the body velocity already.
  const Twist& nu = body.velocity();
  odom.twist.twist.linear.x = nu[0];
  odom.twist.twist.linear.y = nu[1];
  odom.twist.twist.linear.z = nu[2];
  odom.twist.twist.angular.x = nu[3];
  odom.twist.twist.angular.y = nu[4];
  odom.twist.twist.angular.z = nu[5];
  return odom;
}

geometry_msgs::TransformStamped toVehicleTransform(const VehicleBody& body, const ros::Time& stamp,
                                                   const std::string& world_frame, const std::string& vehicle_frame)
{
  geometry_msgs::TransformStamped transform;
  transform.header.stamp = stamp;
  transform.header.frame_id = world_frame;
  transform.child_frame_id = vehicle_frame;
  transform.transform.translation.x = body.position().x();
  transform.transform.translation.y = body.position().y();
  transform.transform.translation.z = body.position().z();
  transform.transform.rotation = toQuaternion(body.attitude());
  return transform;
}

void toVehicleMarker(const Eigen::Isometry3d& pose, const Eigen::Vector3d& size, bool present, const ros::Time& stamp,
                     const std::string& frame_id, visualization_msgs::Marker* marker)
{
  marker->header.stamp = stamp;
  marker->header.frame_id = frame_id;
  marker->ns = "vehicle";
  marker->id = 0;
  marker->type = visualization_msgs::Marker::CUBE;
  marker->action = present ? visualization_msgs::Marker::ADD : visualization_msgs::Marker::DELETE;
  const Eigen::Vector3d position = pose.translation();
  const Eigen::Quaterniond attitude(pose.rotation());
  marker->pose.position.x = position.x();
  marker->pose.position.y = position.y();
  marker->pose.position.z = position.z();
  marker->pose.orientation = toQuaternion(attitude);
  marker->scale.x = size.x();
  marker->scale.y = size.y();
  marker->scale.z = size.z();
  marker->color.r = 0.95f;  // a yellow hull, half transparent: the attachment point and the cable's end show
  marker->color.g = 0.8f;
  marker->color.b = 0.2f;
  marker->color.a = 0.5f;
}

Eigen::Isometry3d startPose(const Eigen::Vector4d& xyz_yaw)
{
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = xyz_yaw.head<3>();
  pose.linear() = Eigen::AngleAxisd(xyz_yaw[3], Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return pose;
}

std::string WrenchCommand::refuse(const std::string& why)
{
  ++refused_;
  return why;
}

std::string WrenchCommand::accept(const geometry_msgs::Wrench& command, const ros::Time& arrival)
{
  const Wrench wrench = toWrenchVector(command);
  if (!wrench.allFinite())
  {
    ++refused_;
    return "a non-finite command (NaN or inf): refused, the last command stays";
  }
  command_ = wrench;
  arrival_ = arrival;
  stale_said_ = false;
  ++accepted_;
  return "";
}

double WrenchCommand::age(const ros::Time& now) const
{
  return arrival_.isZero() ? std::numeric_limits<double>::infinity() : (now - arrival_).toSec();
}

bool WrenchCommand::fresh(const ros::Time& now) const { return age(now) <= timeout_; }

Wrench WrenchCommand::thrustAt(const ros::Time& now, bool* went_stale)
{
  *went_stale = false;
  if (fresh(now))
  {
    return command_;
  }
  if (!arrival_.isZero() && !stale_said_)
  {
    stale_said_ = true;
    ++stale_periods_;
    *went_stale = true;
  }
  return Wrench::Zero();
}

VehicleIo::VehicleIo(const TetherSetup& setup, Tether& tether, const std::string& label)
    : options_(setup.options),
      vehicle_params_(setup.vehicle),
      tether_(tether),
      label_(label),
      command_(setup.options.cmd_wrench_timeout),
      last_control_time_(std::nan(""))
{
  // The gains were checked against this vehicle when the file was read (readControllerGains); the built-in
  // defaults are the BlueROV2 Heavy's design. Refused, the node cannot follow setpoints: it says so at start.
  const Status configured = controller_.configure(vehicle_params_, setup.gains);
  if (!configured)
  {
    throw std::runtime_error("tether_node" + label +
                             ": the vehicle controller refused its gains: " + configured.message);
  }
}

void VehicleIo::restarted(const ros::Time& clock)
{
  start_due_ = true;
  {
    std::lock_guard<std::mutex> lock(command_mutex_);
    command_.forgetArrivedAfter(clock);  // the vehicle starts again at rest, with no command of the old time
  }
  setpoints_.clear();
  controller_.reset();
  last_control_time_ = std::nan("");
}

void VehicleIo::advertise(const ros::NodeHandle& private_nh, ros::CallbackQueueInterface* input_queue)
{
  ros::NodeHandle command_nh(private_nh);
  command_nh.setCallbackQueue(input_queue);
  command_sub_ = command_nh.subscribe<geometry_msgs::WrenchStamped>(
      "cmd_wrench", 10, [this](const geometry_msgs::WrenchStamped::ConstPtr& msg) { receive(*msg, ros::Time::now()); });
  ros::NodeHandle out(private_nh);
  odom_pub_ = out.advertise<nav_msgs::Odometry>("odom", 10);
  tf_pub_ = out.advertise<tf2_msgs::TFMessage>("/tf", 10);
}

void VehicleIo::receive(const geometry_msgs::WrenchStamped& msg, const ros::Time& now)
{
  std::string why;
  bool log = false;
  {
    std::lock_guard<std::mutex> lock(command_mutex_);
    if (!msg.header.frame_id.empty() && msg.header.frame_id != options_.rov_frame)
    {
      // The thrust is the body's: a wrench in another frame (the world's) would push the wrong way.
      why = command_.refuse("in frame '" + msg.header.frame_id + "': expected the body frame rov_frame '" +
                            options_.rov_frame + "' (or none); refused, the last command stays");
    }
    else
    {
      why = command_.accept(msg.wrench, now);
    }
    // A command in another frame has its own throttle: it hides no other refusal.
    log = !why.empty() && (why.rfind("in frame", 0) == 0 ? frame_log_ : command_log_).due(now);
  }
  if (log)
  {
    ROS_WARN("tether_node%s: ~cmd_wrench: %s", label_.c_str(), why.c_str());
  }
}

bool VehicleIo::start(const Eigen::Isometry3d& pose)
{
  VehicleBody body;
  Status status = body.setParams(vehicle_params_);
  status = status ? body.setState(pose.translation(), Eigen::Quaterniond(pose.rotation()), Twist::Zero()) : status;
  status = status ? tether_.attachVehicleBody(body, options_.attachment_offset) : status;
  if (!status)
  {
    if (start_log_.due())
    {
      ROS_ERROR("tether_node%s: the dynamic vehicle cannot start at [%.3f, %.3f, %.3f]: %s", label_.c_str(),
                pose.translation().x(), pose.translation().y(), pose.translation().z(), status.message.c_str());
    }
    return false;
  }
  start_due_ = false;
  ROS_INFO("tether_node%s: dynamic vehicle started at [%.3f, %.3f, %.3f] in %s", label_.c_str(), pose.translation().x(),
           pose.translation().y(), pose.translation().z(), options_.world_frame.c_str());
  // Out of reach, said at each start (the pose differs); the vehicle's other water said at the first start only
  // (the two densities are at-start parameters: the same at every start).
  std::string said = status.message;
  const std::string water = waterMismatch(vehicle_params_, tether_.params().water_density);
  const std::size_t at = water.empty() || water != water_said_ ? std::string::npos : said.rfind(water);
  if (at != std::string::npos)
  {
    said.erase(at >= 2 ? at - 2 : at);  // with the "; " that joins it to the reach's warning
  }
  water_said_ = water.empty() ? water_said_ : water;
  if (!said.empty())
  {
    ROS_WARN("tether_node%s: dynamic vehicle: %s", label_.c_str(), said.c_str());
  }
  return true;
}

Status VehicleIo::takePose(double t, const Eigen::Isometry3d& vehicle)
{
  if (start_due_ && !options_.has_vehicle_start)
  {
    return start(vehicle) ? Status::success() : Status::error("the dynamic vehicle could not start at this pose");
  }
  if (tether_.vehicleDynamic())
  {
    setpoints_.add(t, vehicle);  // stamps never decrease: PoseInput::sinkPose refuses older ones
    ++setpoint_count_;
  }
  return Status::success();
}

void VehicleIo::noteSaturation()
{
  // The last step's thrust as applied: an axis commanded beyond thrust_limit was held at it (never silently).
  const ThrustUsed* used = tether_.vehicleThrustUsed();
  if (used == nullptr || !used->saturated())
  {
    return;
  }
  {
    std::lock_guard<std::mutex> lock(command_mutex_);
    ++saturated_ticks_;
  }
  const auto axes = [bits = used->saturated_axes]  // named only when the warning is printed: no work a tick
  {
    static const char* const kAxes[6] = {"surge", "sway", "heave", "roll", "pitch", "yaw"};
    std::string names;
    for (int i = 0; i < 6; ++i)
    {
      names += (bits >> i) & 1u ? std::string(names.empty() ? "" : ", ") + kAxes[i] : "";
    }
    return names;
  };
  if (saturation_log_.due())
  {
    ROS_WARN("tether_node%s: the thrust from %s is held at the vehicle's thrust_limit on %s", label_.c_str(), driver_,
             axes().c_str());
  }
}

Wrench VehicleIo::controlledThrust()
{
  const double now = tether_.time();
  const double dt = std::isnan(last_control_time_) ? tether_.params().time_step : now - last_control_time_;
  if (!(dt > 0.0))
  {
    return thrust_;  // the physics did not move since the last update (a tick that took no step)
  }
  const Eigen::Isometry3d target = setpoints_.at(now);
  VehicleSetpoint setpoint;
  setpoint.position = target.translation();
  setpoint.yaw = VehicleController::yawOf(Eigen::Quaterniond(target.rotation()));
  ControllerOutput output;
  const Status status = controller_.update(dt, setpoint, *tether_.vehicleBody(), &output);
  if (!status)
  {
    if (controller_log_.due())
    {
      ROS_WARN("tether_node%s: vehicle controller: %s (zero thrust)", label_.c_str(), status.message.c_str());
    }
    return Wrench::Zero();
  }
  last_control_time_ = now;
  if (output.level_step_too_long && level_step_log_.due())
  {
    ROS_WARN(
        "tether_node%s: vehicle controller: updated every %.3f s, longer than the %.3f s its level hold settles "
        "at (it swings roll and pitch up): raise physics_rate or lower the vehicle file's level_bandwidth",
        label_.c_str(), dt, controller_.levelStepLimit());
  }
  return output.thrust;
}

void VehicleIo::beforeAdvance(const ros::Time& now)
{
  if (start_due_ && options_.has_vehicle_start)
  {
    start(startPose(options_.vehicle_start));
  }
  if (!tether_.vehicleDynamic())
  {
    return;
  }
  noteSaturation();
  bool went_stale = false;
  bool fresh = false;
  double age = 0.0;
  Wrench commanded;
  {
    std::lock_guard<std::mutex> lock(command_mutex_);
    commanded = command_.thrustAt(now, &went_stale);
    fresh = command_.fresh(now);
    age = command_.age(now);
  }
  const bool controlled = !fresh && !setpoints_.empty();
  if (went_stale)
  {
    ROS_WARN("tether_node%s: ~cmd_wrench is stale (the last came %.3f s ago, cmd_wrench_timeout %.3f s): %s",
             label_.c_str(), age, options_.cmd_wrench_timeout,
             controlled ? "the controller follows the poses again" : "zero thrust until the next one");
  }
  if (fresh)
  {
    thrust_ = commanded;  // a fresh command wins over the setpoints
    last_control_time_ = std::nan("");
    driver_ = "cmd_wrench";
  }
  else if (controlled)
  {
    if (std::isnan(last_control_time_))
    {
      controller_.reset();  // it takes over: its integrals start from zero
    }
    thrust_ = controlledThrust();
    driver_ = "controller";
  }
  else
  {
    thrust_ = Wrench::Zero();
    driver_ = "none";
  }
  const Status status = tether_.setVehicleThrust(thrust_);  // finite: refused on arrival otherwise
  if (!status)
  {
    if (thrust_log_.due())
    {
      ROS_WARN("tether_node%s: thrust refused: %s", label_.c_str(), status.message.c_str());
    }
  }
}

void VehicleIo::publishState()
{
  const VehicleBody* body = tether_.vehicleBody();
  if (body == nullptr)
  {
    return;
  }
  const ros::Time stamp(std::max(tether_.time(), 0.0));  // of the physics' time, as ~state
  if (odom_pub_.getNumSubscribers() > 0)
  {
    odom_pub_.publish(toOdometry(*body, stamp, options_.world_frame, options_.rov_frame));
  }
  transforms_.transforms.resize(1);
  transforms_.transforms[0] = toVehicleTransform(*body, stamp, options_.world_frame, options_.rov_frame);
  tf_pub_.publish(transforms_);
}

Eigen::Isometry3d VehicleIo::pose() const
{
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  if (const VehicleBody* body = tether_.vehicleBody())
  {
    pose.translation() = body->position();
    pose.linear() = body->attitude().toRotationMatrix();
  }
  return pose;
}

void VehicleIo::diagnose(diagnostic_updater::DiagnosticStatusWrapper& status)
{
  std::uint64_t accepted = 0, refused = 0, stale = 0, saturated = 0;
  bool fresh = false;
  {
    std::lock_guard<std::mutex> lock(command_mutex_);
    accepted = command_.accepted();
    refused = command_.refused();
    stale = command_.stalePeriods();
    fresh = command_.fresh(ros::Time::now());
    saturated = saturated_ticks_;
  }
  const bool held_since = saturated > saturated_reported_;  // since the last report
  saturated_reported_ = saturated;
  status.add("vehicle model", "dynamic");
  status.add("cmd_wrench taken", accepted);
  status.add("cmd_wrench refused", refused);
  status.add("cmd_wrench stale periods", stale);
  status.add("cmd_wrench fresh", fresh ? "yes" : "no");
  status.add("setpoints taken (poses after the start)", setpoint_count_);
  status.add("thrust from", driver_);
  status.add("ticks with the thrust held at thrust_limit", saturated);
  if (held_since)
  {
    status.mergeSummary(diagnostic_msgs::DiagnosticStatus::WARN, "thrust held at thrust_limit (see the log)");
  }
  if (const VehicleBody* body = tether_.vehicleBody())
  {
    status.addf("vehicle speed [m/s]", "%.4f", body->velocity().head<3>().norm());
  }
  else
  {
    status.mergeSummary(diagnostic_msgs::DiagnosticStatus::WARN,
                        options_.has_vehicle_start ? "dynamic vehicle not started (see the log)"
                                                   : "dynamic vehicle waits for its first pose (or set vehicle_start)");
  }
}

}  // namespace rov_tether::ros_layer
