#include "rov_tether/ros/scheduler.hpp"

#include <ros/console.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace rov_tether::ros_layer
{
namespace
{

/// Exponential smoothing of diagnostics figures.
double smooth(double previous, double sample) { return previous <= 0.0 ? sample : 0.95 * previous + 0.05 * sample; }

}  // namespace

Scheduler::Scheduler(World& world, double interpolation_delay, WallClock wall_clock)
    : world_(world),
      interpolation_delay_(interpolation_delay),
      delay_(interpolation_delay),
      hold_limit_(interpolation_delay),
      wall_clock_(std::move(wall_clock))
{
}

template <class Call>
void Scheduler::timed(std::size_t i, Call&& call)
{
  const ros::WallTime start = wall_clock_();
  call();
  charge(i, start);
}

void Scheduler::charge(std::size_t i, const ros::WallTime& start)
{
  charged_[i] += std::max(0.0, (wall_clock_() - start).toSec());  // a wall clock set back charges nothing
}

std::size_t Scheduler::add(const NodeOptions& options, TetherHooks& hooks, const std::string& label)
{
  const std::size_t i = tethers_.size();
  tethers_.emplace_back(hooks, options, world_.tether(i).params().iterations, label);
  charged_.push_back(0.0);
  hold_limit_ = std::max(hold_limit_, options.stale_pose_timeout);
  return i;
}

double Scheduler::alignedPhysicsTime(std::size_t i, const ros::Time& now) const
{
  const double dt = world_.tether(i).params().time_step;
  return std::floor((now.toSec() - delay_) / dt) * dt;
}

void Scheduler::restart(std::size_t i, const ros::Time& now, const ros::Time& clock)
{
  // ROS time is finite and far below Tether::kMaxTime, so the reset is not refused; were it, the tether
  // goes on as it is and the log says why.
  const Status status = world_.tether(i).reset(alignedPhysicsTime(i, now));
  if (!status.ok)
  {
    if (tethers_[i].restart_log.due())
    {
      ROS_WARN("tether_node%s: restart refused: %s", tethers_[i].label.c_str(), status.message.c_str());
    }
    return;
  }
  tethers_[i].next_state = 0.0;
  tethers_[i].hooks->restarted(clock);
}

void Scheduler::reset(std::size_t i, const ros::Time& now, const std::string& why) { reset(i, now, now, why); }

void Scheduler::reset(std::size_t i, const ros::Time& now, const ros::Time& clock, const std::string& why)
{
  ROS_WARN("tether_node%s: %s: resetting the tether to %.2f m", tethers_[i].label.c_str(), why.c_str(),
           world_.tether(i).params().initial_deployed_length);
  restart(i, now, clock);
  ++tethers_[i].resets;
  last_time_ = now;
}

void Scheduler::resetAll(const ros::Time& now, const ros::Time& clock, const std::string& why)
{
  delay_ = interpolation_delay_;  // the poses' timing starts over with the tethers
  for (std::size_t i = 0; i < tethers_.size(); ++i)
  {
    timed(i, [&] { reset(i, now, clock, why); });  // re-laying a long cable is its own work
  }
}

void Scheduler::tick(const ros::Time& now)
{
  if (now.isZero())
  {
    return;  // simulated time has not started
  }
  std::fill(charged_.begin(), charged_.end(), 0.0);
  const ros::WallTime wall_now = wall_clock_();
  // The wall time since the last tick: ROS time that passed with it is the node's own stall (a render too
  // big, a slow machine), not a clock that leapt.
  const double wall_gap = last_wall_.isZero() ? 0.0 : std::max(0.0, (wall_now - last_wall_).toSec());
  last_wall_ = wall_now;
  if (!started_)
  {
    started_ = true;
    for (std::size_t i = 0; i < tethers_.size(); ++i)
    {
      timed(i, [&] { restart(i, now, now); });
    }
    last_time_ = now;
  }
  else if (now < last_time_)
  {
    ros::Time at = now;
    for (const auto& tether : tethers_)
    {
      const ros::Time arrival = tether.hooks->earliestArrival();
      if (!arrival.isZero() && arrival < at)
      {
        at = arrival;  // a pose of the new clock, before this tick
      }
    }
    // Restarted at the new clock's first pose, `at`; what arrived after this tick's `now` came on the old clock.
    resetAll(at, now, "time jumped backwards by " + std::to_string((last_time_ - at).toSec()) + " s");
  }
  else if ((now - last_time_).toSec() - wall_gap > kMaxForwardJump)
  {
    resetAll(now, now,
             "time jumped forwards by " + std::to_string((now - last_time_).toSec()) + " s in " +
                 std::to_string(wall_gap) + " s of wall time");
  }
  else if ((now - last_time_).toSec() > kMaxForwardJump)
  {
    ROS_WARN(
        "tether_node: the node itself stalled for %.2f s of wall time (ROS time went on with it: no clock jump); "
        "the physics catches up, or skips ahead beyond max_lag",
        wall_gap);
  }
  for (std::size_t i = 0; i < tethers_.size(); ++i)
  {
    timed(i, [&] { tethers_[i].hooks->beforeAdvance(now); });
  }
  const double target = physicsTarget(now);
  for (std::size_t i = 0; i < tethers_.size(); ++i)
  {
    timed(i, [&] { prepare(i, target, now); });  // a skip ahead holds the cable: its work too
  }
  std::vector<std::uint64_t>& steps_before = ticked_before_;
  steps_before.resize(tethers_.size());
  for (std::size_t i = 0; i < tethers_.size(); ++i)
  {
    steps_before[i] = world_.tether(i).stepCount();
  }
  const ros::WallTime wall_start = wall_now;  // the tick's work from its start: poses taken, skips, steps
  advance(target);
  const ros::WallTime wall_end = wall_clock_();
  account((wall_end - wall_start).toSec(), wall_end, steps_before);
  last_time_ = now;
  for (auto& tether : tethers_)
  {
    tether.hooks->afterAdvance(now);
  }
}

double Scheduler::physicsTarget(const ros::Time& now)
{
  // Poses arrive late, and sparse ones (1 Hz navigation) far apart: running the physics behind ROS time
  // by the largest gap the poses leave lets two of them bracket every step, so the vehicle end moves
  // between them instead of holding and then leaping.
  double wanted = interpolation_delay_;
  double latest = std::numeric_limits<double>::infinity();
  for (const auto& tether : tethers_)
  {
    const TetherHooks::PoseTiming timing = tether.hooks->poseTiming();
    wanted = std::max(wanted, std::min(timing.needed_delay, hold_limit_));
    if (!std::isnan(timing.latest_stamp))
    {
      latest = std::min(latest, timing.latest_stamp);
    }
  }
  const double elapsed = std::max(0.0, (now - last_time_).toSec());
  delay_ = wanted >= delay_ ? wanted : std::max(wanted, delay_ - kDelayShrinkRate * elapsed);
  // Never past the latest pose (the next one will say where the vehicle went), unless it is older than
  // the hold limit: then the vehicle is stale and the physics goes on with it where it was last.
  const double t = now.toSec();
  target_ = std::max(std::min(t - delay_, latest), t - hold_limit_);
  return target_;
}

void Scheduler::prepare(std::size_t i, double target, const ros::Time& now)
{
  TetherSchedule& s = tethers_[i];
  Tether& tether = world_.tether(i);
  const double period = s.state_period;
  if (s.next_state <= 0.0 || s.next_state < target - 1.0)
  {
    s.next_state = std::ceil(std::max(tether.time(), target - 1.0) / period) * period;
  }
  if (target - tether.time() > s.max_lag)
  {
    // Too far behind to catch up: jump ahead with the cable held at rest, and say so.
    const double behind = target - tether.time();
    const double dt = tether.params().time_step;
    const Status skipped = tether.skipTo(std::floor(target / dt) * dt);
    if (!skipped.ok)
    {
      // Only a time before the tether's own can be refused (max_lag shorter than a step): it catches up instead.
      if (s.skip_refused_log.due())
      {
        ROS_WARN("tether_node%s: skip ahead refused: %s", s.label.c_str(), skipped.message.c_str());
      }
      return;
    }
    // The held cable is published at once and the state grid restarts there. Resumed on the old grid,
    // the next state point usually lay past what the next tick could compute before it skipped again,
    // so a node far behind published almost nothing (overload.test under the sanitizers: 0-2 states in
    // 120 s). Now every skip publishes, however slow the physics.
    s.next_state = tether.time();
    ++s.skips;
    s.last_skip_time = now;
    if (s.skip_log.due())
    {
      ROS_ERROR(
          "tether_node%s: the physics fell %.2f s behind real time (more than max_lag = %.2f s): skipped ahead with "
          "the cable held",
          s.label.c_str(), behind, s.max_lag);
    }
  }
}

double Scheduler::nextStop(double target) const
{
  double stop = target;
  for (std::size_t i = 0; i < tethers_.size(); ++i)
  {
    const TetherSchedule& s = tethers_[i];
    if (s.next_state <= stop)
    {
      stop = s.next_state;  // the earliest ~state point due by the target
    }
    const Tether& tether = world_.tether(i);
    if (s.hooks->watchesSteps() && tether.stepFits(stop))
    {
      stop = std::min(stop, tether.nextStepTime());  // the end of its next step, where it is told
    }
  }
  return stop;
}

void Scheduler::advance(double target)
{
  std::vector<std::uint64_t>& steps_before = stepped_before_;
  for (;;)
  {
    const double stop = nextStop(target);
    steps_before.resize(tethers_.size());
    for (std::size_t i = 0; i < tethers_.size(); ++i)
    {
      steps_before[i] = world_.tether(i).stepCount();
    }
    std::size_t taken = 0;
    const Status status = world_.advanceTo(stop, &taken, this);
    if (!status.ok)
    {
      // A target from ROS time is finite and far below Tether::kMaxTime; were one refused, nothing is
      // published for a time the physics did not reach.
      ROS_WARN_THROTTLE(1.0, "tether_node: physics advance refused: %s", status.message.c_str());
      return;
    }
    for (std::size_t i = 0; i < tethers_.size(); ++i)
    {
      if (tethers_[i].hooks->watchesSteps() && world_.tether(i).stepCount() != steps_before[i])
      {
        timed(i, [&] { tethers_[i].hooks->stepped(delay_); });
      }
    }
    bool state_due = false;
    for (std::size_t i = 0; i < tethers_.size(); ++i)
    {
      TetherSchedule& s = tethers_[i];
      if (s.next_state <= stop)
      {
        // Not before time 0: a clock starting at 0 puts the physics interpolation_delay behind it, at negative
        // times, which no stamp can carry (they were clamped to 0: several ~state and tf at stamp 0, tf's
        // TF_REPEATED_DATA).
        if (world_.tether(i).time() >= 0.0)
        {
          timed(i, [&] { s.hooks->publishState(); });
        }
        s.next_state += s.state_period;
        state_due = true;
      }
    }
    // On at a ~state point or a watched step's end short of the target; done at the target, or when a
    // watched step did not fit after all (nothing taken: never loop on the spot).
    if (stop >= target || (!state_due && taken == 0))
    {
      break;
    }
  }
}

void Scheduler::beforeStep(std::size_t /*tether*/) { step_start_ = wall_clock_(); }

void Scheduler::afterStep(std::size_t tether)
{
  if (tether < charged_.size())  // a tether of the world not (yet) scheduled is charged to none
  {
    charge(tether, step_start_);
  }
}

void Scheduler::account(double wall, const ros::WallTime& wall_end, const std::vector<std::uint64_t>& steps_before)
{
  if (tethers_.empty())
  {
    return;
  }
  double measured = 0.0;
  for (const double seconds : charged_)
  {
    measured += seconds;
  }
  // What no tether's own calls took (scheduling, skips, re-lays) is shared evenly.
  const double rest = std::max(0.0, wall - measured) / static_cast<double>(tethers_.size());
  for (std::size_t i = 0; i < tethers_.size(); ++i)
  {
    TetherSchedule& s = tethers_[i];
    Tether& tether = world_.tether(i);
    const double tether_wall = charged_[i] + rest;
    s.governor.update(tether_wall, wall_end, tether);
    const std::uint64_t steps = tether.stepCount() - steps_before[i];
    if (steps > 0 && tether_wall > 0.0)
    {
      s.step_seconds = smooth(s.step_seconds, tether_wall / static_cast<double>(steps));
      s.real_time_factor =
          smooth(s.real_time_factor, static_cast<double>(steps) * tether.params().time_step / tether_wall);
    }
  }
}

}  // namespace rov_tether::ros_layer
