#pragma once
// The one reader of a `cameras` list, for the node (parameter server, converted to YAML) and the scenario
// runner (YAML files) alike: the same fields, naming rule, checks and messages.

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <string>
#include <vector>

// Plain data and checks only (header-only, no OpenCV): the spec library does not link the camera library.
#include "rov_tether/camera/camera_intrinsics.hpp"

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

/// One camera as described (fields not used by its mount keep their defaults).
struct CameraSpec
{
  std::string name;         ///< 1-64 letters, digits or '_', not a digit first (a ROS name and a directory name).
  std::string frame;        ///< kTfFrame: tf optical frame (z forward, x right, y down).
  std::string info_topic;   ///< kTfFrame: sensor_msgs/CameraInfo; "" uses the fixed intrinsics.
  std::string image_topic;  ///< kTfFrame: render at each image's stamp; "" renders at `rate`.
  Eigen::Vector3d position = Eigen::Vector3d::Zero();     ///< kVehicle: in the vehicle frame [m].
  Eigen::Vector3d orientation = Eigen::Vector3d::Zero();  ///< kVehicle: roll, pitch, yaw [deg].
  double rate = 10.0;                                     ///< Frames per second without image_topic [Hz].
  camera::CameraIntrinsics intrinsics;                    ///< The fixed width, height, K, D (without info_topic).
};

/// Largest distance of a vehicle camera from the vehicle's centre in each axis [m], and largest angle [deg].
constexpr double kMaxCameraOffset = 100.0;
constexpr double kMaxCameraAngle = 360.0;

/// Reads the list `cameras`: each entry's fields for `mount`, its name (see CameraSpec::name) unique and
/// not one of `reserved`. Returns "" or the first problem, naming the entry, the field, the value and what
/// is allowed; `cameras` is set only on success.
std::string readCameras(const YAML::Node& node, CameraMount mount, const std::vector<std::string>& reserved,
                        std::vector<CameraSpec>* cameras);

}  // namespace rov_tether::spec
