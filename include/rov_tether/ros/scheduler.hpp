#pragma once

#include <ros/time.h>

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "rov_tether/core/world.hpp"
#include "rov_tether/ros/load_governor.hpp"
#include "rov_tether/ros/log_throttle.hpp"
#include "rov_tether/ros/param_loader.hpp"

namespace rov_tether::ros_layer
{

/// What the scheduler asks of one tether's node during a physics tick (TetherNode implements it; the
/// golden replay test too).
class TetherHooks
{
 public:
  virtual ~TetherHooks() = default;
  /// Before the physics advances: pending parameters, polled poses (tf, spool frame).
  virtual void beforeAdvance(const ros::Time& /*now*/) {}
  /// ~state (and ~wrench) is due at the tether's current physics time, a point of its state grid.
  virtual void publishState() = 0;
  /// True while the node wants every internal step of this tether (~coupling has subscribers): the world
  /// then advances to each of its steps' ends in turn and calls stepped() there.
  virtual bool watchesSteps() const { return false; }
  /// After each internal step of this tether while watchesSteps(): its physics time is that step's end, `delay`
  /// [s] behind ROS time (delay(): interpolation_delay, or more for sparse or late poses).
  virtual void stepped(double /*delay*/) {}
  /// After the physics advanced on this tick: reports, markers, diagnostics.
  virtual void afterAdvance(const ros::Time& /*now*/) {}
  /// The tether was re-laid (start, clock jump, ~reset) on the tick at ROS time `now` (after a clock that went
  /// back it restarted earlier, at the new clock's first pose): inputs and outputs start over.
  virtual void restarted(const ros::Time& /*now*/) {}

  /// When the tether's vehicle poses come, for the physics' place behind ROS time.
  struct PoseTiming
  {
    double latest_stamp = std::numeric_limits<double>::quiet_NaN();  ///< Of the last pose taken; NaN: none [s].
    double needed_delay = 0.0;  ///< Behind ROS time the poses bracket the physics (PoseInput::neededDelay) [s].
  };
  virtual PoseTiming poseTiming() const { return {}; }
  /// ROS time the earliest pose still waiting for the physics arrived; zero when none waits. When the
  /// clock went back, the tethers restart at the first arrival on the new clock, not at the tick that
  /// noticed (its time depends on when /clock messages come), so a bag replayed twice restarts the same.
  virtual ros::Time earliestArrival() const { return ros::Time(); }
};

/// One tether's schedule and what it reports (read by the diagnostics).
struct TetherSchedule
{
  TetherSchedule(TetherHooks& hooks_in, const NodeOptions& options, int iterations, const std::string& name)
      : hooks(&hooks_in),
        label(name.empty() ? "" : " " + name),
        state_period(1.0 / options.state_rate),
        max_lag(options.max_lag),
        governor(options, iterations, name)
  {
  }

  TetherHooks* hooks;
  std::string label;              ///< " name" for log messages, "" alone.
  double state_period;            ///< 1 / state_rate [s].
  double max_lag;                 ///< [s]
  double next_state = 0.0;        ///< Physics time at which ~state is due next [s]; 0: not set.
  std::uint32_t resets = 0;       ///< Resets (clock jumps, ~reset); the start is none.
  std::uint64_t skips = 0;        ///< Times the physics fell more than max_lag behind and skipped.
  ros::Time last_skip_time;       ///< ROS time of the last skip.
  double step_seconds = 0.0;      ///< Smoothed wall time per internal step [s].
  double real_time_factor = 0.0;  ///< Smoothed simulated / wall time of the physics [-].
  LoadGovernor governor;
  /// This tether's own log throttles, once a second each (ROS_WARN_THROTTLE's belongs to the line: one tether's
  /// would hide another's): a restart refused, a skip ahead refused, a skip ahead.
  LogThrottle restart_log{1.0}, skip_refused_log{1.0}, skip_log{1.0};
};

/**
 * Runs the physics of a World on ROS time, one tick at a time (the node's one timer), for every tether in
 * lockstep. Clock policy: the first tick starts the tethers at the current time; a clock that goes
 * backwards, or leaps more than 5 s forwards beyond the wall time since the last tick, resets them
 * (warning). ROS time that passed with the wall clock is the node's own stall (a huge camera render):
 * never a clock jump; the physics catches up, or skips ahead beyond max_lag. The physics runs behind ROS time so
 * that the vehicle poses bracket it: interpolation_delay, or more when poses come further apart (the
 * largest needed delay of any tether, up to the hold limit; it grows at once and shrinks at
 * kDelayShrinkRate, so the physics never jumps), and it never passes the latest pose of any tether
 * (it waits for the next one) while that pose is less than the hold limit old: the largest of
 * interpolation_delay and every tether's stale_pose_timeout. Its start is aligned to each tether's
 * time_step grid. Each tether has its own ~state grid
 * (multiples of 1 / its state_rate in physics time, so a replay gives the same series): the world
 * advances from one due point to the next and the tethers due there publish. A tether more than its
 * max_lag behind skips ahead with its cable held (error, counted), publishes that held state at once and
 * restarts its ~state grid there, so a node that cannot hold real time still publishes at least once a
 * skip. A tether whose hooks watch its steps (~coupling subscribed) is told after each of its internal steps
 * (the world still steps in lockstep; unwatched, it advances to the next stop in one call, as before). After
 * the physics, each tether is charged the wall time of its own steps (the world tells the scheduler around
 * each) and of its hooks' calls (poses taken, ~state published), re-lays and skips, plus an even share of the
 * rest of the tick (the contact grid, which is every tether's, and the scheduling itself),
 * and that is fed to its LoadGovernor: measured, not estimated, so a tether that gives up iterations does
 * not pass its cost on to the others. Needs no ROS master: the wall clock is injected.
 */
class Scheduler : private StepObserver
{
 public:
  using WallClock = std::function<ros::WallTime()>;

