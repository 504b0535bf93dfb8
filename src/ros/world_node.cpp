#include "rov_tether/ros/world_node.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <string>

#include "rov_tether/ros/camera_config.hpp"
#include "rov_tether/ros/obstacle_config.hpp"
#include "rov_tether/scenario/world_spec.hpp"

namespace rov_tether::ros_layer
{
namespace
{

/// The names in the private parameter `tethers`; empty when it is absent (one tether, configured in ~).
std::vector<std::string> tetherNames(const ros::NodeHandle& private_nh)
{
  std::vector<std::string> result;
  XmlRpc::XmlRpcValue names;
  if (!private_nh.getParam("tethers", names))
  {
    return result;
  }
  if (names.getType() != XmlRpc::XmlRpcValue::TypeArray || names.size() == 0)
  {
    throw std::runtime_error("parameter 'tethers': expected a non-empty list of names");
  }
  for (int i = 0; i < names.size(); ++i)
  {
    if (names[i].getType() != XmlRpc::XmlRpcValue::TypeString)
    {
      throw std::runtime_error("parameter 'tethers': entry " + std::to_string(i) + " is not a name");
    }
    // The runner's rule (isTetherName), checked before a namespace is made of it.
    const std::string bad = checkNodeTetherName(static_cast<std::string>(names[i]));
    if (!bad.empty())
    {
      throw std::runtime_error("parameter 'tethers': entry " + std::to_string(i) + " " + bad);
    }
    result.push_back(static_cast<std::string>(names[i]));
  }
  return result;
}

/// The tethers of one world run on one clock: the timer at the highest physics_rate asked for and the
/// physics the largest interpolation_delay behind ROS time. Says so when some tether asked otherwise.
void shareOneClock(const std::vector<std::string>& names, std::vector<TetherSetup>* setups)
{
  double rate = 0.0;
  double delay = 0.0;
  for (const auto& setup : *setups)
  {
    rate = std::max(rate, setup.options.physics_rate);
    delay = std::max(delay, setup.options.interpolation_delay);
  }
  std::string differing;
  for (std::size_t i = 0; i < setups->size(); ++i)
  {
    NodeOptions& options = (*setups)[i].options;
    if (options.physics_rate != rate || options.interpolation_delay != delay)
    {
      differing += (differing.empty() ? "" : ", ") + names[i] + " (physics_rate " +
                   std::to_string(options.physics_rate) + " Hz, interpolation_delay " +
                   std::to_string(options.interpolation_delay) + " s)";
    }
    options.physics_rate = rate;
    options.interpolation_delay = delay;
  }
  if (!differing.empty())
  {
    ROS_WARN(
        "tether_node: the tethers of one process share one physics clock: physics_rate %.1f Hz and "
        "interpolation_delay %.3f s (the highest and the largest asked for) also apply to %s",
        rate, delay, differing.c_str());
  }
}

/// Dynamic vehicles publish world_frame -> rov_frame on tf: two of them under one rov_frame would fight over it.
void checkVehicleFrames(const std::vector<std::string>& names, const std::vector<TetherSetup>& setups)
{
  for (std::size_t i = 0; i < setups.size(); ++i)
  {
    for (std::size_t j = 0; j < i; ++j)
    {
      if (setups[i].options.vehicle_model == "dynamic" && setups[j].options.vehicle_model == "dynamic" &&
          setups[i].options.rov_frame == setups[j].options.rov_frame)
      {
        throw std::runtime_error("tethers " + names[j] + " and " + names[i] + ": both dynamic vehicles publish tf " +
                                 "frame '" + setups[i].options.rov_frame + "': give each its own rov_frame");
      }
    }
  }
}

/// A spool on another tether's vehicle (spool_on, a TMS): that tether is listed before, its vehicle is dynamic
/// and starts at vehicle_start (where the spool starts), and the spool has no spool_frame of its own.
void checkSpoolMounts(const std::vector<std::string>& names, const std::vector<TetherSetup>& setups)
{
  for (std::size_t i = 0; i < setups.size(); ++i)
  {
    const NodeOptions& options = setups[i].options;
    const std::string prefix = names.empty() ? "" : names[i] + "/";
    if (options.spool_on.empty())
    {
      if (!options.spool_outlet_offset.isZero(0.0))
      {
        throw std::runtime_error("parameter " + prefix +
                                 "spool_outlet_offset: only with spool_on (the outlet on another tether's vehicle)");
      }
      continue;
    }
    if (options.spool_outlet_offset.norm() > VehicleParams::kMaxOffset)
    {
      std::ostringstream message;
      message << "parameter " << prefix << "spool_outlet_offset: must be within " << VehicleParams::kMaxOffset
              << " m of the vehicle's origin";
      throw std::runtime_error(message.str());
    }
    const std::string who = "parameter " + (names.empty() ? std::string("spool_on") : names[i] + "/spool_on") + " = '" +
                            options.spool_on + "': ";
    const auto carrier = std::find(names.begin(), names.end(), options.spool_on);
    if (carrier == names.end() || carrier - names.begin() >= static_cast<std::ptrdiff_t>(i))
    {
      throw std::runtime_error(who + (names.empty() ? "a spool rides on another tether: list both in `tethers`"
                                                    : "expected a tether listed before " + names[i] + " in `tethers`"));
    }
    const NodeOptions& carried_by = setups[static_cast<std::size_t>(carrier - names.begin())].options;
    if (carried_by.vehicle_model != "dynamic" || !carried_by.has_vehicle_start)
    {
      throw std::runtime_error(who +
                               "its vehicle must be dynamic (vehicle_model: dynamic) with a vehicle_start, "
                               "where the spool starts");
    }
    if (!options.spool_frame.empty())
    {
      throw std::runtime_error(who + "not with spool_frame '" + options.spool_frame +
                               "': the spool goes where the vehicle carries it");
    }
    if (!options.spool_position.isZero(0.0))
    {
      ROS_WARN("tether_node: parameter %sspool_position is not used: the spool rides on %s's vehicle (spool_on)",
               prefix.c_str(), options.spool_on.c_str());
    }
  }
}

}  // namespace

namespace
{
/// Each tether's setup: the one in ~ alone, or one per name in `tethers` with ~'s values shared.
std::vector<TetherSetup> loadSetups(const ros::NodeHandle& private_nh, const std::vector<std::string>& names)
{
  std::vector<TetherSetup> setups;
  if (names.empty())
  {
    setups.push_back(loadTetherSetup(private_nh, XmlRpc::XmlRpcValue()));
  }
  else
  {
    XmlRpc::XmlRpcValue shared;
    private_nh.getParam(private_nh.getNamespace(), shared);
    for (const auto& name : names)
    {
      setups.push_back(loadTetherSetup(ros::NodeHandle(private_nh, name), shared));
    }
    // The shared keys, as ~'s are checked with one tether (each tether's own map is checked by its loader).
    const std::string unknown = shared.valid() ? unknownParameters(shared) : "";
    if (!unknown.empty())
    {
      ROS_WARN("tether_node: ignoring unknown parameters in %s (typos?): %s", private_nh.getNamespace().c_str(),
               unknown.c_str());
    }
  }
  // The files the launch loaded into ~, once for all tethers (they share ~'s param_files).
  const std::string repeated = checkParamFiles(setups.front().options.param_files);
  if (!repeated.empty())
  {
    throw std::runtime_error("invalid parameters in " + private_nh.getNamespace() + ": " + repeated);
  }
  if (!names.empty())
  {
    shareOneClock(names, &setups);
    checkVehicleFrames(names, setups);
  }
  std::vector<std::string> vehicle_frames;  // each dynamic vehicle's, which the node publishes under world_frame
  for (const TetherSetup& setup : setups)
  {
    if (setup.options.vehicle_model == "dynamic")
    {
      vehicle_frames.push_back(setup.options.rov_frame);
    }
  }
  for (TetherSetup& setup : setups)
  {
    setup.options.node_vehicle_frames = vehicle_frames;
  }
  checkSpoolMounts(names, setups);
  return setups;
}

/// The world's description from ~ (obstacles, contact, cameras) and the tethers' setups, checked whole:
/// throws std::runtime_error naming the parameter when it is invalid.
WorldSpec describeWorld(const ros::NodeHandle& private_nh, const std::vector<std::string>& world_names,
                        const std::vector<TetherSetup>& setups, WorldOptions* world_options)
{
  XmlRpc::XmlRpcValue top;
  private_nh.getParam(private_nh.getNamespace(), top);
  std::string world_error = loadWorldOptions(top, world_options, world_names);
  // The world from its one description, by the runner's builder: tethers, contact, obstacles (each mesh read
  // once); the cameras are read into it too, so their names are checked with the others' (validateWorldSpec).
  WorldSpec world_spec;
  world_error = world_error.empty() ? nodeWorldSpec(world_names, setups, *world_options, &world_spec) : world_error;
  XmlRpc::XmlRpcValue cameras;
  if (world_error.empty() && private_nh.getParam("cameras", cameras))
  {
    const std::string camera_error = loadCameraConfigs(cameras, world_names, &world_spec.cameras);
    if (!camera_error.empty())
    {
      throw std::runtime_error("parameter " + camera_error);
    }
  }
  if (!world_error.empty())
  {
    throw std::runtime_error("invalid parameters in " + private_nh.getNamespace() + ": " + world_error);
  }
  return world_spec;
}
}  // namespace

WorldNode::WorldNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh) : nh_(nh), private_nh_(private_nh)
{
  const std::vector<std::string> names = tetherNames(private_nh_);
  std::vector<TetherSetup> setups = loadSetups(private_nh_, names);
  // The world's own parameters (in ~ only): obstacles, built before anything is advertised.
  const std::vector<std::string> world_names = names.empty() ? std::vector<std::string>{"tether"} : names;
  WorldOptions world_options;
  world_spec_ = describeWorld(private_nh_, world_names, setups, &world_options);
  const WorldSpec& world_spec = world_spec_;
  const bool has_cameras = private_nh_.hasParam("cameras");
  std::vector<std::string> world_warnings;
  const std::string world_error = buildWorld(world_spec, &world_, &world_warnings);
  if (!world_error.empty())
  {
    throw std::runtime_error("invalid parameters in " + private_nh_.getNamespace() + ": " + world_error);
  }
  for (const std::string& warning : world_warnings)
  {
    ROS_WARN("tether_node: %s", warning.c_str());
  }
  const NodeOptions& clock = setups.front().options;
  double state_rate = 0.0;
  for (const auto& setup : setups)
  {
    state_rate = std::max(state_rate, setup.options.state_rate);
  }
  scheduler_ = std::make_unique<Scheduler>(world_, clock.interpolation_delay);
  topology_ = std::make_unique<TopologyReport>(private_nh_, world_, clock.world_frame, state_rate);
  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(tf_buffer_);
  ros::NodeHandle input_nh(nh_);
  input_nh.setCallbackQueue(&input_queue_);
  for (std::size_t i = 0; i < setups.size(); ++i)
  {
    const std::string name = names.empty() ? "" : names[i];
    const ros::NodeHandle tether_nh = names.empty() ? private_nh_ : ros::NodeHandle(private_nh_, name);
    tethers_.push_back(std::make_unique<TetherNode>(nh_, tether_nh, input_nh, setups[i], name, world_, *scheduler_,
                                                    tf_buffer_, *topology_));
  }
  if (world_.obstacleCount() > 0)
  {
    obstacles_ = std::make_unique<ObstacleScene>(private_nh_, clock.world_frame, clock.marker_rate, world_, tf_buffer_);
    ROS_INFO("tether_node: %zu obstacles%s", world_.obstacleCount(),
             world_options.tether_contact ? ", contact between tethers on" : ", contact between tethers off");
  }
  if (has_cameras)
  {
    double longest_hold = 0.0;  // the physics waits for the slowest tether's poses
    for (const auto& setup : setups)
    {
      longest_hold = std::max(longest_hold, setup.options.stale_pose_timeout);
    }
    cameras_ = std::make_unique<CameraSet>(world_spec.cameras, nh_, private_nh_, tf_buffer_, world_,
                                           setups.front().options.world_frame, setups.front().options.max_pose_future,
                                           CameraSet::maxWait(longest_hold, setups.front().options.interpolation_delay),
                                           setups.front().options.max_lag);
  }
  for (std::size_t i = 0; i < world_spec.tethers.size(); ++i)
  {
    if (!world_spec.tethers[i].spool_on.empty())
    {
      unmounted_.push_back(i);  // mounted when the vehicle that carries it starts (mountStartedCarriers)
    }
  }
  input_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &input_queue_);
  input_spinner_->start();
  timer_ = nh_.createTimer(ros::Duration(1.0 / clock.physics_rate), &WorldNode::onTimer, this);
  if (!names.empty())
  {
    ROS_INFO("tether_node: %zu tethers in one process, one world stepped at %.0f Hz", tethers_.size(),
             clock.physics_rate);
  }
}

