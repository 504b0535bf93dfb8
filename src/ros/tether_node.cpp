#include "rov_tether/ros/tether_node.hpp"

#include <tf2_eigen/tf2_eigen.h>

#include <cmath>
#include <stdexcept>

namespace rov_tether::ros_layer
{
namespace
{

/// Exponential smoothing of diagnostics figures.
double smooth(double previous, double sample) { return previous <= 0.0 ? sample : 0.95 * previous + 0.05 * sample; }

/// Forward time jumps larger than this are not integrated step by step but reset the tether [s].
constexpr double kMaxForwardJump = 5.0;
/// Diagnostics stay ERROR for this long after a simulation failure [s].
constexpr double kFailureReportTime = 5.0;

}  // namespace

TetherNode::TetherNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh, const XmlRpc::XmlRpcValue& shared,
                       const std::string& name)
    : nh_(nh), private_nh_(private_nh), name_(name)
{
  XmlRpc::XmlRpcValue dict;
  if (!private_nh_.getParam(private_nh_.getNamespace(), dict))
  {
    dict = XmlRpc::XmlRpcValue();
  }
  TetherParams params;
  std::string error;
  for (const XmlRpc::XmlRpcValue* source :
       {&shared, static_cast<const XmlRpc::XmlRpcValue*>(&dict)})  // shared first, this tether's own on top
  {
    if (error.empty() && source->valid())
    {
      error = loadTetherParams(*source, &params);
      error = error.empty() ? loadNodeOptions(*source, &options_) : error;
    }
  }
  if (!error.empty())
  {
    throw std::runtime_error("invalid parameters in " + private_nh_.getNamespace() + ": " + error);
  }
  const std::string unknown = dict.valid() ? unknownParameters(dict) : "";
  if (!unknown.empty())
  {
    ROS_WARN("tether_node: ignoring unknown parameters in %s (typos?): %s", private_nh_.getNamespace().c_str(),
             unknown.c_str());
  }
  configured_iterations_ = params.iterations;
  marker_rate_ = options_.marker_rate;
  sim_ = std::make_unique<Tether>(params, options_.spool_position);
  warnAboutStability();

  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(tf_buffer_);
  state_pub_ = private_nh_.advertise<TetherState>("state", 10);
  wrench_pub_ = private_nh_.advertise<geometry_msgs::WrenchStamped>("wrench", 10);
  marker_pub_ = private_nh_.advertise<visualization_msgs::MarkerArray>("markers", 2);
  get_tension_srv_ = private_nh_.advertiseService("get_tension", &TetherNode::onGetTension, this);
  set_winch_srv_ = private_nh_.advertiseService("set_winch", &TetherNode::onSetWinch, this);
  reset_srv_ = private_nh_.advertiseService("reset", &TetherNode::onReset, this);
  diagnostics_ = std::make_unique<diagnostic_updater::Updater>(nh_, private_nh_);
  diagnostics_->setHardwareID(name_.empty() ? "rov_tether" : "rov_tether/" + name_);
  diagnostics_->add(name_.empty() ? "tether" : "tether " + name_, this, &TetherNode::diagnose);
  reconfigure_server_ = std::make_unique<dynamic_reconfigure::Server<TetherConfig>>(reconfigure_mutex_, private_nh_);
  reconfigure_server_->updateConfig(paramsToConfig(params));
  reconfigure_server_->setCallback([this](TetherConfig& config, uint32_t level) { onReconfigure(config, level); });
  if (options_.pose_source == "topic")
  {
    // Deep enough for poses at 1 kHz between two physics ticks.
    pose_sub_ = nh_.subscribe(options_.pose_topic, 100, &TetherNode::onPose, this);
  }
  timer_ = nh_.createTimer(ros::Duration(1.0 / options_.physics_rate), &TetherNode::onTimer, this);
  ROS_INFO("tether_node: %.1f m cable in %zu segments, %s solver, pose from %s, physics at %.0f Hz",
           params.cable_length, params.segmentCount(), toString(params.solver).c_str(),
           options_.pose_source == "topic" ? pose_sub_.getTopic().c_str()
                                           : ("tf " + options_.world_frame + " -> " + options_.rov_frame).c_str(),
           options_.physics_rate);
}

