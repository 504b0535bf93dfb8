#pragma once
// A fixed-rate camera's frame times, on the grid k / rate of physics time. No ROS: tested without a master.

#include <cmath>
#include <vector>

namespace rov_tether::ros_layer
{

/**
 * The frame times of a camera at a fixed `rate` [Hz]: the multiples of 1 / rate of physics time, each
 * once, as the tether shapes kept come to cover them. It starts at the first grid time at or after the
 * newest shape, and starts there again when its next time lies outside what the shapes can reach: older
 * than the oldest shape (the camera fell behind the shapes kept), or more than one period past the newest
 * (physics time went back: a bag played in a loop, a clock reset). Without the latter the camera waited,
 * silent, for the physics to come back to its old schedule.
 */
class FrameSchedule
{
 public:
  /// How due() found the schedule.
  enum class Start
  {
    kKept,       ///< going on as it was
    kFirst,      ///< started for the first time (or after reset())
    kRestarted,  ///< its next time was outside the shapes: started again at the newest
  };

  explicit FrameSchedule(double rate) : rate_(rate) {}

  /// Forgets the schedule: the next due() starts it afresh (kFirst).
  void reset() { next_ = -1.0; }
  /// Physics time of the next frame [s]; < 0 before the start.
  double next() const { return next_; }

  /// The grid times [s] now due, oldest first, with the shapes covering [oldest, newest] [s]; `start` (may
  /// be null) says whether the schedule started, or started again, on this call.
  std::vector<double> due(double oldest, double newest, Start* start = nullptr)
  {
    Start how = Start::kKept;
    if (next_ < 0.0)
    {
      how = Start::kFirst;
    }
    // 1e-6 s: the grid times' rounding at ROS times of 2^32 s is below 5e-7 s.
    else if (next_ < oldest || next_ > newest + 1.0 / rate_ + 1e-6)
    {
      how = Start::kRestarted;
    }
    if (how != Start::kKept)
    {
      next_ = std::ceil(newest * rate_ - 1e-9) / rate_;
    }
    std::vector<double> times;
    while (next_ <= newest + 1e-9)
    {
      times.push_back(next_);
      next_ = std::round(next_ * rate_ + 1.0) / rate_;
    }
    if (start != nullptr)
    {
      *start = how;
    }
    return times;
  }

 private:
  double rate_;         ///< [Hz]
  double next_ = -1.0;  ///< Physics time of the next frame [s]; < 0: not started.
};

}  // namespace rov_tether::ros_layer