WorldNode::~WorldNode()
{
  if (input_spinner_)
  {
    input_spinner_->stop();
  }
}

void WorldNode::mountStartedCarriers()
{
  for (auto i = unmounted_.begin(); i != unmounted_.end();)
  {
    const ScenarioTether& tether = world_spec_.tethers[*i];
    if (!world_.tether(world_.find(tether.spool_on)).vehicleDynamic())
    {
      ++i;
      continue;
    }
    const std::string error = mountSpool(world_spec_, *i, &world_);
    if (error.empty())
    {
      ROS_INFO("tether_node: %s's spool rides on %s's vehicle", tether.name.c_str(), tether.spool_on.c_str());
    }
    else
    {
      ROS_ERROR("tether_node: %s's spool stays where it is: %s", tether.name.c_str(), error.c_str());
    }
    i = unmounted_.erase(i);
  }
}

void WorldNode::onTimer(const ros::TimerEvent& /*event*/)
{
  const ros::Time now = ros::Time::now();
  if (obstacles_)
  {
    obstacles_->update(now);  // obstacles that move with a frame, before the physics steps
  }
  scheduler_->tick(now);
  mountStartedCarriers();
  topology_->publish();
  if (cameras_)
  {
    cameras_->afterTick();
  }
}

}  // namespace rov_tether::ros_layer
