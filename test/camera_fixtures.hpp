#pragma once
// Cameras shared by the camera tests (test_camera.cpp, test_camera_raster.cpp).
#include <utility>
#include <vector>

#include "rov_tether/spec/camera_intrinsics.hpp"

namespace rov_tether::camera::test
{

/// A pinhole camera of width x height px with focal length f px and the principal point at the image centre;
/// `d` its distortion (plumb_bob).
inline CameraIntrinsics pinhole(int width, int height, double f, std::vector<double> d = {})
{
  CameraIntrinsics c;
  c.width = width;
  c.height = height;
  c.K = {f, 0.0, 0.5 * (width - 1), 0.0, f, 0.5 * (height - 1), 0.0, 0.0, 1.0};
  c.D = std::move(d);
  return c;
}

/// A strong barrel distortion of a wide lens (a GoPro-like calibration), invertible over the image, whose
/// image rows bend far from straight.
inline const std::vector<double> kBarrel = {-0.28, 0.09, 0.0012, -0.0008, -0.012};

}  // namespace rov_tether::camera::test
