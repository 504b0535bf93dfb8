#pragma once

#include <dynamic_reconfigure/server.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>

#include <boost/thread/recursive_mutex.hpp>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "rov_tether/GetTension.h"
#include "rov_tether/SetWinch.h"
#include "rov_tether/TetherConfig.h"
#include "rov_tether/core/tether.hpp"
#include "rov_tether/core/world.hpp"
#include "rov_tether/ros/param_loader.hpp"
#include "rov_tether/ros/pose_input.hpp"
#include "rov_tether/ros/scheduler.hpp"
#include "rov_tether/ros/tether_diagnostics.hpp"
#include "rov_tether/ros/tether_publisher.hpp"
#include "rov_tether/ros/vehicle_io.hpp"
#include "rov_tether/ros/world_report.hpp"

namespace rov_tether::ros_layer
{

/// Loads a tether's parameters from `private_nh`'s namespace on top of `shared` (the parameters common
/// to several tethers; invalid: none). Throws std::runtime_error naming a bad parameter; warns about
/// unknown ones (typos).
TetherSetup loadTetherSetup(const ros::NodeHandle& private_nh, const XmlRpc::XmlRpcValue& shared);

/**
 * One tether's ROS interface in tether_node: its Tether (added to the process's World), its PoseInput,
 * TetherPublisher and TetherDiagnostics, its services ~get_tension, ~set_winch, ~reset and its
 * dynamic_reconfigure server, whose changes take effect between steps; with vehicle_model dynamic its
 * VehicleIo (~cmd_wrench, ~odom, tf), which takes the poses instead of the tether. The WorldNode's Scheduler steps
 * it through the TetherHooks.
 */
class TetherNode : public TetherHooks
{
 public:
  /// Takes the tether `world` holds as `name` (or "tether" alone; built by buildWorld), adds it to `scheduler`,
  /// then advertises under `private_nh` and subscribes to poses under `input_nh` (whose callback queue is
  /// the process's input queue, served by its own thread). `tf` is the process's one buffer; `topology` the
  /// world's topology report (for the diagnostics). `world`, `scheduler`, `tf` and `topology` must outlive this.
  TetherNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh, const ros::NodeHandle& input_nh,
             const TetherSetup& setup, const std::string& name, World& world, Scheduler& scheduler, tf2_ros::Buffer& tf,
             TopologyReport& topology);

  void beforeAdvance(const ros::Time& now) override;
  void publishState() override;
  void afterAdvance(const ros::Time& now) override;
  void restarted(const ros::Time& now) override;
  /// While ~coupling is subscribed (and the tether can give it): every step is published.
  bool watchesSteps() const override { return publisher_.couplingWanted(tether_); }
  /// ~coupling for the step just taken; K over the time a simulator runs ahead of it (couplingHorizon()).
  void stepped(double delay) override { publisher_.publishCoupling(tether_, couplingHorizon(delay)); }
  PoseTiming poseTiming() const override;
  ros::Time earliestArrival() const override { return pose_input_.earliestArrival(); }

 private:
  bool onGetTension(GetTension::Request& request, GetTension::Response& response);
  bool onSetWinch(SetWinch::Request& request, SetWinch::Response& response);
  bool onReset(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);
  void onReconfigure(TetherConfig& config, uint32_t level);
  void applyPendingParams();
  /// Warns when the parameters make the method unstable (lumped_mass above its critical step).
  void warnAboutStability() const;
  /// How far ahead of the step just taken an external simulator's state is [s]: ROS time now less the step's
  /// time, at least the physics' `delay` (the node running behind on a busy machine adds to it).
  double couplingHorizon(double delay) const;
  /// `options` with the tf frames this tether publishes prefixed "name/" among several tethers.
  static NodeOptions withTetherFrames(NodeOptions options, const std::string& name);
  /// Adds the tether to the world and returns it (throws when the world refuses the name).
  static Tether& tetherIn(World& world, const std::string& name);

  ros::NodeHandle nh_;
  ros::NodeHandle private_nh_;
  NodeOptions options_;
  std::string name_;  ///< This tether's name among several ("" alone).
  const World& world_;
  Tether& tether_;
  Scheduler& scheduler_;
  std::size_t index_;  ///< In the world and the scheduler.
  PoseInput pose_input_;
  std::unique_ptr<VehicleIo> vehicle_io_;  ///< vehicle_model dynamic; null: kinematic.
  TetherPublisher publisher_;
  TetherDiagnostics diagnostics_;
  ros::ServiceServer get_tension_srv_;
  ros::ServiceServer set_winch_srv_;
  ros::ServiceServer reset_srv_;
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<TetherConfig>> reconfigure_server_;
  std::mutex pending_mutex_;
  std::optional<TetherParams> pending_params_;  ///< Written by dynamic_reconfigure, applied between steps.
  /// The parameters as the user asked for them (`iterations: auto` kept; the tether runs them resolved), the
  /// start of every dynamic_reconfigure and set_winch change. Guarded by pending_mutex_.
  TetherParams requested_params_;
  /// The request the tether runs: what requested_params_ goes back to when the tether refuses a change that passed
  /// dynamic_reconfigure's checks (a dynamic vehicle's solver). Guarded by pending_mutex_.
  TetherParams running_params_;
  std::vector<double> tensions_;
  Eigen::Isometry3d vehicle_pose_ = Eigen::Isometry3d::Identity();  ///< At the last ~state (for ~markers).
};

}  // namespace rov_tether::ros_layer