void TetherNode::onPose(const geometry_msgs::PoseStamped::ConstPtr& msg)
{
  const auto& p = msg->pose.position;
  const auto& q = msg->pose.orientation;
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(q.x) || !std::isfinite(q.y) ||
      !std::isfinite(q.z) || !std::isfinite(q.w))
  {
    ++rejected_poses_;
    ROS_WARN_THROTTLE(1.0, "rov_pose rejected: position or orientation is not finite");
    return;
  }
  const double norm = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  if (std::abs(norm - 1.0) > 1e-3)
  {
    ++rejected_poses_;
    ROS_WARN_THROTTLE(1.0, "rov_pose rejected: quaternion is not normalised (|q| = %.6f)", norm);
    return;
  }
  const ros::Time now = ros::Time::now();
  if (started_ && now < last_time_)
  {
    resetTether(now, "time jumped backwards by " + std::to_string((last_time_ - now).toSec()) + " s");
  }
  const ros::Time stamp = msg->header.stamp.isZero() ? now : msg->header.stamp;
  Eigen::Isometry3d pose = Eigen::Translation3d(p.x, p.y, p.z) * Eigen::Quaterniond(q.w, q.x, q.y, q.z);
  const std::string& frame = msg->header.frame_id;
  if (!frame.empty() && frame != options_.world_frame)
  {
    Eigen::Isometry3d frame_in_world;
    if (!lookup(frame, stamp, &frame_in_world))
    {
      ++rejected_poses_;
      return;
    }
    pose = frame_in_world * pose;
  }
  addVehiclePose(pose, stamp);
}

bool TetherNode::lookup(const std::string& frame, const ros::Time& time, Eigen::Isometry3d* pose, ros::Time* stamp)
{
  try
  {
    const auto transform = tf_buffer_.lookupTransform(options_.world_frame, frame, time);
    *pose = tf2::transformToEigen(transform);
    if (stamp != nullptr)
    {
      *stamp = transform.header.stamp;
    }
    return true;
  }
  catch (const tf2::TransformException& e)
  {
    ROS_WARN_THROTTLE(1.0, "tether_node: no transform %s -> %s: %s", options_.world_frame.c_str(), frame.c_str(),
                      e.what());
    return false;
  }
}

void TetherNode::addVehiclePose(const Eigen::Isometry3d& vehicle, const ros::Time& stamp)
{
  const Position attachment = vehicle * options_.attachment_offset;
  const Status status = sim_->addVehicleSample(stamp.toSec(), attachment);
  if (!status.ok)
  {
    ++rejected_poses_;
    ROS_WARN_THROTTLE(1.0, "rov_pose rejected: %s", status.message.c_str());
    return;
  }
  last_vehicle_ = vehicle;
  last_pose_time_ = ros::Time::now();
  last_pose_stamp_ = stamp;
}

void TetherNode::resetTether(const ros::Time& now, const std::string& why)
{
  ROS_WARN("tether_node: %s: resetting the tether to %.2f m", why.c_str(), sim_->params().initial_deployed_length);
  sim_->reset(alignedPhysicsTime(now));
  next_state_physics_ = 0.0;
  ++resets_;
  last_time_ = now;
  last_pose_stamp_ = ros::Time();
  next_marker_time_ = ros::Time();
  last_state_physics_ = 0.0;
  last_deployed_ = sim_->deployedLength();
}

