#pragma once

#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "rov_tether/core/obstacle.hpp"
#include "rov_tether/core/tether.hpp"
#include "rov_tether/core/tether_params.hpp"
#include "rov_tether/core/vehicle_controller.hpp"
#include "rov_tether/core/vehicle_params.hpp"
#include "rov_tether/spec/camera_spec.hpp"

namespace rov_tether
{

/// A vehicle waypoint: time [s] and attachment position [m].
struct Waypoint
{
  double time;
  Position position;
};

/// A camera carried by the vehicle, for the offline dataset of its tether masks (the runner writes
/// DIR/cameras/<name>/; see the camera library's DatasetWriter): the one description of a camera
/// (spec::readCameras with CameraMount::kVehicle: name, position and orientation in the vehicle frame, rate,
/// intrinsics; the node's cameras use its tf fields instead).
using ScenarioCamera = spec::CameraSpec;

/// Position on a piecewise-linear path at time t [s]: held before the first and after the last waypoint;
/// at two waypoints with the same time the later one wins from that time on (a jump). Zero for no path.
Position pathAt(const std::vector<Waypoint>& path, double t);

/// A body-frame thrust command at a time: time [s], wrench [Fx, Fy, Fz, Mx, My, Mz] [N, N m].
struct WrenchPoint
{
  double time;
  Wrench wrench;
};

/// The thrust of a schedule at time t [s], as pathAt: piecewise-linear, held before the first and after the last
/// point; at two points with the same time the later one wins from that time on. Zero for no schedule.
Wrench wrenchAt(const std::vector<WrenchPoint>& schedule, double t);

/// A dynamic vehicle at a tether's end (the runner's `vehicle: {model: dynamic, ...}`): a VehicleBody coupled
/// into the `direct` solver's step (Tether::attachVehicleBody), driven by a thrust schedule or, following the
/// tether's vehicle path as its setpoint, by the built-in controller.
struct DynamicVehicle
{
  VehicleParams params;
  ControllerGains controller;                                   ///< Used when `wrench` is empty.
  Position start = Position::Zero();                            ///< The body origin at t = 0, world frame [m].
  double start_yaw = 0.0;                                       ///< Heading at t = 0 [rad]; the controller holds it.
  Eigen::Vector3d attachment_offset = Eigen::Vector3d::Zero();  ///< The tether's attachment, body frame [m].
  std::vector<WrenchPoint> wrench;  ///< Non-empty: the thrust command, and no controller runs.
};

/// One tether of a scenario's `tethers:` list: its own parameters, spool and vehicle path.
struct ScenarioTether
{
  std::string name;  ///< Directory name under the output directory (isTetherName: the node's rule too).
  TetherParams params;
  Position spool = Position::Zero();
  /// Empty: a free end (or a dynamic vehicle under a thrust schedule). With `dynamic`, the controller's
  /// setpoints; otherwise the kinematic vehicle's positions.
  std::vector<Waypoint> vehicle;
  std::optional<DynamicVehicle> dynamic = std::nullopt;  ///< A dynamic vehicle; none: the kinematic end of `vehicle`.
  /// Non-empty: the spool rides on the dynamic vehicle of the tether of this name (a TMS; `spool: {on: name,
  /// outlet_offset: [x, y, z]}`), which is listed before this one; `spool` is then where the outlet starts.
  std::string spool_on;
  Eigen::Vector3d spool_outlet_offset = Eigen::Vector3d::Zero();  ///< The outlet on that body, body frame [m].
  /// The spool follows a tf frame (the node's spool_frame): `spool` is not where it will be.
  bool spool_moves = false;
  /// The tension above which the run warns of this tether [N] (the node's per-tether option of that name); NaN:
  /// the run's (rov_tether_run --max-tension-warning, 500 N by default).
  double max_tension_warning = std::numeric_limits<double>::quiet_NaN();
};

/**
 * An offline run: parameters, spool, vehicle path, duration and output rate; or several tethers and the
 * obstacles they share, in one World.
 *
 * YAML form (z up):
 *   params: {iterations: 5, drag: 0.9}   # any model parameter; missing ones take defaults
 *   spool: [x, y, z]                    # [m]
 *   vehicle: [[t, x, y, z], ...]        # [s, m]; followed piecewise-linearly; omit for a free end
 *   # or vehicle: {model: dynamic, params, start, attachment_offset, path | wrench, controller} (docs/runner.md)
 *   duration: 20.0                      # [s]
 *   output_rate: 10.0                   # rows per simulated second
 *   cameras: [{name, position, orientation, rate, width, height, K, D}]   # optional, see ScenarioCamera
 *   obstacles: [{name, type, position, orientation, radius, length, size, file, scale, friction}]
 *   tethers: [{name, params, spool, vehicle}]   # instead of the top-level params, spool, vehicle
 *   tether_contact: false               # contact between tethers and of each with itself
 */
struct Scenario
{
  std::string description;
  TetherParams params;
  Position spool = Position::Zero();
  std::vector<Waypoint> vehicle;          ///< Empty: the tether hangs from its spool with a free end.
  std::optional<DynamicVehicle> dynamic;  ///< `vehicle: {model: dynamic, ...}`: see ScenarioTether.
  double duration = 0.0;                  ///< [s]; 0 when a description leaves it out (ScenarioDuration::kOptional).
  double output_rate = 10.0;
  std::vector<ScenarioCamera> cameras;  ///< On the vehicle; only with a vehicle path.
  /// Several tethers in one world, each written to DIR/<name>/; empty: the one tether of params, spool and
  /// vehicle, written to DIR itself.
  std::vector<ScenarioTether> tethers;
  std::vector<ObstacleSpec> obstacles;  ///< Shared by every tether; mesh files resolved to usable paths.
  bool tether_contact = false;          ///< World::setContactBetweenTethers.