  /// Forward clock jumps larger than this (beyond the wall time that passed) reset the tethers [s].
  static constexpr double kMaxForwardJump = 5.0;
  /// The delay behind ROS time shrinks at most this fast when poses come closer together: the physics
  /// then runs at most 1.5x real time to catch up, never skipping [s/s].
  static constexpr double kDelayShrinkRate = 0.5;

  /// `world` must outlive the scheduler. `interpolation_delay` [s] is the world's (one clock for all).
  explicit Scheduler(World& world, double interpolation_delay, WallClock wall_clock = &ros::WallTime::now);

  /// Schedules world.tether(size()) with its node options (state_rate, max_lag, overload_policy ...);
  /// `hooks` must outlive the scheduler. Returns the tether's index. Add tethers in the world's order.
  std::size_t add(const NodeOptions& options, TetherHooks& hooks, const std::string& label = "");
  std::size_t size() const { return tethers_.size(); }

  /// One physics tick at ROS time `now` (nothing before the clock starts, at zero).
  void tick(const ros::Time& now);
  /// Re-lays tether i at the physics time of `now`, counts a reset and warns with `why`.
  void reset(std::size_t i, const ros::Time& now, const std::string& why);

  /// The physics time for ROS time `now`: the current delay behind, on the grid of tether i's time_step.
  double alignedPhysicsTime(std::size_t i, const ros::Time& now) const;
  double interpolationDelay() const { return interpolation_delay_; }
  /// How far behind ROS time the physics runs now [s] (interpolation_delay, or more for sparse poses).
  double delay() const { return delay_; }
  /// The physics' target time for ROS time `now` on the last tick [s].
  double target() const { return target_; }
  const TetherSchedule& schedule(std::size_t i) const { return tethers_[i]; }
  LoadGovernor& governor(std::size_t i) { return tethers_[i].governor; }

 private:
  /// The physics' target for ROS time `now`: the delay updated from the tethers' pose timing, and held
  /// at the latest pose (see the class).
  double physicsTarget(const ros::Time& now);
  /// Re-lays tether i at the physics time of `now` and restarts its state grid and its hooks (restarted(clock):
  /// `clock` is the tick's ROS time, later than `now` when a clock that went back restarts at its first pose).
  void restart(std::size_t i, const ros::Time& now, const ros::Time& clock);
  /// reset() with the tick's ROS time `clock` for the hooks (restart()).
  void reset(std::size_t i, const ros::Time& now, const ros::Time& clock, const std::string& why);
  void resetAll(const ros::Time& now, const ros::Time& clock, const std::string& why);
  /// Sets tether i's next ~state point for physics target `target`, and skips ahead beyond max_lag.
  void prepare(std::size_t i, double target, const ros::Time& now);
  /// Advances the world to `target`, stopping at every due ~state point to publish, and after every step of
  /// a tether whose hooks watch its steps.
  void advance(double target);
  /// Where advance() stops next on its way to `target`: the earliest due ~state point, or the end of the
  /// next step of a tether whose steps are watched, or `target`.
  double nextStop(double target) const;
  /// Charges each tether what was measured for it on this tick, plus an even share of the rest of `wall` [s],
  /// and updates their statistics and governors.
  void account(double wall, const ros::WallTime& wall_end, const std::vector<std::uint64_t>& steps_before);
  /// Runs `call` and charges its wall time to tether i.
  template <class Call>
  void timed(std::size_t i, Call&& call);
  /// Charges tether i the wall time since `start` (none when the clock went back).
  void charge(std::size_t i, const ros::WallTime& start);
  void beforeStep(std::size_t tether) override;
  void afterStep(std::size_t tether) override;

  World& world_;
  double interpolation_delay_;
  double delay_;         ///< Current delay behind ROS time [s].
  double hold_limit_;    ///< The physics never runs further behind ROS time than this [s].
  double target_ = 0.0;  ///< Physics target of the last tick [s].
  WallClock wall_clock_;
  std::vector<TetherSchedule> tethers_;
  std::vector<std::uint64_t> stepped_before_;  ///< advance(): each tether's step count before a stop (reused).
  std::vector<std::uint64_t> ticked_before_;   ///< tick(): each tether's step count before the tick (reused).
  std::vector<double> charged_;                ///< Each tether's measured wall time on this tick [s].
  ros::WallTime step_start_;                   ///< Wall time the world's current step began.
  bool started_ = false;
  ros::Time last_time_;      ///< ROS time of the last tick (or reset).
  ros::WallTime last_wall_;  ///< Wall time of the last tick's start; zero before the first.
};

}  // namespace rov_tether::ros_layer
