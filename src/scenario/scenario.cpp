#include "rov_tether/scenario/scenario.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "rov_tether/scenario/world_spec.hpp"

namespace rov_tether
{

namespace
{

/// `points`' `value` at time t, piecewise-linear (pathAt, wrenchAt): the last point at or before t found by
/// bisection (times never decrease: the readers refuse a path or schedule going back), held before the first
/// (and for a t that is NaN) and after the last.
template <typename Point, typename Value>
Value interpolated(const std::vector<Point>& points, Value Point::*value, double t)
{
  if (points.empty())
  {
    return Value::Zero();
  }
  if (!(t >= points.front().time))
  {
    return points.front().*value;
  }
  const auto after = std::upper_bound(points.begin(), points.end(), t,
                                      [](double time, const Point& point) { return time < point.time; });
  if (after == points.end())
  {
    return points.back().*value;
  }
  const Point& a = *(after - 1);  // a.time <= t < b.time
  const Point& b = *after;
  const double alpha = (t - a.time) / (b.time - a.time);
  return a.*value + alpha * (b.*value - a.*value);
}

}  // namespace

Position pathAt(const std::vector<Waypoint>& path, double t) { return interpolated(path, &Waypoint::position, t); }

Wrench wrenchAt(const std::vector<WrenchPoint>& schedule, double t)
{
  return interpolated(schedule, &WrenchPoint::wrench, t);
}

Position Scenario::vehicleAt(double t) const { return pathAt(vehicle, t); }

bool Scenario::hasDynamicVehicle() const
{
  return dynamic.has_value() ||
         std::any_of(tethers.begin(), tethers.end(), [](const ScenarioTether& t) { return t.dynamic.has_value(); });
}

std::string Scenario::checkOutputRate() const
{
  for (const ScenarioTether& tether : tetherList())
  {
    const double step = tether.params.time_step;
    if (output_rate * step > 1.0 + 1e-9)
    {
      char text[320];
      std::snprintf(text, sizeof text,
                    "output_rate = %g rows per s is faster than %s's steps (time_step = %g s: %g per s); a row "
                    "between two steps would repeat the last step's state: output_rate must be at most %g",
                    output_rate, tethers.empty() ? "the tether" : ("tether '" + tether.name + "'").c_str(), step,
                    1.0 / step, 1.0 / step);
      return text;
    }
  }
  return "";
}

std::string Scenario::checkRunSize() const
{
  const double outputs = std::floor(duration * output_rate + 1e-9) + 1.0;
  double particles = 0.0, substeps = 0.0;
  for (const ScenarioTether& tether : tetherList())
  {
    const TetherParams p = tether.params.resolved();
    // shape.csv writes the cable that is out: all of it at most, what is laid out at the start when locked.
    const double segments = static_cast<double>(p.segmentCount());
    particles += (p.winch_mode == WinchMode::kLocked
                      ? std::min(segments, std::ceil(p.initial_deployed_length / p.segment_length - 1e-9))
                      : segments) +
                 1.0;
    substeps += std::ceil(duration / p.time_step) * p.substeps;
  }
  char text[400];
  if (outputs * particles > kMaxShapeRows)
  {
    std::snprintf(text, sizeof text,
                  "shape.csv would hold up to %.3g rows (%.0f output times, duration x output_rate, x %.0f particles "
                  "with all the cable out a winch may pay out), more than %.0e (some 60 GB): lower output_rate or "
                  "duration, or lengthen segment_length or shorten cable_length",
                  outputs * particles, outputs, particles, kMaxShapeRows);
    return text;
  }
  if (substeps > kMaxSubSteps)
  {
    std::snprintf(text, sizeof text,
                  "the run would take %.3g sub-steps (duration / time_step x substeps, over the tethers), more than "
                  "%.0e (hours to days): shorten duration, or lengthen time_step or lower substeps",
                  substeps, kMaxSubSteps);
    return text;
  }
  return "";
}

std::vector<ScenarioTether> Scenario::tetherList() const
{
  if (!tethers.empty())
  {
    return tethers;
  }
  ScenarioTether one;
  one.name = "tether";
  one.params = params;
  one.spool = spool;
  one.vehicle = vehicle;
  one.dynamic = dynamic;
  return {one};
}

Tether PathDriver::makeSimulation() const
{
  ScenarioTether one;
  one.params = params_;
  one.spool = spool_;
  one.vehicle = vehicle_;
  return makeTether(one);
}

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