  /// Whether the run is a world's (obstacles, a `tethers` list or contact between tethers): then the runner
  /// also writes DIR/topology.csv. Otherwise it writes exactly state.csv and shape.csv, as it always has.
  bool usesWorld() const { return !tethers.empty() || !obstacles.empty() || tether_contact; }
  /// Whether any vehicle is dynamic: the top-level one or one of the `tethers`.
  bool hasDynamicVehicle() const;
  /// "" when every tether steps at least as often as output_rate writes rows, else the error naming the
  /// tether and its time_step (a row between two steps would repeat the last step's state).
  std::string checkOutputRate() const;
  /// "" when the run's size is sane, else the error naming the numbers: shape.csv's rows (output times x every
  /// tether's particles with all its cable out) at most kMaxShapeRows, the sub-steps (duration / time_step x
  /// substeps, over the tethers) at most kMaxSubSteps. A run past either would take days or fill a disk.
  std::string checkRunSize() const;
  static constexpr double kMaxShapeRows = 1e9;  ///< some 60 GB of shape.csv
  static constexpr double kMaxSubSteps = 1e10;  ///< hours at a microsecond a sub-step
  /// The tethers to run: `tethers`, or the one of params, spool and vehicle (named "tether").
  std::vector<ScenarioTether> tetherList() const;

  /// Vehicle position at time t [s]: piecewise-linear, held before the first and after the last
  /// waypoint; at two waypoints with the same time the later one wins from that time on (a jump).
  Position vehicleAt(double t) const;
  /// The frames `camera` renders over the run: one at t = 0 and one every 1 / rate up to the duration.
  std::size_t cameraFrames(const ScenarioCamera& camera) const
  {
    return static_cast<std::size_t>(std::floor(duration * camera.rate + 1e-9)) + 1;
  }
};

/**
 * Feeds a scenario's vehicle path into a simulation as a pose stream would: samples every 10 ms, a
 * little ahead of the simulation, so the simulation interpolates between them.
 */
class PathDriver
{
 public:
  explicit PathDriver(const Scenario& scenario)
      : params_(scenario.params), spool_(scenario.spool), vehicle_(scenario.vehicle)
  {
  }
  /// A dynamic vehicle's path is its controller's setpoints (VehicleDriver), not samples: none are fed.
  explicit PathDriver(const ScenarioTether& tether)
      : params_(tether.params), spool_(tether.spool), vehicle_(tether.dynamic ? noPath() : tether.vehicle)
  {
  }
  /// A simulation set up for the scenario: spool, parameters, vehicle at its t = 0 position (makeTether).
  Tether makeSimulation() const;
  /// Feeds the path up to t (plus one sample interval) and advances the simulation to t [s]. Refuses, and
  /// stops where it was refused, when the simulation refuses a sample or the advance (see feed).
  Status advanceTo(Tether& sim, double t);
  /// Whether every sample up to t (plus one sample interval) is fed (always, without a path).
  bool fedUpTo(double t) const;
  /// Feeds at most 100 further samples towards t (plus one sample interval), so the simulation's sample
  /// buffer never overfills; `reach` gets the time the simulation may advance to with what it holds [s].
  /// advanceTo is: while not fedUpTo(t), advance to reach; then advance to t. Refuses when the simulation
  /// refuses a sample (a path that was not validated: beyond Tether::kMaxCoordinate, or a time beyond
  /// Tether::kMaxTime); the message names the sample's time.
  Status feed(Tether& sim, double t, double* reach);
  /// Interval between fed samples [s].
  static constexpr double kSampleInterval = 0.01;

 private:
  static const std::vector<Waypoint>& noPath();

  const TetherParams& params_;
  const Position& spool_;
  const std::vector<Waypoint>& vehicle_;
  std::uint64_t fed_samples_ = 0;  ///< Samples fed so far; sample k is at k * kSampleInterval.
};

}  // namespace rov_tether
