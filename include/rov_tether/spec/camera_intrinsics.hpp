#pragma once
// A pinhole camera's intrinsics as sensor_msgs/CameraInfo holds them. Plain data and checks only (no
// OpenCV, no ROS): the description of a camera (spec), the camera library and the node share it, so it
// sits with the descriptions, below both scenario and camera.

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace rov_tether::camera
{

/**
 * Image size, camera matrix K (3x3, row-major, as CameraInfo.K) and plumb_bob distortion D = (k1, k2, p1,
 * p2, k3) (as CameraInfo.D with distortion_model "plumb_bob"; empty means none). Pixel (u, v) is the
 * centre of column u and row v, as in OpenCV and CameraInfo. The optical frame is REP 103's: z forward,
 * x right, y down.
 */
struct CameraIntrinsics
{
  int width = 0;   ///< [px]
  int height = 0;  ///< [px]
  std::array<double, 9> K{};
  std::vector<double> D;  ///< plumb_bob: 0, 4 or 5 coefficients (k3 = 0 when 4).

  /// Largest image side accepted [px].
  static constexpr int kMaxSide = 16384;
  /// Most pixels accepted, 4096 x 4096: building a camera takes some 40 bytes a pixel (its rays, and the
  /// distortion's inversion), so 16384 x 16384, within kMaxSide, would need more than 10 GB.
  static constexpr long kMaxPixels = 4096L * 4096L;

  double fx() const { return K[0]; }
  double fy() const { return K[4]; }
  double skew() const { return K[1]; }
  double cx() const { return K[2]; }
  double cy() const { return K[5]; }
  /// The five plumb_bob coefficients (zeros where D is shorter).
  std::array<double, 5> plumbBob() const
  {
    std::array<double, 5> d{};
    for (std::size_t i = 0; i < D.size() && i < d.size(); ++i)
    {
      d[i] = D[i];
    }
    return d;
  }
  bool distorted() const
  {
    for (double d : D)
    {
      if (d != 0.0)
      {
        return true;
      }
    }
    return false;
  }

  /// Every problem, each naming the field (after `prefix`), its value and what is allowed; empty when
  /// valid. Whether D can be inverted over the image is checked by CameraModel.
  std::vector<std::string> validate(const std::string& prefix = "") const
  {
    std::vector<std::string> errors;
    const auto number = [](double v) { return std::to_string(v); };
    if (width < 1 || width > kMaxSide)
    {
      errors.push_back(prefix + "width = " + std::to_string(width) + ": must be in [1, 16384] px");
    }
    if (height < 1 || height > kMaxSide)
    {
      errors.push_back(prefix + "height = " + std::to_string(height) + ": must be in [1, 16384] px");
    }
    if (width >= 1 && height >= 1 && static_cast<long>(width) * height > kMaxPixels)
    {
      errors.push_back(prefix + "width x height = " + std::to_string(width) + " x " + std::to_string(height) + " = " +
                       std::to_string(static_cast<long>(width) * height) +
                       " px: at most 4096 x 4096 = 16777216 px (a camera takes some 40 bytes a pixel to build)");
    }
    for (std::size_t i = 0; i < K.size(); ++i)
    {
      if (!std::isfinite(K[i]))
      {
        errors.push_back(prefix + "K[" + std::to_string(i) + "] = " + number(K[i]) + ": must be finite");
        return errors;
      }
    }
    if (!(fx() > 0.0) || !(fy() > 0.0))
    {
      errors.push_back(prefix + "K: fx = K[0] = " + number(fx()) + " and fy = K[4] = " + number(fy()) +
                       " must be > 0 px");
    }
    if (K[3] != 0.0 || K[6] != 0.0 || K[7] != 0.0 || K[8] != 1.0)
    {
      errors.push_back(prefix + "K = [fx, s, cx, 0, fy, cy, 0, 0, 1]: K[3], K[6], K[7] must be 0 and K[8] 1");
    }
    if (std::abs(cx() - 0.5 * width) > width || std::abs(cy() - 0.5 * height) > height)
    {
      errors.push_back(prefix + "K: principal point (" + number(cx()) + ", " + number(cy()) +
                       ") px must lie within one image size of the image centre");
    }
    if (D.size() != 0 && D.size() != 4 && D.size() != 5)
    {
      errors.push_back(prefix + "D: " + std::to_string(D.size()) +
                       " coefficients; plumb_bob has 5 (k1, k2, p1, p2, k3), or 4, or none");
    }
    for (std::size_t i = 0; i < D.size(); ++i)
    {
      if (!std::isfinite(D[i]) || std::abs(D[i]) > 1e3)
      {
        errors.push_back(prefix + "D[" + std::to_string(i) + "] = " + number(D[i]) + ": must be in [-1000, 1000]");
      }
    }
    return errors;
  }

  bool operator==(const CameraIntrinsics& other) const
  {
    return width == other.width && height == other.height && K == other.K && plumbBob() == other.plumbBob();
  }
  bool operator!=(const CameraIntrinsics& other) const { return !(*this == other); }
};

}  // namespace rov_tether::camera
