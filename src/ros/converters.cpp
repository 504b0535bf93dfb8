#include "rov_tether/ros/converters.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>

namespace rov_tether::ros_layer
{

void toStateMessage(const Tether& sim, const std::vector<double>& tensions, const ros::Time& stamp,
                    const std::string& frame_id, double measured_winch_speed, std::uint32_t resets, TetherState* msg)
{
  const TetherParams& p = sim.params();
  msg->header.stamp = stamp;
  msg->header.frame_id = frame_id;
  msg->deployed_length = sim.deployedLength();
  msg->cable_length = p.cable_length;
  msg->segment_tension.assign(tensions.begin(), tensions.end());
  const TetherSummary summary = sim.summarize(tensions);
  msg->tension_spool = summary.tension_spool;
  msg->tension_vehicle = summary.tension_vehicle;
  const auto vector3 = [](const Force& f, geometry_msgs::Vector3& out) { out.x = f.x(), out.y = f.y(), out.z = f.z(); };
  vector3(summary.spool_force, msg->spool_force);
  vector3(summary.vehicle_force, msg->vehicle_force);
  msg->max_tension = summary.max_tension;
  msg->max_tension_segment = static_cast<std::uint32_t>(summary.max_tension_segment);
  msg->max_tension_arc_length = tensions.empty() ? 0.0 : sim.arcLengthFromVehicleToSegment(summary.max_tension_segment);
  msg->winch_mode = toString(p.winch_mode);
  msg->winch_speed = measured_winch_speed;
  msg->target_length = sim.targetLength();
  msg->brake_tension = p.brake_tension;
  msg->target_tension = p.target_tension;
  msg->winch_outrun = sim.winchOutrun();
  msg->residual_stretch = summary.mean_strain;
  msg->max_strain = summary.max_strain;
  msg->solver = toString(p.solver);
  msg->iterations = static_cast<std::uint32_t>(p.iterations);
  msg->drag = p.drag;
  msg->noise = p.noise;
  msg->vehicle_attached = sim.vehicleAttached();
  msg->jumps = static_cast<std::uint32_t>(sim.jumpCount());
  msg->resets = resets;
}

void toTopologyMessage(const World& world, const std::vector<TopologyEntry>& entries, const ros::Time& stamp,
                       const std::string& frame_id, Topology* msg)
{
  msg->header.stamp = stamp;
  msg->header.frame_id = frame_id;
  msg->entries.resize(entries.size());
  for (std::size_t k = 0; k < entries.size(); ++k)
  {
    const TopologyEntry& entry = entries[k];
    TopologyValue& out = msg->entries[k];
    out.tether = world.name(entry.tether);
    out.object_is_tether = entry.object_is_tether;
    out.object = entry.object_is_tether ? world.name(entry.object) : world.obstacle(entry.object).name();
    out.kind = topologyKindName(entry.kind);
    out.value = entry.value;
  }
}

void toTransforms(const Tether& sim, const ros::Time& stamp, const std::string& world_frame,
                  const std::string& spool_frame, const std::string& end_frame, tf2_msgs::TFMessage* message)
{
  message->transforms.clear();
  const std::pair<const std::string*, Position> frames[] = {
      {&spool_frame, sim.particle(0)}, {&end_frame, sim.particle(sim.deployedParticleCount() - 1)}};
  for (const auto& [name, at] : frames)
  {
    if (name->empty())
    {
      continue;
    }
    geometry_msgs::TransformStamped t;
    t.header.stamp = stamp;
    t.header.frame_id = world_frame;
    t.child_frame_id = *name;
    t.transform.translation.x = at.x();
    t.transform.translation.y = at.y();
    t.transform.translation.z = at.z();
    t.transform.rotation.w = 1.0;
    message->transforms.push_back(t);
  }
}

namespace
{

geometry_msgs::WrenchStamped wrenchMessage(const Eigen::Vector3d& force, const Eigen::Vector3d& torque,
                                           const ros::Time& stamp, const std::string& frame_id)
{
  geometry_msgs::WrenchStamped wrench;
  wrench.header.stamp = stamp;
  wrench.header.frame_id = frame_id;
  wrench.wrench.force.x = force.x();
  wrench.wrench.force.y = force.y();
  wrench.wrench.force.z = force.z();
  wrench.wrench.torque.x = torque.x();
  wrench.wrench.torque.y = torque.y();
  wrench.wrench.torque.z = torque.z();
  return wrench;
}

}  // namespace

geometry_msgs::WrenchStamped toWrench(const Force& pull, const Eigen::Isometry3d& vehicle,
                                      const Eigen::Vector3d& attachment_offset, const ros::Time& stamp,
                                      const std::string& frame_id)
{
  const Eigen::Vector3d lever = vehicle.rotation() * attachment_offset;
  return wrenchMessage(pull, lever.cross(pull), stamp, frame_id);
}

geometry_msgs::WrenchStamped toVehicleWrench(const Force& pull, const Eigen::Isometry3d& vehicle,
                                             const Eigen::Vector3d& attachment_offset, const ros::Time& stamp,
                                             const std::string& vehicle_frame)
{
  const Eigen::Vector3d force = vehicle.rotation().transpose() * pull;
  return wrenchMessage(force, attachment_offset.cross(force), stamp, vehicle_frame);
}

void toCouplingMessage(const EndLinearisation& linearisation, const Force& pull, const std::string& frame_id,
                       TetherCoupling* message)
{
  message->header.stamp = ros::Time(std::max(linearisation.time, 0.0));
  message->header.frame_id = frame_id;
  message->force.x = pull.x();
  message->force.y = pull.y();
  message->force.z = pull.z();
  message->position.x = linearisation.position.x();
  message->position.y = linearisation.position.y();
  message->position.z = linearisation.position.z();
  message->velocity.x = linearisation.velocity.x();
  message->velocity.y = linearisation.velocity.y();
  message->velocity.z = linearisation.velocity.z();
  for (int row = 0; row < 3; ++row)
  {
    for (int col = 0; col < 3; ++col)
    {
      message->stiffness[3 * row + col] = linearisation.stiffness(row, col);
      message->damping[3 * row + col] = linearisation.damping(row, col);
    }
  }
  message->horizon = linearisation.horizon;
  message->taut = linearisation.taut;
}

void answerGetTension(const Tether& sim, const std::vector<double>& tensions, const GetTension::Request& request,
                      GetTension::Response* response)
{
  const TetherSummary summary = sim.summarize(tensions);
  response->deployed_length = summary.deployed_length;
  response->tension_spool = summary.tension_spool;
  response->tension_vehicle = summary.tension_vehicle;
  response->max_tension = summary.max_tension;
  response->max_tension_segment = static_cast<std::uint32_t>(summary.max_tension_segment);

  // The empty request (`rosservice call .../get_tension "{}"`: both fields 0) asks for the vehicle end.
  const bool empty = request.arc_length_from_vehicle == 0.0 && request.segment == 0;
  const bool by_arc = request.arc_length_from_vehicle >= 0.0;
  const bool by_segment = request.segment >= 0 && !empty;
  if (by_arc == by_segment)
  {
    response->success = false;
    response->message = "give exactly one of arc_length_from_vehicle >= 0 [m] or segment >= 0 (set the other to -1)";
    return;
  }
  std::size_t segment = 0;
  if (by_arc && !sim.segmentAtArcLengthFromVehicle(request.arc_length_from_vehicle, &segment))
  {
    char message[160];
    std::snprintf(message, sizeof(message), "arc_length_from_vehicle = %g m is outside the deployed cable [0, %g] m",
                  request.arc_length_from_vehicle, sim.deployedLength());
    response->success = false;
    response->message = message;
    return;
  }
  if (by_segment)
  {
    segment = static_cast<std::size_t>(request.segment);
    if (segment >= tensions.size())
    {
      response->success = false;
      response->message = "segment = " + std::to_string(request.segment) + " is outside [0, " +
                          std::to_string(static_cast<long>(tensions.size()) - 1) + "]";
      return;
    }
  }
  response->success = true;
  response->segment = static_cast<std::uint32_t>(segment);
  response->tension = tensions[segment];
  response->message = "";
}

}  // namespace rov_tether::ros_layer
