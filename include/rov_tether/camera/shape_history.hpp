#pragma once

#include <cstddef>
#include <vector>

#include "rov_tether/core/tether.hpp"

namespace rov_tether::camera
{

/**
 * The last shapes of one tether and their physics times, so that a camera image can see the tether as it
 * was at the image's stamp: the shape is interpolated between the two recorded shapes around it. Ring
 * storage sized once (positions kept as float, 12 bytes per particle and shape); recording allocates
 * nothing once every slot has held a cable of that size.
 */
class ShapeHistory
{
 public:
  /// Keeps shapes over `span` [s], at most one per `min_interval` [s] (ones closer to the last are skipped).
  explicit ShapeHistory(double span = 1.0, double min_interval = 0.005);

  /// Records `tether`'s deployed shape at its time(). A time before the newest clears the history first
  /// (a reset or a clock jump).
  void record(const Tether& tether);
  void clear() { count_ = 0; }
  bool empty() const { return count_ == 0; }
  double oldest() const;  ///< [s]; only when !empty()
  double newest() const;  ///< [s]; only when !empty()

  /// The deployed shape at time t [s] (spool first) into `out`: each particle interpolated linearly
  /// between the recorded shapes before and after t. A particle released in between sits at the earlier
  /// shape's spool outlet there. Returns false, leaving `out` alone, when t is outside [oldest, newest].
  bool shapeAt(double t, std::vector<Position>& out) const;

 private:
  struct Entry
  {
    double time = 0.0;
    std::size_t first = 0;   ///< Index of the spool outlet in the whole cable.
    std::size_t total = 0;   ///< Particles of the whole cable (deployed or not).
    std::vector<float> xyz;  ///< Deployed particles, spool first.
  };
  const Entry& at(std::size_t k) const { return entries_[(start_ + k) % entries_.size()]; }
  Position positionOf(const Entry& e, std::size_t index) const;

  double span_;
  double min_interval_;
  std::vector<Entry> entries_;
  std::size_t start_ = 0;  ///< Ring index of the oldest entry.
  std::size_t count_ = 0;
};

}  // namespace rov_tether::camera
