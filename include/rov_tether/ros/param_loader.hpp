#pragma once

#include <XmlRpcValue.h>

#include <Eigen/Core>
#include <string>
#include <vector>

#include "rov_tether/core/tether_params.hpp"
#include "rov_tether/core/vehicle_controller.hpp"
#include "rov_tether/core/vehicle_params.hpp"

namespace rov_tether::ros_layer
{

/// Options of tether_node that are not model parameters (frames, rates, display).
struct NodeOptions
{
  std::string world_frame = "world";  ///< Frame of the spool, the cable and all outputs.
  /// When poses come in a frame tf cannot connect to world_frame and nobody else uses world_frame in tf
  /// (no parent, no children but the node's own frames), world_frame is taken as the poses' frame: the identity
  /// pose_frame -> world_frame is set in tf and published on /tf_static, with an INFO (a pose in map or odom works out
  /// of the box).
  bool world_frame_from_pose = true;
  std::string pose_source = "topic";  ///< "topic" (rov_pose, PoseStamped) or "tf" (world_frame -> rov_frame).
  std::string rov_frame = "rov";      ///< Vehicle frame: looked up when pose_source is "tf"; frame of ~wrench_vehicle.
  Eigen::Vector3d attachment_offset = Eigen::Vector3d::Zero();  ///< Tether attachment in the vehicle frame [m].
  std::string spool_frame;  ///< Empty: the spool is fixed at spool_position; else a tf frame.
  Eigen::Vector3d spool_position = Eigen::Vector3d::Zero();  ///< Spool outlet in world_frame [m].
  /// Non-empty: the spool rides on the dynamic vehicle of the tether of this name (a TMS), listed before this
  /// one in `tethers`, at spool_outlet_offset in that vehicle's frame; spool_position and spool_frame are then
  /// not used (World::mountSpool).
  std::string spool_on;
  Eigen::Vector3d spool_outlet_offset = Eigen::Vector3d::Zero();  ///< The outlet on spool_on's vehicle, its frame [m].
  double physics_rate = 200.0;                                    ///< Timer rate advancing the physics [Hz].
  /// The physics runs this far behind ROS time so that vehicle poses, which arrive late, bracket it and
  /// the vehicle end is interpolated smoothly instead of held and jerked [s].
  double interpolation_delay = 0.1;
  double state_rate = 30.0;          ///< ~state and ~wrench rate [Hz].
  double marker_rate = 30.0;         ///< ~markers rate when subscribed [Hz].
  double marker_line_width = 0.03;   ///< Cable width in rviz [m].
  double tension_full_scale = 50.0;  ///< Tension drawn red [N].
  int stripe_segments = 5;           ///< Segments per colour stripe (shows pay-out, paper Fig. 7).
  double stale_pose_timeout = 2.0;   ///< No pose for this long: a warning, and the physics stops waiting for one [s].
  /// A pose stamped further ahead of ROS time than this is refused and counted: taken, it would have every
  /// later pose refused as older than it until ROS time caught up (a clock an hour ahead froze the tether) [s].
  double max_pose_future = 1.0;
  double max_tension_warning = 500.0;  ///< Tension above this is a diagnostics warning [N].
  /// A sub-step the solver (direct) ends short of solver_tolerance with its relative residual above this is a
  /// diagnostics warning for 5 s, and logged; every one short of the tolerance is counted [-].
  double solver_residual_warning = 1e-4;
  std::string pose_topic = "rov_pose";  ///< Vehicle pose topic (pose_source topic), relative to the node's namespace.
  /// What to give up when the physics cannot hold real time: "reduce_iterations" (down to
  /// min_iterations), "reduce_markers" (halve the marker rate, down to 1 Hz) or "none". Always reported.
  std::string overload_policy = "reduce_iterations";
  int min_iterations = 2;  ///< reduce_iterations never goes below this [-].
  /// Fraction of one core's wall time the physics may use before the node degrades [-].
  double cpu_budget = 0.8;
  /// When the physics falls further than this behind its target time, it skips ahead (ERROR) [s].
  double max_lag = 1.0;
  /// tf frames published under world_frame at the spool outlet and at the cable's vehicle end (with several
  /// tethers, prefixed "name/"); "" publishes none.
  std::string spool_outlet_frame = "tether_spool";
  std::string cable_end_frame = "tether_end";
  /// /diagnostics WARN when the tether winds this many turns (either way) around an obstacle [-], > 0.
  double wrap_warning_turns = 0.5;
  /// /diagnostics WARN ("snag") when a contact's capstan ratio e^(mu angle) exceeds this [-], > 1.
  double snag_ratio = 3.0;
  /// "kinematic": the vehicle end follows the poses (pose_source); "dynamic": the vehicle is a VehicleBody coupled
  /// into the step, driven by ~cmd_wrench (VehicleIo); needs solver direct and pose_source topic.
  std::string vehicle_model = "kinematic";
  /// The vehicle's parameter file (spec::loadVehicleParamsFile): an absolute path, file:///path or
  /// package://package/path; "" is VehicleParams' defaults, the BlueROV2 Heavy of
  /// config/vehicles/bluerov2_heavy.yaml. Its `size` is drawn in rviz in both models.
  std::string vehicle_params;
  /// A ~cmd_wrench older than this (ROS time since it arrived) is stale: zero thrust, warned [s].
  double cmd_wrench_timeout = 0.5;
  /// Dynamic vehicle: where it starts (and restarts after a reset), [x, y, z] [m] in world_frame and yaw
  /// [rad], at rest. Without it (has_vehicle_start false) the vehicle starts at the first pose taken.
  bool has_vehicle_start = false;
  Eigen::Vector4d vehicle_start = Eigen::Vector4d::Zero();
  /// The YAML files the launch loaded into the node's namespace (the shipped launch files set it), which
  /// checkParamFiles reads again for a key given twice (roslaunch keeps the last one without a word).
  std::vector<std::string> param_files;
  /// Not a parameter: the rov_frame of every dynamic vehicle of the node (the world's setup fills it in), frames the
  /// node itself publishes under world_frame (PoseInput's "does someone else use world_frame?").
  std::vector<std::string> node_vehicle_frames;
};

/// One tether's parameters as loaded: the model's and the node's.
struct TetherSetup
{
  TetherParams params;
  NodeOptions options;
  VehicleParams vehicle;  ///< From options.vehicle_params (the defaults when "").
  /// The dynamic vehicle's controller (the file's `controller:` block, or the design for its vehicle; the
  /// defaults when vehicle_params is "").
  ControllerGains gains;
  /// What the setup was given but does not use, each naming the parameter and why (the node warns of each):
  /// vehicle_start with a kinematic vehicle.
  std::vector<std::string> ignored;
};

/// Applies every model parameter found in `dict` (the node's private namespace as a map) on top of
/// `params` through the core's setParameter, then validates. Returns "" on success, otherwise every
/// problem, each naming its parameter. `params` is changed only on success.
std::string loadTetherParams(const XmlRpc::XmlRpcValue& dict, TetherParams* params);

/// Reads each of `files` (NodeOptions::param_files: "" skipped; a relative path from $PWD, where roslaunch
/// read it) again and refuses a key given twice in one, which roslaunch keeps the last of without a word:
/// "" or "param_files: FILE: duplicate key 'k' (lines A and B): give each key once" (or YAML that does not
/// parse). A file it cannot read is warned of and skipped: roslaunch has read it (on another machine, say).
std::string checkParamFiles(const std::vector<std::string>& files);

/// Reads the node options found in `dict` on top of `options` and checks them. Returns "" or every
/// problem, each naming its parameter. `options` is changed only on success.
std::string loadNodeOptions(const XmlRpc::XmlRpcValue& dict, NodeOptions* options);

/// A tether's parameters and options: `shared` (the parameters common to several tethers; invalid: none),
/// then `own` (its namespace as a map; invalid: none) on top. Returns "" or every problem, each naming its
/// parameter; `setup` is changed only on success. Reads the vehicle file (vehicle_params) and checks what a
/// dynamic vehicle needs (checkVehicleModel); what the vehicle model does not use goes to setup->ignored.
std::string loadTetherSetup(const XmlRpc::XmlRpcValue& shared, const XmlRpc::XmlRpcValue& own, TetherSetup* setup);

/// Why the setup cannot run its vehicle model ("" when it can): vehicle_model dynamic needs solver direct (the
/// one that couples a vehicle into its step) and pose_source topic (it publishes world_frame -> rov_frame on
/// tf itself, and would read its own output back as its input).
std::string checkVehicleModel(const TetherSetup& setup);

/// Keys of `dict` that are neither model parameters nor node options (likely typos), comma-separated, a close
/// name suggested; a map that `tethers` does not list is named as one (a tether's map left out of the list, or
/// misspelt). The keys `tethers`, `cameras`, `obstacles` and `tether_contact` and the maps `tethers` names (one
/// tether each, see tether_node) are known.
std::string unknownParameters(const XmlRpc::XmlRpcValue& dict);

}  // namespace rov_tether::ros_layer
