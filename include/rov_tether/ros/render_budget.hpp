#pragma once

#include <algorithm>
#include <cstdio>
#include <string>

namespace rov_tether::ros_layer
{

/**
 * The wall time one camera may spend drawing a frame, on the node's one thread (the physics waits
 * meanwhile). The cost of a frame is its pixels times the wall time per pixel this camera last measured;
 * a frame predicted to take longer than the budget is skipped, and why() says so. The first frame of a
 * camera is always drawn (nothing measured yet): it measures the cost.
 *
 * A cost measured once while the machine was busy would otherwise skip every later frame of that size for
 * good (nothing drawn, nothing measured again). So a camera skipping frames draws one again after
 * kFirstRetry [s] of skipping, to measure again, then after twice as long each time it is still too slow,
 * up to kLastRetry: a frame that really is too big stalls the node once in ten minutes at most.
 */
class RenderBudget
{
 public:
  static constexpr double kFirstRetry = 10.0;  ///< [s] of skipping before a frame is drawn to measure again.
  static constexpr double kLastRetry = 600.0;  ///< [s] the longest wait between such frames.

  /// `budget` [s] per frame (the node's max_lag: a longer render would make the physics skip ahead).
  explicit RenderBudget(double budget) : budget_(budget) {}

  /// Whether a frame of `pixels` fits the budget at wall time `now` [s]; when not, why() says why.
  bool allows(double pixels, double now)
  {
    predicted_ = pixels * seconds_per_pixel_;
    if (predicted_ <= budget_)
    {
      skipping_since_ = -1.0;
      return true;
    }
    if (skipping_since_ < 0.0)
    {
      skipping_since_ = now;
    }
    if (now - skipping_since_ >= retry_)
    {
      skipping_since_ = -1.0;  // drawn to measure again; skipping starts over from the measurement
      retry_ = std::min(2.0 * retry_, kLastRetry);
      return true;
    }
    return false;
  }
  /// A frame of `pixels` took `seconds` [s] of wall time to draw and publish.
  void measured(double pixels, double seconds)
  {
    if (pixels > 0.0 && seconds >= 0.0)
    {
      seconds_per_pixel_ = seconds / pixels;
      if (seconds <= budget_)
      {
        retry_ = kFirstRetry;
      }
    }
  }
  /// Why the last frame allows() refused was skipped.
  std::string why(int width, int height) const
  {
    char text[240];
    std::snprintf(text, sizeof(text),
                  "a %dx%d frame would take about %.2f s to draw, more than its budget of %.2f s (max_lag): "
                  "skipped, and drawn again to measure in %.0f s (give the camera fewer pixels)",
                  width, height, predicted_, budget_, retry_);
    return text;
  }
  double budget() const { return budget_; }
  /// [s] how long a camera skips frames before it draws one to measure again (kFirstRetry, doubling).
  double retry() const { return retry_; }

 private:
  double budget_;                   ///< [s]
  double seconds_per_pixel_ = 0.0;  ///< Measured on this camera's last frame drawn [s].
  double predicted_ = 0.0;          ///< For the last allows() [s].
  double skipping_since_ = -1.0;    ///< [s] wall time of the first frame skipped in a row; negative: none.
  double retry_ = kFirstRetry;      ///< [s] of skipping before the next frame drawn to measure again.
};

}  // namespace rov_tether::ros_layer