void TetherNode::applyPendingParams()
{
  std::optional<TetherParams> pending;
  {
    std::lock_guard<std::mutex> lock(pending_mutex_);
    pending.swap(pending_params_);
  }
  if (!pending)
  {
    return;
  }
  const Status status = sim_->setParams(*pending);
  if (!status.ok)
  {
    ROS_ERROR("tether_node: parameters refused: %s", status.message.c_str());
  }
  else
  {
    configured_iterations_ = pending->iterations;  // a new configuration ends any overload reduction
    degraded_.clear();
    if (!status.message.empty())
    {
      ROS_INFO("tether_node: %s", status.message.c_str());
    }
  }
  if (status.ok)
  {
    warnAboutStability();
  }
}

void TetherNode::warnAboutStability() const
{
  const TetherParams& p = sim_->params();
  if (p.solver == SolverType::kLumpedMass && p.subStep() > p.criticalStep())
  {
    ROS_WARN(
        "tether_node: lumped_mass sub-step %.3g s exceeds its critical step %.3g s (segment_length / "
        "sqrt(EA / mu)): it will diverge (detected and reported); set substeps >= %.0f or iterations: auto",
        p.subStep(), p.criticalStep(), std::ceil(p.time_step / p.criticalStep()));
  }
}

void TetherNode::onTimer(const ros::TimerEvent& /*event*/)
{
  const ros::Time now = ros::Time::now();
  if (now.isZero())
  {
    return;  // simulated time has not started
  }
  if (!started_)
  {
    started_ = true;
    sim_->reset(alignedPhysicsTime(now));
    next_state_physics_ = 0.0;
    last_time_ = now;
    last_deployed_ = sim_->deployedLength();
  }
  else if (now < last_time_)
  {
    resetTether(now, "time jumped backwards by " + std::to_string((last_time_ - now).toSec()) + " s");
  }
  else if ((now - last_time_).toSec() > kMaxForwardJump)
  {
    resetTether(now, "time jumped forwards by " + std::to_string((now - last_time_).toSec()) + " s");
  }
  applyPendingParams();

  Eigen::Isometry3d pose;
  if (!options_.spool_frame.empty() && lookup(options_.spool_frame, ros::Time(0), &pose))
  {
    sim_->setSpoolPosition(pose.translation());
  }
  ros::Time stamp;
  if (options_.pose_source == "tf" && lookup(options_.rov_frame, ros::Time(0), &pose, &stamp) &&
      stamp > last_pose_stamp_)
  {
    addVehiclePose(pose, stamp);
  }

  // Poses arrive late: running the physics behind ROS time lets them bracket it. ~state is published
  // on a grid of physics time (multiples of 1 / state_rate), so a replay gives the same series.
  const double target = now.toSec() - options_.interpolation_delay;
  const double period = 1.0 / options_.state_rate;
  if (next_state_physics_ <= 0.0 || next_state_physics_ < target - 1.0)
  {
    next_state_physics_ = std::ceil(std::max(sim_->time(), target - 1.0) / period) * period;
  }
  if (target - sim_->time() > options_.max_lag)
  {
    // Too far behind to catch up: jump ahead with the cable held at rest, and say so.
    const double behind = target - sim_->time();
    sim_->skipTo(std::floor(target / sim_->params().time_step) * sim_->params().time_step);
    next_state_physics_ = std::ceil(sim_->time() / period) * period;  // the state grid resumes from there
    ++skips_;
    last_skip_time_ = now;
    ROS_ERROR_THROTTLE(1.0,
                       "tether_node%s: the physics fell %.2f s behind real time (more than max_lag = %.2f s): "
                       "skipped ahead with the cable held",
                       name_.empty() ? "" : (" " + name_).c_str(), behind, options_.max_lag);
  }
  const ros::WallTime wall_start = ros::WallTime::now();
  std::size_t steps = 0;
  for (;;)
  {
    const bool state_due = next_state_physics_ <= target;
    std::size_t taken = 0;
    sim_->advanceTo(state_due ? next_state_physics_ : target, &taken);
    steps += taken;
    if (!state_due)
    {
      break;
    }
    publishState();
    next_state_physics_ += period;
  }
  const ros::WallTime wall_end = ros::WallTime::now();
  const double wall = (wall_end - wall_start).toSec();
  manageLoad(wall, wall_end);
  if (steps > 0 && wall > 0.0)
  {
    step_seconds_ = smooth(step_seconds_, wall / static_cast<double>(steps));
    real_time_factor_ = smooth(real_time_factor_, static_cast<double>(steps) * sim_->params().time_step / wall);
  }
  if (sim_->recoveryCount() > reported_failures_)
  {
    reported_failures_ = sim_->recoveryCount();
    last_failure_time_ = now;
    ROS_ERROR_THROTTLE(1.0, "tether_node: simulation failure (%llu so far): %s",
                       static_cast<unsigned long long>(reported_failures_), sim_->lastFailure().c_str());
  }
  if (sim_->jumpCount() > reported_jumps_)
  {
    reported_jumps_ = sim_->jumpCount();
    ROS_WARN_THROTTLE(1.0, "tether_node: the vehicle pose jumped more than max_vehicle_jump = %.2f m: cable re-laid",
                      sim_->params().max_vehicle_jump);
  }
  last_time_ = now;
  publishMarkers(now);
  diagnostics_->update();
}

