#pragma once

#include <string>
#include <vector>

#include "rov_tether/camera/camera_intrinsics.hpp"
#include "rov_tether/tether.hpp"
#include "rov_tether/tether_params.hpp"

namespace rov_tether
{

/// A vehicle waypoint: time [s] and attachment position [m].
struct Waypoint
{
  double time;
  Position position;
};

/// A camera carried by the vehicle, for the offline dataset of its tether masks (the runner writes
/// DIR/cameras/<name>/; see the camera library's DatasetWriter).
struct ScenarioCamera
{
  std::string name;                                    ///< Directory name: letters, digits, '_' and '-'.
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< In the vehicle frame (x forward, z up) [m].
  /// Roll, pitch, yaw of the camera in the vehicle frame [deg], of a frame whose x axis looks along the
  /// view and z is up (pitch > 0 looks down); the image's optical frame (z forward, x right, y down)
  /// follows from it.
  Eigen::Vector3d orientation = Eigen::Vector3d::Zero();
  double rate = 10.0;  ///< Frames per simulated second [Hz].
  camera::CameraIntrinsics intrinsics;
};

/**
 * An offline run: parameters, spool, vehicle path, duration and output rate.
 *
 * YAML form (z up):
 *   params: {iterations: 5, drag: 0.9}   # any model parameter; missing ones take defaults
 *   spool: [x, y, z]                    # [m]
 *   vehicle: [[t, x, y, z], ...]        # [s, m]; followed piecewise-linearly; omit for a free end
 *   duration: 20.0                      # [s]
 *   output_rate: 10.0                   # rows per simulated second
 *   cameras: [{name, position, orientation, rate, width, height, K, D}]   # optional, see ScenarioCamera
 */
struct Scenario
{
  std::string description;
  TetherParams params;
  Position spool = Position::Zero();
  std::vector<Waypoint> vehicle;  ///< Empty: the tether hangs from its spool with a free end.
  double duration = 0.0;
  double output_rate = 10.0;
  std::vector<ScenarioCamera> cameras;  ///< On the vehicle; only with a vehicle path.

  /// Vehicle position at time t [s]: piecewise-linear, held before the first and after the last
  /// waypoint; at two waypoints with the same time the later one wins from that time on (a jump).
  Position vehicleAt(double t) const;
};

/**
 * Feeds a scenario's vehicle path into a simulation as a pose stream would: samples every 10 ms, a
 * little ahead of the simulation, so the simulation interpolates between them.
 */
class PathDriver
{
 public:
  explicit PathDriver(const Scenario& scenario) : scenario_(scenario) {}
  /// A simulation set up for the scenario: spool, parameters, vehicle at its t = 0 position.
  Tether makeSimulation() const;
  /// Feeds the path up to t (plus one sample interval) and advances the simulation to t [s].
  void advanceTo(Tether& sim, double t);
  /// Interval between fed samples [s].
  static constexpr double kSampleInterval = 0.01;

 private:
  const Scenario& scenario_;
  std::uint64_t fed_samples_ = 0;  ///< Samples fed so far; sample k is at k * kSampleInterval.
};

}  // namespace rov_tether
