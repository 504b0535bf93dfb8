#include "rov_tether/scenario/scenario.hpp"

#include <algorithm>
#include <string>

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

Wrench wrenchAt(const std::vector<WrenchPoint>& schedule, double t)
{
  if (schedule.empty())
  {
    return Wrench::Zero();
  }
  if (t < schedule.front().time)
  {
    return schedule.front().wrench;
  }
  for (std::size_t k = schedule.size(); k-- > 0;)
  {
    if (schedule[k].time <= t)
    {
      if (k + 1 == schedule.size())
      {
        return schedule[k].wrench;
      }
      const WrenchPoint& a = schedule[k];
      const WrenchPoint& b = schedule[k + 1];
      const double alpha = (t - a.time) / (b.time - a.time);
      return a.wrench + alpha * (b.wrench - a.wrench);
    }
  }
  return schedule.front().wrench;
}

Position Scenario::vehicleAt(double t) const { return pathAt(vehicle, t); }

std::vector<ScenarioTether> Scenario::tetherList() const
{
  if (!tethers.empty())
  {
    return tethers;
  }
  return {ScenarioTether{"tether", params, spool, vehicle, dynamic}};
}

Tether PathDriver::makeSimulation() const { return makeTether(ScenarioTether{"", params_, spool_, vehicle_, {}}); }

const std::vector<Waypoint>& PathDriver::noPath()
{
  static const std::vector<Waypoint> none;
  return none;
}

bool PathDriver::fedUpTo(double t) const
{
  return vehicle_.empty() || static_cast<double>(fed_samples_) * kSampleInterval >= t + kSampleInterval;
}

Status PathDriver::feed(Tether& sim, double t, double* reach)
{
  if (fedUpTo(t))
  {
    *reach = t;
    return Status::success();
  }
  for (int k = 0; k < 100 && static_cast<double>(fed_samples_) * kSampleInterval < t + kSampleInterval; ++k)
  {
    const double sample_time = static_cast<double>(++fed_samples_) * kSampleInterval;
    const Status fed = sim.addVehicleSample(sample_time, pathAt(vehicle_, sample_time));
    if (!fed.ok)
    {
      return Status::error("vehicle path at t = " + std::to_string(sample_time) + " s: " + fed.message);
    }
  }
  *reach = std::min(t, static_cast<double>(fed_samples_ - 1) * kSampleInterval);
  return Status::success();
}

Status PathDriver::advanceTo(Tether& sim, double t)
{
  // Feed and advance in chunks of 100 samples, so a long interval never overfills the simulation's
  // sample buffer; the result is the same as feeding everything first.
  while (!fedUpTo(t))
  {
    double reach = t;
    Status status = feed(sim, t, &reach);
    if (status.ok)
    {
      status = sim.advanceTo(reach);
    }
    if (!status.ok)
    {
      return status;
    }
  }
  return sim.advanceTo(t);
}

}  // namespace rov_tether
