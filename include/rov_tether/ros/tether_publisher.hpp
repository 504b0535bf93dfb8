#pragma once

#include <geometry_msgs/WrenchStamped.h>
#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <ros/time.h>
#include <visualization_msgs/MarkerArray.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "rov_tether/TetherState.h"
#include "rov_tether/core/tether.hpp"
#include "rov_tether/ros/converters.hpp"
#include "rov_tether/ros/log_throttle.hpp"
#include "rov_tether/ros/markers.hpp"
#include "rov_tether/ros/param_loader.hpp"

namespace rov_tether::ros_layer
{

/**
 * Builds ~state, ~wrench and ~wrench_vehicle for a tether at its current physics time (stamped with it),
 * measuring the winch speed between two states. Needs no ROS master.
 */
/**
 * ~markers as the node publishes them: toMarkers' four (ids 0-3), where the cable touched something in its last
 * step (4, toContactMarker), the vehicle's box at `vehicle` (5, deleted when nullptr), then the sections and
 * attachments (6 on, toMaterialMarkers). Reuses `markers`' storage.
 */
void buildMarkers(const Tether& tether, const std::vector<double>& tensions, const ContactRecord& contacts,
                  const Eigen::Isometry3d* vehicle, const Eigen::Vector3d& vehicle_size, const MarkerOptions& options,
                  visualization_msgs::MarkerArray* markers);

class StateBuilder
{
 public:
  /// `frame_id`: the world frame; `vehicle_frame`: the frame of ~wrench_vehicle; `attachment_offset`: the
  /// attachment point in the vehicle frame [m].
  StateBuilder(const std::string& frame_id, const std::string& vehicle_frame = "rov",
               const Eigen::Vector3d& attachment_offset = Eigen::Vector3d::Zero())
      : frame_id_(frame_id), vehicle_frame_(vehicle_frame), attachment_offset_(attachment_offset)
  {
  }

  /// The state of `tether` now; `resets` is reported in the message. Reuses its storage.
  const TetherState& state(const Tether& tether, std::uint32_t resets);
  /// The pull on the vehicle at the same time (call after state()), in the world frame with its torque
  /// about the vehicle origin; `vehicle` is the vehicle's pose at the tether's time (the force's).
  geometry_msgs::WrenchStamped wrench(const Tether& tether, const Eigen::Isometry3d& vehicle) const;
  /// The same pull in the vehicle frame (~wrench_vehicle).
  geometry_msgs::WrenchStamped vehicleWrench(const Tether& tether, const Eigen::Isometry3d& vehicle) const;
  /// After a reset of the tether: the winch speed is measured afresh.
  void restart(const Tether& tether);

 private:
  std::string frame_id_;
  std::string vehicle_frame_;
  Eigen::Vector3d attachment_offset_;
  double last_state_physics_ = 0.0;  ///< Physics time of the last state [s].
  double last_deployed_ = 0.0;
  ros::Time stamp_;
  std::vector<double> tensions_;
  TetherState msg_;
};

/**
 * One tether's topics: ~state, ~wrench and ~wrench_vehicle (on its state grid, see Scheduler; the last
 * only computed while someone subscribes), ~coupling after every physics step (only while someone subscribes:
 * the linearisation costs a factorisation and three solves; direct solver and kinematic vehicle end only), the
 * tf frames of the spool outlet and the cable's vehicle end (with ~state), ~markers at a rate (only while
 * someone subscribes), contact points and the vehicle's box included, and the colour legend ~legend
 * (latched, once).
 */
class TetherPublisher
{
 public:
  /// Advertises under `private_nh` (and /tf). `options`' frame names are used as given (TetherNode prefixes
  /// them with the tether's name among several). `vehicle_size`: the box drawn at the vehicle [m].
  TetherPublisher(ros::NodeHandle& private_nh, const NodeOptions& options,
                  const Eigen::Vector3d& vehicle_size = VehicleParams().size);

  /// Publishes ~state, ~wrench and (with subscribers) ~wrench_vehicle for the tether's current physics time;
  /// `vehicle` is the vehicle's pose at that time.
  void publishState(const Tether& tether, std::uint32_t resets, const Eigen::Isometry3d& vehicle);
  /// Publishes ~markers when due at `rate` [Hz] and someone subscribes: the cable (toMarkers) and where it
  /// touched something in its last step (`contacts`, toContactMarker), and the vehicle as a box at `vehicle`,
  /// its pose at the tether's time (toVehicleMarker; null: no vehicle, the box is deleted). Returns the wall
  /// time it took [s] (0 when it published nothing), which the load governor counts.
  double publishMarkers(const Tether& tether, const ContactRecord& contacts, const ros::Time& now, double rate,
                        const Eigen::Isometry3d* vehicle = nullptr);
  /// After a reset of the tether.
  void restart(const Tether& tether);

  /// True while ~coupling has subscribers and `tether` can give it: solver direct, a kinematic vehicle end.
  bool couplingWanted(const Tether& tether) const;
  /// Publishes ~coupling for `tether`'s last step (call after each step while couplingWanted()). Before the
  /// first pose there is no vehicle and nothing is published; a linearisation refused otherwise is a
  /// throttled warning with the core's reason. `horizon` [s]: how far the simulator
  /// runs ahead of the step (the physics' delay behind ROS time), the time K answers over.
  void publishCoupling(Tether& tether, double horizon);
  /// Warns once while ~coupling is subscribed but `tether` cannot give it (another solver, a dynamic vehicle),
  /// saying what to use; again after the subscribers left or it could be given meanwhile.
  void explainMissingCoupling(const Tether& tether);

 private:
  NodeOptions options_;
  Eigen::Vector3d vehicle_size_;
  StateBuilder builder_;
  ros::Publisher state_pub_;
  ros::Publisher wrench_pub_;
  ros::Publisher vehicle_wrench_pub_;
  ros::Publisher coupling_pub_;      ///< ~coupling (TetherCoupling), after every step with subscribers.
  EndLinearisation linearisation_;   ///< Reused by publishCoupling().
  TetherCoupling coupling_;          ///< Reused by publishCoupling().
  bool coupling_explained_ = false;  ///< explainMissingCoupling() has warned for this subscription.
  LogThrottle coupling_log_{5.0};    ///< ~coupling not published: this tether's own throttle.
  ros::Publisher tf_pub_;            ///< /tf: the spool outlet and the cable's vehicle end.
  tf2_msgs::TFMessage transforms_;
  ros::Publisher marker_pub_;
  ros::Publisher legend_pub_;   ///< ~legend: the colour legend image, latched.
  ros::Time next_marker_time_;  ///< When ~markers are due next (with subscribers).
  std::vector<double> tensions_;
  visualization_msgs::MarkerArray markers_;
};

}  // namespace rov_tether::ros_layer
