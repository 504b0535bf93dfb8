#include "rov_tether/scenario/scenario.hpp"

#include <algorithm>

#include "rov_tether/scenario/world_spec.hpp"

namespace rov_tether
{

Position pathAt(const std::vector<Waypoint>& path, double t)
{
  if (path.empty())
  {
    return Position::Zero();
  }
  if (t < path.front().time)
  {
    return path.front().position;
  }
  for (std::size_t k = path.size(); k-- > 0;)
  {
    if (path[k].time <= t)
    {
      if (k + 1 == path.size())
      {
        return path[k].position;
      }
      const Waypoint& a = path[k];
      const Waypoint& b = path[k + 1];
      const double alpha = (t - a.time) / (b.time - a.time);
      return a.position + alpha * (b.position - a.position);
    }
  }
  return path.front().position;
}

Position Scenario::vehicleAt(double t) const { return pathAt(vehicle, t); }

std::vector<ScenarioTether> Scenario::tetherList() const
{
  if (!tethers.empty())
  {
    return tethers;
  }
  return {ScenarioTether{"tether", params, spool, vehicle}};
}

Tether PathDriver::makeSimulation() const { return makeTether(ScenarioTether{"", params_, spool_, vehicle_}); }

bool PathDriver::fedUpTo(double t) const
{
  return vehicle_.empty() || static_cast<double>(fed_samples_) * kSampleInterval >= t + kSampleInterval;
}

double PathDriver::feed(Tether& sim, double t)
{
  if (fedUpTo(t))
  {
    return t;
  }
  for (int k = 0; k < 100 && static_cast<double>(fed_samples_) * kSampleInterval < t + kSampleInterval; ++k)
  {
    const double sample_time = static_cast<double>(++fed_samples_) * kSampleInterval;
    sim.addVehicleSample(sample_time, pathAt(vehicle_, sample_time));
  }
  return std::min(t, static_cast<double>(fed_samples_ - 1) * kSampleInterval);
}

void PathDriver::advanceTo(Tether& sim, double t)
{
  // Feed and advance in chunks of 100 samples, so a long interval never overfills the simulation's
  // sample buffer; the result is the same as feeding everything first.
  while (!fedUpTo(t))
  {
    sim.advanceTo(feed(sim, t));
  }
  sim.advanceTo(t);
}

}  // namespace rov_tether
