#pragma once
// The one reader of a `cameras` list, for the node (parameter server, converted to YAML) and the scenario
// runner (YAML files) alike: the same fields, naming rule, checks and messages.

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <string>
#include <vector>

#include "rov_tether/spec/camera_spec.hpp"

namespace rov_tether::spec
{

/// How a camera is placed, which decides the fields it may have.
enum class CameraMount
{
  /// The node's: it looks from a tf optical `frame`, takes its intrinsics from `info_topic` or the fixed
  /// width, height, K, D, and renders at the stamps of `image_topic` or at `rate`.
  kTfFrame,
  /// A scenario's: it rides on the vehicle at `position` and `orientation` and renders at `rate` with the
  /// fixed width, height, K, D.
  kVehicle,
};

/// Largest distance of a vehicle camera from the vehicle's centre in each axis [m], and largest angle [deg].
constexpr double kMaxCameraOffset = 100.0;
constexpr double kMaxCameraAngle = 360.0;

/// Reads the list `cameras`: each entry's fields for `mount` and its name (see CameraSpec::name). Returns ""
/// or the first problem, naming the entry, the field, the value and what is allowed; `cameras` is set only
/// on success. Names (unique, none a tether's) are the world's to check: validateWorldSpec (world_spec.hpp).
[[nodiscard]] std::string readCameras(const YAML::Node& node, CameraMount mount, std::vector<CameraSpec>* cameras);

}  // namespace rov_tether::spec
