#pragma once

#include <Eigen/Geometry>
#include <boost/circular_buffer.hpp>

namespace rov_tether::ros_layer
{

/**
 * The vehicle's recent poses (its origin and orientation in the world frame) with their times, so that
 * what the physics computes at its own time, behind the latest pose, is put together with the pose of
 * that time: the lever arm and the vehicle frame of the pull on the vehicle. Positions are interpolated
 * linearly and orientations by slerp, as the core interpolates the attachment point. Fixed capacity,
 * so adding allocates nothing; ROS-free.
 */
class VehicleHistory
{
 public:
  /// Poses kept (64 bytes each); the oldest go first when it is full (the core refuses more than 4096
  /// waiting ahead).
  static constexpr std::size_t kCapacity = 4200;

  VehicleHistory() : poses_(kCapacity) {}

  /// Adds the pose at time t [s]; times must not decrease (a pose at the same time replaces the last).
  void add(double t, const Eigen::Isometry3d& pose);
  /// The pose at time t [s]: interpolated between the two around it, the first before the first, the
  /// last after the last; identity when empty. Drops the poses no longer needed for times >= t.
  Eigen::Isometry3d at(double t);
  void clear() { poses_.clear(); }
  bool empty() const { return poses_.empty(); }

 private:
  struct Timed
  {
    double time;
    Eigen::Vector3d position;
    Eigen::Quaterniond orientation;
  };
  boost::circular_buffer<Timed> poses_;
};

}  // namespace rov_tether::ros_layer
