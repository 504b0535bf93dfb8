#include "rov_tether/core/contact_substeps.hpp"

#include <cmath>

namespace rov_tether
{

void StepMotion::start(const Cable& cable)
{
  x_.assign(cable.x.begin(), cable.x.end());  // same size every step: no allocation
  y_.assign(cable.y.begin(), cable.y.end());
  z_.assign(cable.z.begin(), cable.z.end());
  first_ = cable.first;
}

double StepMotion::fastest(const Cable& cable) const
{
  double fastest2 = 0.0;
  const std::size_t n = std::min(cable.size(), x_.size());
  // Particles paid out during the step were on the drum at its start, and the outlet (pinned) jumps along
  // the cable when one is reeled in: neither is motion.
  for (std::size_t i = std::max(cable.first, first_) + 1; i < n; ++i)
  {
    const double dx = cable.x[i] - x_[i], dy = cable.y[i] - y_[i], dz = cable.z[i] - z_[i];
    fastest2 = std::max(fastest2, dx * dx + dy * dy + dz * dz);
  }
  return std::sqrt(fastest2);
}

void ContactSubstepPolicy::plan(double motion, double diameter, int substeps)
{
  last_motion_ = std::isfinite(motion) ? motion : 0.0;
  next_ = ask(motion, diameter, substeps);
  deepest_ = 0.0;
}

int ContactSubstepPolicy::ask(double motion, double diameter, int substeps) const
{
  // The motion rule: at most kMotionShareOfRadius of the radius (half the diameter) in each sub-step.
  const double allowed = kMotionShareOfRadius * 0.5 * diameter;
  if (!(motion < allowed * kMaxSubsteps))
  {
    return std::isfinite(motion) ? kMaxSubsteps : 1;
  }
  const int for_motion = std::max(1, static_cast<int>(std::ceil(motion / allowed)));
  // The depth rule: the pull-in scales as (last_ / n)^2 at n sub-steps instead of last_.
  const double aimed = kAimedPullInShare * diameter;
  const double ratio = std::sqrt(deepest_ / aimed);
  int for_depth = static_cast<int>(std::min<double>(kMaxSubsteps, std::ceil(last_ * ratio)));
  if (for_depth < last_)
  {
    // One fewer only when the pull predicted for it stays below the aim.
    const int fewer = last_ - 1;
    const double predicted = deepest_ * (static_cast<double>(last_) / std::max(fewer, 1)) *
                             (static_cast<double>(last_) / std::max(fewer, 1));
    for_depth = predicted < aimed ? fewer : last_;
  }
  const int floor = std::max(for_motion, substeps);
  return std::min({kMaxSubsteps, kDepthFactor * floor, std::max(floor, for_depth)});
}

}  // namespace rov_tether
