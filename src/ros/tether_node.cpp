#include "rov_tether/ros/tether_node.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "rov_tether/ros/reconfigure.hpp"
#include "rov_tether/ros/winch_service.hpp"

namespace rov_tether::ros_layer
{

TetherSetup loadTetherSetup(const ros::NodeHandle& private_nh, const XmlRpc::XmlRpcValue& shared)
{
  XmlRpc::XmlRpcValue dict;
  if (!private_nh.getParam(private_nh.getNamespace(), dict))
  {
    dict = XmlRpc::XmlRpcValue();
  }
  TetherSetup setup;
  const std::string error = loadTetherSetup(shared, dict, &setup);
  if (!error.empty())
  {
    throw std::runtime_error("invalid parameters in " + private_nh.getNamespace() + ": " + error);
  }
  for (const std::string& ignored : setup.ignored)
  {
    ROS_WARN("tether_node: %s: %s", private_nh.getNamespace().c_str(), ignored.c_str());
  }
  const std::string unknown = dict.valid() ? unknownParameters(dict) : "";
  if (!unknown.empty())
  {
    ROS_WARN("tether_node: ignoring unknown parameters in %s (typos?): %s", private_nh.getNamespace().c_str(),
             unknown.c_str());
  }
  return setup;
}

NodeOptions TetherNode::withTetherFrames(NodeOptions options, const std::string& name)
{
  for (std::string* frame : {&options.spool_outlet_frame, &options.cable_end_frame})
  {
    if (!name.empty() && !frame->empty())
    {
      *frame = name + "/" + *frame;  // several tethers: each its own frames
    }
  }
  return options;
}

Tether& TetherNode::tetherIn(World& world, const std::string& name)
{
  const std::size_t index = world.find(name.empty() ? "tether" : name);
  if (index == World::npos)
  {
    throw std::runtime_error("tether_node: no tether '" + name + "' in the world built from the parameters");
  }
  return world.tether(index);
}

TetherNode::TetherNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh, const ros::NodeHandle& input_nh,
                       const TetherSetup& setup, const std::string& name, World& world, Scheduler& scheduler,
                       tf2_ros::Buffer& tf, TopologyReport& topology)
    : nh_(nh),
      private_nh_(private_nh),
      options_(setup.options),
      name_(name),
      world_(world),
      tether_(tetherIn(world, name)),
      scheduler_(scheduler),
      index_(scheduler.add(setup.options, *this, name)),
      pose_input_(setup.options, tf, tether_, name, input_nh.getCallbackQueue()),
      vehicle_io_(setup.options.vehicle_model == "dynamic"
                      ? std::make_unique<VehicleIo>(setup, tether_, name.empty() ? "" : " " + name)
                      : nullptr),
      publisher_(private_nh_, withTetherFrames(setup.options, name), setup.vehicle.size),
      diagnostics_(nh_, private_nh_, setup.options, name, tether_, pose_input_, scheduler, index_, topology),
      requested_params_(setup.params),
      running_params_(setup.params)
{
  warnAboutStability();
  get_tension_srv_ = private_nh_.advertiseService("get_tension", &TetherNode::onGetTension, this);
  set_winch_srv_ = private_nh_.advertiseService("set_winch", &TetherNode::onSetWinch, this);
  reset_srv_ = private_nh_.advertiseService("reset", &TetherNode::onReset, this);
  reconfigure_server_ = std::make_unique<dynamic_reconfigure::Server<TetherConfig>>(reconfigure_mutex_, private_nh_);
  reconfigure_server_->setConfigMin(configBounds(false));  // the table's ranges, for rqt_reconfigure
  reconfigure_server_->setConfigMax(configBounds(true));
  reconfigure_server_->updateConfig(paramsToConfig(setup.params));
  reconfigure_server_->setCallback([this](TetherConfig& config, uint32_t level) { onReconfigure(config, level); });
  if (vehicle_io_)
  {
    pose_input_.setVehicleSink([this](double t, const Eigen::Isometry3d& vehicle)
                               { return vehicle_io_->takePose(t, vehicle); });
    vehicle_io_->advertise(private_nh_, input_nh.getCallbackQueue());
    diagnostics_.addExtra([this](diagnostic_updater::DiagnosticStatusWrapper& status)
                          { vehicle_io_->diagnose(status); });
  }
  ros::NodeHandle pose_nh(input_nh);
  pose_input_.subscribe(pose_nh);
  const TetherParams& p = tether_.params();
  ROS_INFO("tether_node%s: %.1f m cable in %zu segments, %s solver, %s vehicle, pose from %s, physics at %.0f Hz",
           name_.empty() ? "" : (" " + name_).c_str(), p.cable_length, p.segmentCount(), toString(p.solver).c_str(),
           options_.vehicle_model.c_str(),
           options_.pose_source == "topic" ? pose_input_.topic().c_str()
                                           : ("tf " + options_.world_frame + " -> " + options_.rov_frame).c_str(),
           options_.physics_rate);
}

