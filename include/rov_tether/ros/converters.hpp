#pragma once

#include <geometry_msgs/WrenchStamped.h>
#include <ros/time.h>
#include <tf2_msgs/TFMessage.h>

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "rov_tether/GetTension.h"
#include "rov_tether/TetherCoupling.h"
#include "rov_tether/TetherState.h"
#include "rov_tether/Topology.h"
#include "rov_tether/core/tether.hpp"
#include "rov_tether/core/world.hpp"

namespace rov_tether::ros_layer
{

/// Fills a TetherState from the simulation; `tensions` are its segment tensions (spool first) [N].
void toStateMessage(const Tether& sim, const std::vector<double>& tensions, const ros::Time& stamp,
                    const std::string& frame_id, double measured_winch_speed, std::uint32_t resets, TetherState* msg);

/// The world's topology report (World::topology) as a ~topology message: objects and tethers by name,
/// kinds by topologyKindName. Reuses `msg`'s storage.
void toTopologyMessage(const World& world, const std::vector<TopologyEntry>& entries, const ros::Time& stamp,
                       const std::string& frame_id, Topology* msg);

/// The tether's tf frames at `stamp`: the spool outlet (`spool_frame`) and the cable's vehicle end, its
/// last particle (`end_frame`), as children of `world_frame` with the world's axes; an empty name leaves
/// that frame out. Reuses `message`'s storage.
void toTransforms(const Tether& sim, const ros::Time& stamp, const std::string& world_frame,
                  const std::string& spool_frame, const std::string& end_frame, tf2_msgs::TFMessage* message);

/// `pull` [N] in `frame_id` (the world frame), with its torque about the vehicle origin [N m]: the lever arm
/// is `attachment_offset` (vehicle frame) turned by the orientation of `vehicle`, the vehicle's pose at the
/// time of the force (the physics' time).
geometry_msgs::WrenchStamped toWrench(const Force& pull, const Eigen::Isometry3d& vehicle,
                                      const Eigen::Vector3d& attachment_offset, const ros::Time& stamp,
                                      const std::string& frame_id);

/// The same pull in the vehicle's own frame `vehicle_frame`, as a vehicle simulator applies it: force
/// R^T pull and torque attachment_offset x R^T pull, R the orientation of `vehicle` at the force's time.
geometry_msgs::WrenchStamped toVehicleWrench(const Force& pull, const Eigen::Isometry3d& vehicle,
                                             const Eigen::Vector3d& attachment_offset, const ros::Time& stamp,
                                             const std::string& vehicle_frame);

/// ~coupling: `linearisation` (Tether::vehicleEndLinearisation) stamped with its physics time, in `frame_id`
/// (the world frame); F0 is `pull` (Tether::vehicleForce(), what ~wrench gives: no push from a compressed
/// end segment, the half segment's weight always), K and C row-major.
void toCouplingMessage(const EndLinearisation& linearisation, const Force& pull, const std::string& frame_id,
                       TetherCoupling* message);

/// Answers a GetTension request from the simulation and its segment tensions.
void answerGetTension(const Tether& sim, const std::vector<double>& tensions, const GetTension::Request& request,
                      GetTension::Response* response);

}  // namespace rov_tether::ros_layer
