#include "rov_tether/scenario/scenario_stepper.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

namespace rov_tether
{
namespace
{

/// The longest stretch of simulated time advanced in one call of World::advanceTo [s]: 2.5 of the longest
/// time_step (0.1 s), and 1 ms of CPU for the demo's dive.
constexpr double kStretch = 0.25;

/// One path driver per tether, in scenario order (a dynamic vehicle's gets no samples: VehicleDriver).
std::vector<PathDriver> driversOf(const std::vector<ScenarioTether>& tethers)
{
  std::vector<PathDriver> drivers;
  drivers.reserve(tethers.size());
  for (const ScenarioTether& tether : tethers)
  {
    drivers.emplace_back(tether);
  }
  return drivers;
}

}  // namespace

ScenarioStepper::ScenarioStepper(const Scenario& scenario, World& world)
    : named_(!scenario.tethers.empty()),
      tethers_(scenario.tetherList()),
      world_(world),
      drivers_(driversOf(tethers_)),
      released_(tethers_.size(), false)
{
  for (std::size_t i = 0; i < tethers_.size(); ++i)
  {
    if (tethers_[i].dynamic)
    {
      vehicles_.emplace_back(i, VehicleDriver(tethers_[i]));
    }
  }
}

bool ScenarioStepper::releaseVehicle(std::size_t i)
{
  if (i >= tethers_.size() || !tethers_[i].dynamic)
  {
    return false;
  }
  released_[i] = true;
  return true;
}

bool ScenarioStepper::advance(double t)
{
  const auto start = std::chrono::steady_clock::now();
  if (!vehicles_.empty())
  {
    const bool advanced = advanceStepByStep(t);
    cpu_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return advanced;
  }
  for (;;)
  {
    bool fed = true;
    double reach = t;
    for (std::size_t i = 0; i < drivers_.size(); ++i)
    {
      if (!drivers_[i].fedUpTo(t))
      {
        fed = false;
        double fed_to = t;
        const Status status = drivers_[i].feed(world_.tether(i), t, &fed_to);
        if (!status.ok)
        {
          run_error_ = (named_ ? "tether " + tethers_[i].name + ": " : "") + status.message;
          return false;
        }
        reach = std::min(reach, fed_to);
      }
    }
    if (fed)
    {
      break;
    }
    if (!advanceWorld(reach))
    {
      return false;
    }
  }
  if (!advanceWorld(t))
  {
    return false;
  }
  cpu_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return true;
}
void ScenarioStepper::observe(const std::vector<RunObserver*>& observers, double until)
{
  while (observer_error_.empty() && run_error_.empty())
  {
    RunObserver* next = nullptr;
    for (RunObserver* observer : observers)
    {
      if (observer->nextTime() <= until + 1e-9 && (!next || observer->nextTime() < next->nextTime()))
      {
        next = observer;
      }
    }
    if (next == nullptr || !advance(next->nextTime()))
    {
      return;
    }
    observer_error_ = next->observe(world_.tether(0));
  }
}
bool ScenarioStepper::advanceStepByStep(double t)
{
  for (;;)
  {
    double next = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < world_.size(); ++i)
    {
      if (world_.tether(i).stepFits(t))
      {
        next = std::min(next, world_.tether(i).nextStepTime());
      }
    }
    if (!std::isfinite(next))
    {
      return advanceWorld(t);
    }
    if (!feedUpTo(next))
    {
      return false;
    }
    for (auto& [i, driver] : vehicles_)
    {
      Tether& sim = world_.tether(i);
      if (!released_[i] && sim.stepFits(next))
      {
        const Status set = driver.beforeStep(sim);
        if (!set.ok)
        {
          run_error_ = (named_ ? "tether " + tethers_[i].name + ": " : "") + set.message;
          return false;
        }
      }
    }
    if (!advanceWorld(next))
    {
      return false;
    }
  }
}
bool ScenarioStepper::feedUpTo(double t)
{
  for (std::size_t i = 0; i < drivers_.size(); ++i)
  {
    while (!drivers_[i].fedUpTo(t))
    {
      double reach = t;
      const Status status = drivers_[i].feed(world_.tether(i), t, &reach);
      if (!status.ok)
      {
        run_error_ = (named_ ? "tether " + tethers_[i].name + ": " : "") + status.message;
        return false;
      }
    }
  }
  return true;
}
bool ScenarioStepper::advanceWorld(double t)
{
  // In stretches of at most kStretch, so that an interrupt is seen within one (World::advanceTo steps the same
  // steps in the same order whether it is called once or in stretches: each tether's grid is its own).
  // A target the world refuses, an empty world, or one that did not move in a whole stretch (every tether's next
  // step ending past it: none is that long) goes to World::advanceTo whole.
  bool whole = !(std::abs(t) <= Tether::kMaxTime) || world_.size() == 0;
  for (;;)
  {
    if (interrupt_ != nullptr && *interrupt_ != 0)
    {
      interrupted_ = true;
      char line[96];
      std::snprintf(line, sizeof line, "interrupted at t = %.6g s", world_.time());
      run_error_ = line;
      return false;
    }
    const double before = world_.time();
    const double to = whole ? t : std::min(t, before + kStretch);
    const Status status = world_.advanceTo(to, nullptr, step_observer_);
    if (!status.ok)
    {
      run_error_ = status.message;
      return false;
    }
    if (to >= t || whole)
    {
      return true;
    }
    whole = !(world_.time() > before);
  }
}
}  // namespace rov_tether
