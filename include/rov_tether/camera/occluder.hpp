#pragma once
// What can hide the tether from a camera. The renderer asks each occluder for the depth of its nearest
// surface on the ray of every pixel where it drew the tether, and keeps the tether only where it is
// nearer. The seabed is one; an obstacle (a mesh, a pile, another vehicle) is another implementation.

#include <Eigen/Core>
#include <limits>

namespace rov_tether::camera
{

/**
 * Something opaque in the world. depthOnRay is called once per tether pixel (never per image pixel),
 * so an implementation may ray-cast exactly; it must be thread-compatible (const, no shared state).
 */
class Occluder
{
 public:
  virtual ~Occluder() = default;
  /// The first point of the occluder on the ray origin + t direction, t > 0, as t [m]. Both are in the
  /// world frame [m]; direction's component along the camera's optical axis is 1, so t is the depth along
  /// the optical axis. +inf when the ray misses; 0 when the origin is inside the occluder.
  virtual double depthOnRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const = 0;
};

/// The flat seabed of the model (`seabed_z`, world frame, z up): everything below the plane is hidden.
class SeabedOccluder : public Occluder
{
 public:
  explicit SeabedOccluder(double seabed_z) : seabed_z_(seabed_z) {}
  double depthOnRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const override
  {
    if (origin.z() <= seabed_z_)
    {
      return 0.0;  // a camera in the ground sees nothing
    }
    if (direction.z() >= 0.0)
    {
      return std::numeric_limits<double>::infinity();
    }
    return (seabed_z_ - origin.z()) / direction.z();
  }
  double seabedZ() const { return seabed_z_; }

 private:
  double seabed_z_;
};

}  // namespace rov_tether::camera