void TetherNode::beforeAdvance(const ros::Time& now)
{
  applyPendingParams();
  pose_input_.poll(now);
  if (vehicle_io_)
  {
    vehicle_io_->beforeAdvance(now);  // after the poll: the first pose may start the vehicle
  }
}

void TetherNode::publishState()
{
  // The force is of the physics' time, behind the latest pose: its lever arm and frame are the vehicle's then
  // (a dynamic vehicle's own pose at that time).
  vehicle_pose_ = vehicle_io_ ? vehicle_io_->pose() : pose_input_.vehicleAt(tether_.time());
  publisher_.publishState(tether_, scheduler_.schedule(index_).resets, vehicle_pose_);
  if (vehicle_io_)
  {
    vehicle_io_->publishState();
  }
}

void TetherNode::afterAdvance(const ros::Time& now)
{
  diagnostics_.report(now);
  publisher_.explainMissingCoupling(tether_);
  // The vehicle's box where it is at the tether's time: a dynamic body's pose, or the poses interpolated.
  if (tether_.vehicleAttached())
  {
    vehicle_pose_ = vehicle_io_ ? vehicle_io_->pose() : pose_input_.vehicleAt(tether_.time());
  }
  const double marker_wall = publisher_.publishMarkers(tether_, world_.contacts(index_), now,
                                                       scheduler_.schedule(index_).governor.markerRate(),
                                                       tether_.vehicleAttached() ? &vehicle_pose_ : nullptr);
  scheduler_.governor(index_).addMarkerTime(marker_wall);
  diagnostics_.publish();
}

void TetherNode::restarted(const ros::Time& now)
{
  pose_input_.reset(now);
  publisher_.restart(tether_);
  diagnostics_.restarted();
  if (vehicle_io_)
  {
    vehicle_io_->restarted(now);
  }
}

TetherHooks::PoseTiming TetherNode::poseTiming() const
{
  if (vehicle_io_)
  {
    return PoseTiming{};  // a dynamic vehicle moves by itself: the physics need not wait for poses
  }
  return PoseTiming{pose_input_.latestStamp(), pose_input_.neededDelay()};
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
  const Status status = tether_.setParams(*pending);
  if (!status.ok)
  {
    // Refused whole, as dynamic_reconfigure's own checks refuse: what was asked goes back to what runs, and
    // `dynparam get` and the parameter server show it (else they kept the refused value, and every later change,
    // made from it, was refused too). A change asked since was made from the refused one: it is checked in turn.
    TetherConfig shown;
    bool newer = false;
    {
      std::lock_guard<std::mutex> lock(pending_mutex_);
      newer = pending_params_.has_value();
      requested_params_ = newer ? requested_params_ : running_params_;
      shown = paramsToConfig(requested_params_);
    }
    if (!newer)
    {
      reconfigure_server_->updateConfig(shown);
    }
    ROS_ERROR("tether_node%s: parameters refused whole, old values kept: %s",
              name_.empty() ? "" : (" " + name_).c_str(), status.message.c_str());
    return;
  }
  {
    std::lock_guard<std::mutex> lock(pending_mutex_);
    running_params_ = *pending;
  }
  // A new configuration ends any reduction (iterations as resolved, `auto` included).
  scheduler_.governor(index_).reconfigured(tether_.params().iterations);
  if (!status.message.empty())
  {
    ROS_INFO("tether_node: %s", status.message.c_str());
  }
  warnAboutStability();
}

