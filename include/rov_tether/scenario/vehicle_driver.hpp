#pragma once
// A scenario's dynamic vehicle in a run: attached to its tether, its thrust set before every step (a thrust
// schedule, or the built-in controller following the path), and its row of vehicle.csv. No YAML here.

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "rov_tether/core/tether.hpp"
#include "rov_tether/core/vehicle_controller.hpp"
#include "rov_tether/scenario/scenario.hpp"

namespace rov_tether
{

/// The body of `vehicle` at its start: at `start`, level, heading `start_yaw`, at rest.
VehicleBody startBody(const DynamicVehicle& vehicle);
/// Where the tether's end is at the start: the attachment point of startBody, world frame [m].
Position startAttachment(const DynamicVehicle& vehicle);

/// Attaches `tether.dynamic` to `sim` (a tether makeTether made for it: its end at startAttachment). Only the
/// `direct` solver couples a vehicle: another is refused here, naming it. "" or the error. A start out of the
/// cable's reach is taken and said in `warning` ("" when there is nothing to say; printed nowhere: the caller says it).
[[nodiscard]] std::string attachDynamicVehicle(const ScenarioTether& tether, Tether* sim, std::string* warning);

/**
 * Drives one tether's dynamic vehicle (ScenarioTether::dynamic) step by step. Before each step of `sim`,
 * from sim.time() to sim.nextStepTime() = t1, it sets the thrust command (Tether::setVehicleThrust):
 *  - a thrust schedule: wrenchAt(schedule, sim.time()), held over the step;
 *  - otherwise the controller's (VehicleController::update with the step's length) for the setpoint at t1:
 *    the path's position pathAt(path, t1), its velocity there as feed-forward (the slope of the path's
 *    segment; 0 before the first and after the last waypoint), and the start heading.
 * No allocation per step.
 */
class VehicleDriver
{
 public:
  /// `tether` must outlive the driver and hold a dynamic vehicle; its controller gains were checked when
  /// read (configure refuses them otherwise: std::invalid_argument).
  explicit VehicleDriver(const ScenarioTether& tether);

  /// Sets the thrust for the step `sim` takes next. Refuses what the controller or the tether refuses.
  Status beforeStep(Tether& sim);

  /// The axes whose command exceeded the limit in the last step (ThrustUsed's bits: 0 surge ... 5 yaw): the
  /// controller's held output, or the schedule's command the body held.
  std::uint8_t saturatedAxes(const Tether& sim) const;
  bool usesController() const { return vehicle_.wrench.empty(); }
  const VehicleController& controller() const { return controller_; }
  const DynamicVehicle& vehicle() const { return vehicle_; }

 private:
  const DynamicVehicle& vehicle_;
  const std::vector<Waypoint>& path_;
  VehicleController controller_;
  ControllerOutput output_;
};

/// The velocity of a piecewise-linear path at t [m/s]: its segment's slope (at a waypoint, the next
/// segment's); zero before the first and from the last waypoint on, and for a jump.
Eigen::Vector3d pathVelocityAt(const std::vector<Waypoint>& path, double t);

/// vehicle.csv's header, part of the documented format (docs/runner.md).
extern const char* const kVehicleCsvHeader;
/// One row of vehicle.csv at t_out: the body's pose and velocity, the thrust the last step applied, the
/// saturated axes, and the tether's pull on the vehicle as a body-frame wrench about its origin.
void writeVehicleRow(std::FILE* file, double t_out, const Tether& sim, const VehicleDriver& driver);

}  // namespace rov_tether