void TetherNode::manageLoad(double physics_wall, const ros::WallTime& wall_now)
{
  if (load_window_start_.isZero())
  {
    load_window_start_ = wall_now;
  }
  load_window_physics_ += physics_wall;
  const double window = (wall_now - load_window_start_).toSec();
  if (window < 1.0)
  {
    return;
  }
  physics_load_ = load_window_physics_ / window;
  load_window_start_ = wall_now;
  load_window_physics_ = 0.0;
  const std::string label = name_.empty() ? "" : " " + name_;
  if (physics_load_ > options_.cpu_budget)
  {
    if (options_.overload_policy == "reduce_iterations" && sim_->params().iterations > options_.min_iterations)
    {
      TetherParams params = sim_->params();
      params.iterations = std::max(options_.min_iterations, params.iterations * 3 / 4);
      sim_->setParams(params);
      degraded_ = "iterations " + std::to_string(params.iterations) + " of " + std::to_string(configured_iterations_);
    }
    else if (options_.overload_policy == "reduce_markers" && marker_rate_ > 1.0)
    {
      marker_rate_ = std::max(1.0, marker_rate_ / 2.0);
      degraded_ = "markers at " + std::to_string(marker_rate_).substr(0, 4) + " Hz";
    }
    ROS_WARN_THROTTLE(
        5.0, "tether_node%s: physics uses %.0f%% of the wall time (cpu_budget %.0f%%): %s", label.c_str(),
        100 * physics_load_, 100 * options_.cpu_budget,
        degraded_.empty() ? "nothing left to give up (overload_policy)" : ("degraded to " + degraded_).c_str());
  }
  else if (physics_load_ < 0.5 * options_.cpu_budget && !degraded_.empty())
  {
    // Load is back down: undo one notch.
    if (options_.overload_policy == "reduce_iterations" && sim_->params().iterations < configured_iterations_)
    {
      TetherParams params = sim_->params();
      params.iterations = std::min(configured_iterations_, params.iterations * 4 / 3 + 1);
      sim_->setParams(params);
      degraded_ = params.iterations < configured_iterations_ ? "iterations " + std::to_string(params.iterations) +
                                                                   " of " + std::to_string(configured_iterations_)
                                                             : "";
    }
    else if (options_.overload_policy == "reduce_markers" && marker_rate_ < options_.marker_rate)
    {
      marker_rate_ = std::min(options_.marker_rate, marker_rate_ * 2.0);
      degraded_ =
          marker_rate_ < options_.marker_rate ? "markers at " + std::to_string(marker_rate_).substr(0, 4) + " Hz" : "";
    }
    if (degraded_.empty())
    {
      ROS_INFO("tether_node%s: load back to %.0f%%, degradation undone", label.c_str(), 100 * physics_load_);
    }
  }
}

double TetherNode::alignedPhysicsTime(const ros::Time& now) const
{
  const double dt = sim_->params().time_step;
  return std::floor((now.toSec() - options_.interpolation_delay) / dt) * dt;
}