double TetherNode::couplingHorizon(double delay) const
{
  return std::max(delay, ros::Time::now().toSec() - tether_.time());
}

void TetherNode::warnAboutStability() const
{
  const TetherParams& p = tether_.params();
  if (p.solver == SolverType::kLumpedMass && p.subStep() > p.criticalStep())
  {
    ROS_WARN(
        "tether_node: lumped_mass sub-step %.3g s exceeds its critical step %.3g s (segment_length / "
        "sqrt(EA / mu), shorter with axial_damping): it will diverge (detected and reported); set substeps >= %.0f or "
        "iterations: auto",
        p.subStep(), p.criticalStep(), std::ceil(p.time_step / p.criticalStep()));
  }
}

bool TetherNode::onGetTension(GetTension::Request& request, GetTension::Response& response)
{
  tether_.computeSegmentTensions(tensions_);
  answerGetTension(tether_, tensions_, request, &response);
  return true;  // refusals are answered with success = false and a message
}

bool TetherNode::onSetWinch(SetWinch::Request& request, SetWinch::Response& response)
{
  applyPendingParams();
  TetherParams params = tether_.params();
  double target = tether_.targetLength();  // the target in force: a request of one field keeps it
  response.success = false;
  response.message = winchRequest(request, &params, &target, private_nh_.getNamespace());
  if (!response.message.empty())
  {
    return true;
  }
  const Status status = tether_.setParams(params);
  if (!status.ok)
  {
    response.message = status.message;
    return true;
  }
  // Checked against the same limits above, before anything changed, so this cannot be refused; were it, the
  // answer says why (the new winch parameters are in force, without the target).
  const Status target_status = tether_.setTargetLength(target);
  if (!target_status.ok)
  {
    response.message = target_status.message;
    return true;
  }
  TetherConfig shown;
  {
    // What the user asked changes in the winch's fields only (`iterations: auto` stays auto).
    std::lock_guard<std::mutex> lock(pending_mutex_);
    for (TetherParams* kept : {&requested_params_, &running_params_})  // the tether runs them already
    {
      kept->winch_mode = params.winch_mode;
      kept->winch_speed = params.winch_speed;
      kept->brake_tension = params.brake_tension;
      kept->target_tension = params.target_tension;
    }
    shown = paramsToConfig(requested_params_);
  }
  reconfigure_server_->updateConfig(shown);
  response.success = true;
  response.message = winchAnswer(params, request.mode);
  return true;
}

bool TetherNode::onReset(std_srvs::Trigger::Request& /*request*/, std_srvs::Trigger::Response& response)
{
  const ros::Time now = ros::Time::now();
  const ros::Time cut = pose_input_.resetCut(now);
  scheduler_.reset(index_, now, "reset requested");
  pose_input_.refuseStampedBefore(cut);  // a pose of the vehicle before the reset, delivered late, lays out nothing
  response.success = true;
  response.message = "tether reset to " + std::to_string(tether_.deployedLength()) + " m";
  return true;
}

void TetherNode::onReconfigure(TetherConfig& config, uint32_t /*level*/)
{
  // Start from what the user asked (`iterations: auto` kept), not from the resolved values the tether runs.
  TetherParams params;
  {
    std::lock_guard<std::mutex> lock(pending_mutex_);
    params = requested_params_;
  }
  const TetherParams current = params;
  const std::string error = applyConfigChanges(config, &params);
  if (!error.empty())
  {
    // The .cfg gives no ranges, so `config` is what was asked, unclamped: name it and what still runs.
    const TetherConfig used = paramsToConfig(current);
    ROS_WARN("tether_node: dynamic_reconfigure change refused whole, old values kept (%s): %s",
             configDifferences(config, used).c_str(), error.c_str());
    config = used;
    return;
  }
  config = paramsToConfig(params);  // shows what `auto` resolves to with the new values
  std::lock_guard<std::mutex> lock(pending_mutex_);
  requested_params_ = params;
  pending_params_ = params;
}

}  // namespace rov_tether::ros_layer
