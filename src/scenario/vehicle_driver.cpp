#include "rov_tether/scenario/vehicle_driver.hpp"

#include <cstdio>
#include <stdexcept>

namespace rov_tether
{

const char* const kVehicleCsvHeader =
    "t,x,y,z,qw,qx,qy,qz,u,v,w,p,q,r,thrust_x,thrust_y,thrust_z,thrust_k,thrust_m,thrust_n,saturated,"
    "tether_fx,tether_fy,tether_fz,tether_mx,tether_my,tether_mz,tether_tension";

VehicleBody startBody(const DynamicVehicle& vehicle)
{
  VehicleBody body;
  if (!body.setParams(vehicle.params).ok ||
      !body.setState(vehicle.start, Eigen::Quaterniond(Eigen::AngleAxisd(vehicle.start_yaw, Eigen::Vector3d::UnitZ())),
                     Twist::Zero())
           .ok)
  {
    throw std::invalid_argument("dynamic vehicle: parameters or start not valid (the reader checks them)");
  }
  return body;
}

Position startAttachment(const DynamicVehicle& vehicle)
{
  return vehicle.start + Eigen::AngleAxisd(vehicle.start_yaw, Eigen::Vector3d::UnitZ()) * vehicle.attachment_offset;
}

std::string attachDynamicVehicle(const ScenarioTether& tether, Tether* sim, std::string* warning)
{
  warning->clear();
  if (!tether.dynamic)
  {
    return "";
  }
  if (tether.params.solver != SolverType::kDirect)
  {
    return "vehicle: a dynamic vehicle is coupled only by the direct solver, and this tether's solver is " +
           toString(tether.params.solver) + " (set params.solver: direct)";
  }
  const Status attached = sim->attachVehicleBody(startBody(*tether.dynamic), tether.dynamic->attachment_offset);
  if (attached.ok && !attached.message.empty())
  {
    *warning = "vehicle: " + attached.message;  // out of reach, in other water than the cable's
  }
  return attached.ok ? "" : "vehicle: " + attached.message;
}

VehicleDriver::VehicleDriver(const ScenarioTether& tether) : vehicle_(*tether.dynamic), path_(tether.vehicle)
{
  const Status configured = controller_.configure(vehicle_.params, vehicle_.controller);
  if (!configured.ok)
  {
    throw std::invalid_argument("vehicle: controller: " + configured.message);
  }
}

Status VehicleDriver::beforeStep(Tether& sim)
{
  const double t0 = sim.time();
  const double t1 = sim.nextStepTime();
  if (!usesController())
  {
    return sim.setVehicleThrust(wrenchAt(vehicle_.wrench, t0));
  }
  const VehicleBody* body = sim.vehicleBody();
  if (body == nullptr)
  {
    return Status::error("vehicle: the tether's vehicle end is not dynamic");
  }
  VehicleSetpoint setpoint;
  setpoint.position = pathAt(path_, t1);
  setpoint.velocity = pathVelocityAt(path_, t1);
  setpoint.yaw = vehicle_.start_yaw;
  const Status updated = controller_.update(t1 - t0, setpoint, *body, &output_);
  return updated.ok ? sim.setVehicleThrust(output_.thrust) : updated;
}

std::uint8_t VehicleDriver::saturatedAxes(const Tether& sim) const
{
  const ThrustUsed* used = sim.vehicleThrustUsed();
  const std::uint8_t held = used != nullptr ? used->saturated_axes : 0;
  return usesController() ? static_cast<std::uint8_t>(output_.saturated_axes | held) : held;
}

Eigen::Vector3d pathVelocityAt(const std::vector<Waypoint>& path, double t)
{
  for (std::size_t k = path.size(); k-- > 0;)
  {
    if (path[k].time <= t)
    {
      if (k + 1 == path.size() || !(path[k + 1].time > path[k].time))
      {
        return Eigen::Vector3d::Zero();
      }
      return (path[k + 1].position - path[k].position) / (path[k + 1].time - path[k].time);
    }
  }
  return Eigen::Vector3d::Zero();
}

void writeVehicleRow(std::FILE* file, double t_out, const Tether& sim, const VehicleDriver& driver)
{
  const VehicleBody& body = *sim.vehicleBody();
  const Eigen::Quaterniond& q = body.attitude();
  const Twist& nu = body.velocity();
  const ThrustUsed* used = sim.vehicleThrustUsed();
  const Wrench thrust = used != nullptr ? used->applied : Wrench::Zero();
  // The pull at the attachment point as a body-frame wrench about the body origin: [R^T F; r x R^T F].
  const Force pull = sim.vehicleForce();
  const Eigen::Vector3d force = q.conjugate() * pull;
  const Eigen::Vector3d moment = driver.vehicle().attachment_offset.cross(force);
  std::fprintf(file, "%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,", t_out,
               body.position().x(), body.position().y(), body.position().z(), q.w(), q.x(), q.y(), q.z(), nu[0], nu[1],
               nu[2], nu[3], nu[4], nu[5]);
  std::fprintf(file, "%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%u,", thrust[0], thrust[1], thrust[2], thrust[3], thrust[4],
               thrust[5], static_cast<unsigned>(driver.saturatedAxes(sim)));
  std::fprintf(file, "%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n", force.x(), force.y(), force.z(), moment.x(), moment.y(),
               moment.z(), pull.norm());
}

}  // namespace rov_tether