void TetherNode::publishState()
{
  sim_->computeSegmentTensions(tensions_);
  const double physics_time = sim_->time();
  const double elapsed = physics_time - last_state_physics_;
  const double deployed = sim_->deployedLength();
  winch_speed_ = last_state_physics_ > 0.0 && elapsed > 0.0 ? (deployed - last_deployed_) / elapsed : 0.0;
  last_deployed_ = deployed;
  last_state_physics_ = physics_time;
  const ros::Time stamp(std::max(physics_time, 0.0));  // the state is of the physics' time
  toStateMessage(*sim_, tensions_, stamp, options_.world_frame, winch_speed_, resets_, &state_msg_);
  state_pub_.publish(state_msg_);
  wrench_pub_.publish(toWrench(*sim_, last_vehicle_.translation(), stamp, options_.world_frame));
}

void TetherNode::publishMarkers(const ros::Time& now)
{
  const ros::Duration period(1.0 / marker_rate_);
  if (marker_pub_.getNumSubscribers() == 0)
  {
    return;  // markers cost nothing when nobody looks
  }
  if (!next_marker_time_.isZero() && now < next_marker_time_ && next_marker_time_ - now <= period)
  {
    return;
  }
  // A fixed schedule (next += period) keeps the average rate exact on the physics timer's grid.
  const bool behind =
      next_marker_time_.isZero() || now - next_marker_time_ > period || next_marker_time_ - now > period;
  next_marker_time_ = behind ? now + period : next_marker_time_ + period;
  sim_->computeSegmentTensions(tensions_);
  MarkerOptions marker_options;
  marker_options.frame_id = options_.world_frame;
  marker_options.line_width = options_.marker_line_width;
  marker_options.tension_full_scale = options_.tension_full_scale;
  marker_options.stripe_segments = options_.stripe_segments;
  toMarkers(*sim_, tensions_, ros::Time(std::max(sim_->time(), 0.0)), marker_options, &markers_);
  marker_pub_.publish(markers_);
}

bool TetherNode::onGetTension(GetTension::Request& request, GetTension::Response& response)
{
  sim_->computeSegmentTensions(tensions_);
  answerGetTension(*sim_, tensions_, request, &response);
  return true;  // refusals are answered with success = false and a message
}

bool TetherNode::onSetWinch(SetWinch::Request& request, SetWinch::Response& response)
{
  applyPendingParams();
  TetherParams params = sim_->params();
  response.success = false;
  if (!request.mode.empty() && !parseWinchMode(request.mode, &params.winch_mode))
  {
    response.message = "mode '" + request.mode + "': expected passive, locked or speed";
    return true;
  }
  params.winch_speed = request.speed;
  const auto errors = params.validate();
  if (!errors.empty())
  {
    response.message = errors.front();
    return true;
  }
  if (request.target_length < 0.0 || !std::isfinite(request.target_length))
  {
    response.message = "target_length must be > 0 m, or 0 for none";
    return true;
  }
  // Check the target against the new limits before changing anything.
  const double target = request.target_length > 0.0 ? request.target_length : std::nan("");
  if (!std::isnan(target) && !(target >= params.min_deployed_length && target <= params.cable_length))
  {
    response.message = "target_length = " + std::to_string(target) + " m: must be in [min_deployed_length, " +
                       "cable_length] = [" + std::to_string(params.min_deployed_length) + ", " +
                       std::to_string(params.cable_length) + "] m";
    return true;
  }
  const Status status = sim_->setParams(params);
  if (!status.ok)
  {
    response.message = status.message;
    return true;
  }
  sim_->setTargetLength(target);
  reconfigure_server_->updateConfig(paramsToConfig(params));
  response.success = true;
  response.message = "winch " + toString(params.winch_mode);
  return true;
}

