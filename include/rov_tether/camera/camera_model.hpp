#pragma once

#include <Eigen/Core>
#include <functional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "rov_tether/spec/camera_intrinsics.hpp"

namespace rov_tether::camera
{

/// A rectangle in normalised image coordinates (x / z, y / z in the optical frame).
struct RayBounds
{
  double x_min, x_max, y_min, y_max;
};

/// Whether a build in progress is no longer wanted (asked between stretches of rows).
using BuildAbandoned = std::function<bool()>;

/// Thrown by CameraModel's constructor when its `abandoned` said so part-way.
class CameraBuildAbandoned : public std::runtime_error
{
 public:
  CameraBuildAbandoned() : std::runtime_error("the camera's build was abandoned") {}
};

/**
 * A calibrated pinhole camera with plumb_bob distortion: projection of points (OpenCV's projectPoints
 * model) and, once per calibration, the ray through every pixel centre (the distortion inverted), with
 * what the renderer needs to find the pixels whose rays fall in a region: each row's band of y, and the
 * columns of a row between two values of x (the rays' x grows along each row for any calibration that
 * does not fold; where it would not, the lookups return whole rows and columns, which is slow but right).
 */
class CameraModel
{
 public:
  /// Columns per block of a row whose band of y is kept (rowYBetween).
  static constexpr int kBandColumns = 32;
  /// Rows of a distorted image whose rays are found between two questions to `abandoned` (some 40 ms of a
  /// 1920x1080 camera, whose 1080 rows took 2.6 s in camera.test).
  static constexpr int kRowsPerStretch = 16;

  /// Throws std::invalid_argument naming the field when the intrinsics are invalid, or when D cannot be
  /// inverted over the image (the radial distortion folds over within it). `abandoned`, when given, is asked
  /// before each kRowsPerStretch rows whose distortion is inverted (seconds for a large distorted camera) and
  /// once before the row tables; when it says so, the constructor throws CameraBuildAbandoned.
  explicit CameraModel(const CameraIntrinsics& intrinsics, const BuildAbandoned& abandoned = {});

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
  /// The rays of row v have y in [rowYMin(v), rowYMax(v)].
  double rowYMin(int v) const { return row_y_[2 * v]; }
  double rowYMax(int v) const { return row_y_[2 * v + 1]; }
  /// The rays of row v in columns [first, last] have y in the returned (min, max) (a little wider: the
  /// bands of the kBandColumns-wide blocks of columns that hold them).
  std::pair<double, double> rowYBetween(int v, int first, int last) const;
  /// The rows [first, last] that may hold rays with y in [y_lo, y_hi]; first > last when none.
  std::pair<int, int> rowsBetween(double y_lo, double y_hi) const;
  /// The columns [first, last] of row v whose rays have x in [x_lo, x_hi]; first > last when none. `near`,
  /// when it holds columns (first in [0, width], last in [-1, width - 1]), is a guess to start from.
  std::pair<int, int> columnsBetween(int v, double x_lo, double x_hi, std::pair<int, int> near = {-1, -2}) const;

 private:
  void computeRays(const BuildAbandoned& abandoned);
  void computeRowTables();

  CameraIntrinsics intrinsics_;
  std::array<double, 5> d_;  ///< k1, k2, p1, p2, k3
  std::vector<float> rays_;
  RayBounds bounds_{};
  double max_focal_ = 0.0;
  std::vector<double> row_y_;   ///< Each row's (min, max) of the rays' y.
  std::vector<float> block_y_;  ///< Each row's blocks' (min, max) of the rays' y, row by row.
  int blocks_ = 0;              ///< Blocks of kBandColumns columns per row.
  bool rows_sorted_ = false;    ///< The rays' x grows along every row.
  bool bands_sorted_ = false;   ///< rowYMin and rowYMax never decrease down the image.
};

}  // namespace rov_tether::camera
