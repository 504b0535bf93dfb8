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
 */
class RenderBudget
{
 public:
  /// `budget` [s] per frame (the node's max_lag: a longer render would make the physics skip ahead).
  explicit RenderBudget(double budget) : budget_(budget) {}

  /// Whether a frame of `pixels` fits the budget; when not, why() says why.
  bool allows(double pixels)
  {
    predicted_ = pixels * seconds_per_pixel_;
    return predicted_ <= budget_;
  }
  /// A frame of `pixels` took `seconds` [s] of wall time to draw and publish.
  void measured(double pixels, double seconds)
  {
    if (pixels > 0.0 && seconds >= 0.0)
    {
      seconds_per_pixel_ = seconds / pixels;
    }
  }
  /// Why the last frame allows() refused was skipped.
  std::string why(int width, int height) const
  {
    char text[200];
    std::snprintf(text, sizeof(text),
                  "a %dx%d frame would take about %.2f s to draw, more than its budget of %.2f s (max_lag): "
                  "skipped (give the camera fewer pixels)",
                  width, height, predicted_, budget_);
    return text;
  }
  double budget() const { return budget_; }

 private:
  double budget_;                   ///< [s]
  double seconds_per_pixel_ = 0.0;  ///< Measured on this camera's last frame drawn [s].
  double predicted_ = 0.0;          ///< For the last allows() [s].
};

}  // namespace rov_tether::ros_layer
