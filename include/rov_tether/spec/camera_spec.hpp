#pragma once
// One camera as a world's description holds it (WorldSpec::cameras): plain data, no YAML and no ROS, so the
// scenario layer's WorldSpec can hold it; read by spec::readCameras (camera_reader.hpp).

#include <Eigen/Core>
#include <string>

// Plain data and checks only (header-only, no OpenCV): the spec library does not link the camera library.
#include "rov_tether/spec/camera_intrinsics.hpp"

namespace rov_tether::spec
{

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

}  // namespace rov_tether::spec
