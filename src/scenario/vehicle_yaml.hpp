#pragma once
// The scenario reader's `vehicle:` (private to rov_tether_scenario_yaml): a path of waypoints (a kinematic
// vehicle, as always) or a block {model: kinematic | dynamic, ...} (docs/runner.md, "A dynamic vehicle").

#include <yaml-cpp/yaml.h>

#include <optional>
#include <string>
#include <vector>

#include "rov_tether/scenario/scenario.hpp"

namespace rov_tether::scenario_yaml
{

/// Reads a vehicle path of [t, x, y, z] waypoints; "" or a message naming `field`.
[[nodiscard]] std::string readPath(const YAML::Node& path, const std::string& field, std::vector<Waypoint>* vehicle);

/**
 * Reads a tether's `vehicle:` named `field`: a list is a kinematic vehicle's path (readPath); a map is a block
 * with `model: kinematic` (then only `path`) or `model: dynamic` with `params` (a vehicle file, relative to
 * `base_dir`, or a map: spec::readVehicleParams), `start: [x, y, z, yaw]` (default: the path's first point,
 * heading 0), `attachment_offset: [x, y, z]` (body frame, default 0), exactly one of `path` (the controller's
 * setpoints) and `wrench: [[t, Fx, Fy, Fz, Mx, My, Mz], ...]` (body frame; then no controller), and
 * `controller` (only with a path: spec::readControllerGains, replacing the params' own block). Unknown keys,
 * non-finite numbers and every contradiction are refused, naming the field. `path` and `dynamic` are set only
 * on success.
 */
[[nodiscard]] std::string readVehicle(const YAML::Node& node, const std::string& field, const std::string& base_dir,
                                      std::vector<Waypoint>* path, std::optional<DynamicVehicle>* dynamic);

}  // namespace rov_tether::scenario_yaml
