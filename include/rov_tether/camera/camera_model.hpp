#pragma once

#include <Eigen/Core>
#include <vector>

#include "rov_tether/camera/camera_intrinsics.hpp"

namespace rov_tether::camera
{

/// A rectangle in normalised image coordinates (x / z, y / z in the optical frame).
struct RayBounds
{
  double x_min, x_max, y_min, y_max;
};

/**
 * A calibrated pinhole camera with plumb_bob distortion: projection of points (OpenCV's projectPoints
 * model) and, once per calibration, the ray through every pixel centre (the distortion inverted).
 */
class CameraModel
{
 public:
  /// Throws std::invalid_argument naming the field when the intrinsics are invalid, or when D cannot be
  /// inverted over the image (the radial distortion folds over within it).
  explicit CameraModel(const CameraIntrinsics& intrinsics);

  const CameraIntrinsics& intrinsics() const { return intrinsics_; }
  int width() const { return intrinsics_.width; }
  int height() const { return intrinsics_.height; }

  /// Pixel of a point in the optical frame [m] (z > 0), with distortion, as cv::projectPoints [px].
  Eigen::Vector2d project(const Eigen::Vector3d& point) const
  {
    return toPixel(point.x() / point.z(), point.y() / point.z());
  }
  /// Pixel of the normalised coordinates (x, y) = (X / Z, Y / Z), with distortion [px].
  Eigen::Vector2d toPixel(double x, double y) const;
  /// Normalised coordinates of the ray through pixel (u, v)'s centre: its direction is (x, y, 1).
  Eigen::Vector2d ray(int u, int v) const
  {
    const float* r = &rays_[2 * (static_cast<std::size_t>(v) * width() + u)];
    return {r[0], r[1]};
  }
  /// The rays of every pixel, row by row, (x, y) interleaved.
  const float* rays() const { return rays_.data(); }
  /// The smallest rectangle holding every pixel's ray.
  const RayBounds& rayBounds() const { return bounds_; }
  /// Largest focal length [px]: pixels per unit of normalised coordinate, at most.
  double maxFocal() const { return max_focal_; }

 private:
  void computeRays();

  CameraIntrinsics intrinsics_;
  std::array<double, 5> d_;  ///< k1, k2, p1, p2, k3
  std::vector<float> rays_;
  RayBounds bounds_{};
  double max_focal_ = 0.0;
};

}  // namespace rov_tether::camera
