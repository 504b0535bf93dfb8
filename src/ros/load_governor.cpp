#include "rov_tether/ros/load_governor.hpp"

#include <ros/console.h>

#include <algorithm>
#include <cstdio>

namespace rov_tether::ros_layer
{
namespace
{

std::string iterationsText(int iterations, int configured)
{
  return "iterations " + std::to_string(iterations) + " of " + std::to_string(configured);
}

std::string markersText(double rate)
{
  char text[32];
  std::snprintf(text, sizeof(text), "markers at %.3g Hz", rate);  // 100, 12.5, 6.25
  return text;
}

}  // namespace

LoadGovernor::LoadGovernor(const NodeOptions& options, int configured_iterations, const std::string& label)
    : options_(options),
      label_(label.empty() ? "" : " " + label),
      configured_iterations_(configured_iterations),
      marker_rate_(options.marker_rate)
{
}

void LoadGovernor::reconfigured(int iterations)
{
  configured_iterations_ = iterations;
  marker_rate_ = options_.marker_rate;
  degraded_.clear();
}

void LoadGovernor::update(double physics_wall, const ros::WallTime& wall_now, Tether& tether)
{
  if (window_start_.isZero())
  {
    window_start_ = wall_now;
  }
  window_physics_ += physics_wall;
  const double window = (wall_now - window_start_).toSec();
  if (window < 1.0)
  {
    return;
  }
  physics_load_ = window_physics_ / window;
  marker_load_ = window_markers_ / window;
  window_start_ = wall_now;
  window_physics_ = 0.0;
  window_markers_ = 0.0;
  const double load = physics_load_ + marker_load_;
  if (load > options_.cpu_budget)
  {
    degrade(tether);
  }
  else if (load < 0.5 * options_.cpu_budget && !degraded_.empty())
  {
    recover(tether);
  }
}

void LoadGovernor::degrade(Tether& tether)
{
  if (options_.overload_policy == "reduce_iterations" && tether.params().iterations > options_.min_iterations)
  {
    TetherParams params = tether.params();
    params.iterations = std::max(options_.min_iterations, params.iterations * 3 / 4);
    const Status status = tether.setParams(params);
    if (status.ok)
    {
      degraded_ = iterationsText(params.iterations, configured_iterations_);
    }
    else
    {
      // Only the iterations changed, to at least min_iterations, which is read within iterations' own
      // range [1, 1000]: not refused in practice. Were it, the tether keeps its iterations and the log says why.
      if (reduce_log_.due())
      {
        ROS_WARN("tether_node%s: reducing iterations to %d refused: %s", label_.c_str(), params.iterations,
                 status.message.c_str());
      }
    }
  }
  else if (options_.overload_policy == "reduce_markers" && marker_rate_ > 1.0 && marker_load_ > 0.0)
  {
    marker_rate_ = std::max(1.0, marker_rate_ / 2.0);
    degraded_ = markersText(marker_rate_);
  }
  if (load_log_.due())
  {
    ROS_WARN("tether_node%s: physics and markers use %.1f%% + %.1f%% of the wall time (cpu_budget %.3g%%): %s",
             label_.c_str(), 100 * physics_load_, 100 * marker_load_, 100 * options_.cpu_budget,
             degraded_.empty() ? "nothing left to give up (overload_policy)" : ("degraded to " + degraded_).c_str());
  }
}

void LoadGovernor::recover(Tether& tether)
{
  if (options_.overload_policy == "reduce_iterations" && tether.params().iterations < configured_iterations_)
  {
    TetherParams params = tether.params();
    params.iterations = std::min(configured_iterations_, params.iterations * 4 / 3 + 1);
    const Status status = tether.setParams(params);
    if (status.ok)
    {
      degraded_ =
          params.iterations < configured_iterations_ ? iterationsText(params.iterations, configured_iterations_) : "";
    }
    else
    {
      // Between the current and the configured iterations, both accepted before: not refused in practice.
      if (restore_log_.due())
      {
        ROS_WARN("tether_node%s: restoring iterations to %d refused: %s", label_.c_str(), params.iterations,
                 status.message.c_str());
      }
    }
  }
  else if (options_.overload_policy == "reduce_markers" && marker_rate_ < options_.marker_rate)
  {
    marker_rate_ = std::min(options_.marker_rate, marker_rate_ * 2.0);
    degraded_ = marker_rate_ < options_.marker_rate ? markersText(marker_rate_) : "";
  }
  if (degraded_.empty())
  {
    ROS_INFO("tether_node%s: load back to %.0f%%, degradation undone", label_.c_str(), 100 * physics_load_);
  }
}

}  // namespace rov_tether::ros_layer