bool TetherNode::onReset(std_srvs::Trigger::Request& /*request*/, std_srvs::Trigger::Response& response)
{
  resetTether(ros::Time::now(), "reset requested");
  response.success = true;
  response.message = "tether reset to " + std::to_string(sim_->deployedLength()) + " m";
  return true;
}

void TetherNode::onReconfigure(TetherConfig& config, uint32_t /*level*/)
{
  TetherParams params;
  {
    std::lock_guard<std::mutex> lock(pending_mutex_);
    params = pending_params_ ? *pending_params_ : sim_->params();
  }
  const TetherParams current = params;
  std::string error = configToParams(config, &params);
  for (const auto& e : params.validate())
  {
    error += (error.empty() ? "" : "; ") + e;
  }
  if (!error.empty())
  {
    ROS_ERROR("tether_node: dynamic_reconfigure change refused, old values kept: %s", error.c_str());
    config = paramsToConfig(current);
    return;
  }
  std::lock_guard<std::mutex> lock(pending_mutex_);
  pending_params_ = params;
}

void TetherNode::diagnose(diagnostic_updater::DiagnosticStatusWrapper& status)
{
  using diagnostic_msgs::DiagnosticStatus;
  const TetherSummary summary = sim_->summary();
  status.summary(DiagnosticStatus::OK, "tether simulated");
  status.add("deployed length [m]", summary.deployed_length);
  status.add("tension at vehicle [N]", summary.tension_vehicle);
  status.add("max tension [N]", summary.max_tension);
  status.add("step time [us]", step_seconds_ * 1e6);
  status.add("physics real-time factor", real_time_factor_);
  status.add("residual stretch", summary.mean_strain);
  status.add("rejected poses", rejected_poses_);
  status.add("resets", resets_);
  status.add("vehicle jumps", sim_->jumpCount());
  status.add("solver", toString(sim_->params().solver));
  status.add("iterations", sim_->params().iterations);
  status.add("physics load [% of wall time]", 100.0 * physics_load_);
  status.add("skips (fell behind)", skips_);
  status.add("simulation failures", sim_->recoveryCount());
  if (!sim_->lastFailure().empty())
  {
    status.add("last failure", sim_->lastFailure());
  }
  const ros::Time now = ros::Time::now();
  if (!sim_->vehicleAttached())
  {
    status.mergeSummary(DiagnosticStatus::WARN, "no vehicle pose yet");
  }
  else if (!last_pose_time_.isZero() && (now - last_pose_time_).toSec() > options_.stale_pose_timeout)
  {
    status.mergeSummaryf(DiagnosticStatus::WARN, "stale pose: none for %.1f s", (now - last_pose_time_).toSec());
  }
  if (summary.max_tension > options_.max_tension_warning)
  {
    status.mergeSummaryf(DiagnosticStatus::WARN, "over-tension: %.1f N", summary.max_tension);
  }
  if (summary.deployed_length >= sim_->params().cable_length - 1e-9)
  {
    status.mergeSummary(DiagnosticStatus::WARN, "fully deployed");
  }
  if (!last_failure_time_.isZero() && (now - last_failure_time_).toSec() < kFailureReportTime)
  {
    status.mergeSummaryf(DiagnosticStatus::ERROR, "simulation failure, cable re-laid: %s", sim_->lastFailure().c_str());
  }
  if (!degraded_.empty())
  {
    status.mergeSummaryf(DiagnosticStatus::WARN, "degraded to hold real time: %s (overload_policy %s)",
                         degraded_.c_str(), options_.overload_policy.c_str());
  }
  if (!last_skip_time_.isZero() && (now - last_skip_time_).toSec() < kFailureReportTime)
  {
    status.mergeSummary(DiagnosticStatus::ERROR, "fell behind real time by more than max_lag: skipped ahead");
  }
  if (real_time_factor_ > 0.0 && real_time_factor_ < 1.0)
  {
    status.mergeSummaryf(DiagnosticStatus::ERROR, "physics slower than real time (%.2fx)", real_time_factor_);
  }
}

}  // namespace rov_tether::ros_layer
