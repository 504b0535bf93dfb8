#include "rov_tether/scenario.hpp"

#include <algorithm>

namespace rov_tether
{

Position Scenario::vehicleAt(double t) const
{
  if (vehicle.empty())
  {
    return Position::Zero();
  }
  if (t < vehicle.front().time)
  {
    return vehicle.front().position;
  }
  for (std::size_t k = vehicle.size(); k-- > 0;)
  {
    if (vehicle[k].time <= t)
    {
      if (k + 1 == vehicle.size())
      {
        return vehicle[k].position;
      }
      const Waypoint& a = vehicle[k];
      const Waypoint& b = vehicle[k + 1];
      const double alpha = (t - a.time) / (b.time - a.time);
      return a.position + alpha * (b.position - a.position);
    }
  }
  return vehicle.front().position;
}

Tether PathDriver::makeSimulation() const
{
  if (scenario_.vehicle.empty())
  {
    return Tether(scenario_.params, scenario_.spool, 0.0);
  }
  return Tether(scenario_.params, scenario_.spool, scenario_.vehicleAt(0.0), 0.0);
}

void PathDriver::advanceTo(Tether& sim, double t)
{
  if (!scenario_.vehicle.empty())
  {
    // Feed and advance in chunks of 100 samples, so a long interval never overfills the simulation's
    // sample buffer; the result is the same as feeding everything first.
    while (static_cast<double>(fed_samples_) * kSampleInterval < t + kSampleInterval)
    {
      for (int k = 0; k < 100 && static_cast<double>(fed_samples_) * kSampleInterval < t + kSampleInterval; ++k)
      {
        const double sample_time = static_cast<double>(++fed_samples_) * kSampleInterval;
        sim.addVehicleSample(sample_time, scenario_.vehicleAt(sample_time));
      }
      sim.advanceTo(std::min(t, static_cast<double>(fed_samples_ - 1) * kSampleInterval));
    }
  }
  sim.advanceTo(t);
}

}  // namespace rov_tether
