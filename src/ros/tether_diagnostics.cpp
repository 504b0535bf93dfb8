#include "rov_tether/ros/tether_diagnostics.hpp"

#include <cmath>
#include <limits>

namespace rov_tether::ros_layer
{
namespace
{

/// Diagnostics stay ERROR (WARN for an outrun winch or a step short of the solver's tolerance) for this long
/// after a simulation failure, a skip, the vehicle outrunning the winch or such a step [s].
constexpr double kFailureReportTime = 5.0;

/// Where the motor's stall pull comes from: max_winch_pull, or what 0 derives it from.
std::string stallPullSource(const TetherParams& params)
{
  return params.max_winch_pull > 0.0 ? "max_winch_pull"
                                     : "max_winch_pull 0: 1.25 x the larger of target_tension + tension_deadband and "
                                       "brake_tension";
}

}  // namespace

TetherDiagnostics::TetherDiagnostics(ros::NodeHandle& nh, ros::NodeHandle& private_nh, const NodeOptions& options,
                                     const std::string& name, const Tether& tether, const PoseInput& pose_input,
                                     const Scheduler& scheduler, std::size_t index, TopologyReport& topology)
    : options_(options),
      label_(name.empty() ? "" : " " + name),
      tether_(tether),
      pose_input_(pose_input),
      scheduler_(scheduler),
      index_(index),
      topology_(topology)
{
  updater_ = std::make_unique<diagnostic_updater::Updater>(nh, private_nh);
  updater_->setHardwareID(name.empty() ? "rov_tether" : "rov_tether/" + name);
  updater_->add(name.empty() ? "tether" : "tether " + name, this, &TetherDiagnostics::diagnose);
}

void TetherDiagnostics::report(const ros::Time& now)
{
  if (tether_.recoveryCount() > reported_failures_)
  {
    reported_failures_ = tether_.recoveryCount();
    last_failure_time_ = now;
    if (failure_log_.due(now))
    {
      ROS_ERROR("tether_node%s: simulation failure (%llu so far): %s", label_.c_str(),
                static_cast<unsigned long long>(reported_failures_), tether_.lastFailure().c_str());
    }
  }
  // Each log below is throttled per tether (LogThrottle; ROS_WARN_THROTTLE's is per line: one tether's would hide
  // another's).
  if (tether_.winchOutrun())
  {
    last_outrun_time_ = now;
    if (outrun_log_.due(now))
    {
      // What it gives way at (WinchDrive::atItsLimit): the brake, the auto-tension target, the strain rule's
      // threshold.
      const WinchMode mode = tether_.params().winch_mode;
      ROS_WARN(
          "tether_node%s: the vehicle outruns the winch: it pays out at max_winch_speed = %.2f m/s and the cable "
          "stretches (spool tension above the %s)",
          label_.c_str(), tether_.params().max_winch_speed,
          mode == WinchMode::kBrake             ? "brake_tension"
          : mode == WinchMode::kConstantTension ? "target_tension"
                                                : "strain rule's payout_threshold x axial_stiffness");
    }
  }
  // The cable running out, as the runner says it (RunOutWatch; the diagnostics' "fully deployed" says it as long
  // as it lasts).
  if (run_out_.update(tether_) && run_out_log_.due(now))
  {
    ROS_WARN(
        "tether_node%s: the cable runs out: all of cable_length = %.4g m is paid out, and from then on the winch has "
        "no "
        "more to give (the cable stretches where the vehicle pulls on)",
        label_.c_str(), tether_.params().cable_length);
  }
  // A speed winch asked to reel in past min_deployed_length stands there: said once each time it comes to stand.
  const bool at_shortest = tether_.winchAtShortest();
  if (at_shortest && !was_at_shortest_ && shortest_log_.due(now))
  {
    ROS_WARN(
        "tether_node%s: the winch stands at min_deployed_length = %.4g m: winch_speed = %.3g m/s asks it to reel in "
        "further, which it does not (it slowed down to stop there; ~set_winch a speed >= 0 or a target_length)",
        label_.c_str(), tether_.params().min_deployed_length, tether_.params().winch_speed);
  }
  was_at_shortest_ = at_shortest;
  if (tether_.winchStalled())
  {
    last_stall_time_ = now;
    if (stall_log_.due(now))
    {
      ROS_WARN(
          "tether_node%s: the winch cannot reel in at its commanded %.2f m/s: the spool tension holds it at the "
          "motor's stall pull of %.4g N (%s)",
          label_.c_str(), tether_.winchCommandedSpeed(), tether_.params().winchPull(),
          stallPullSource(tether_.params()).c_str());
    }
  }
  const SolverEffort& effort = tether_.solverEffort();
  if (effort.unconverged > reported_unconverged_)
  {
    // Of the sub-steps short of the tolerance since the last physics tick, the last one's residual is known:
    // one that ended above solver_residual_warning is warned of, one a few times the tolerance (as a corner of
    // the path can leave) only counted. Not while overload_policy has lowered the iterations: its own warning
    // says so.
    reported_unconverged_ = effort.unconverged;
    if (effort.unconverged_residual > options_.solver_residual_warning &&
        scheduler_.schedule(index_).governor.degraded().empty())
    {
      last_unconverged_time_ = now;
      last_unconverged_residual_ = effort.unconverged_residual;
      last_unconverged_iterations_ = effort.unconverged_iterations;
      if (unconverged_log_.due(now))
      {
        ROS_WARN(
            "tether_node%s: a sub-step ended short of solver_tolerance %.3g, at a residual of %.3g of a segment "
            "after %d iterations (%llu short so far): its tensions are not converged (raise iterations; "
            "docs/limitations.md)",
            label_.c_str(), tether_.params().solver_tolerance, last_unconverged_residual_, last_unconverged_iterations_,
            static_cast<unsigned long long>(effort.unconverged));
      }
    }
  }
  if (pose_input_.dropped() > reported_drops_)
  {
    reported_drops_ = pose_input_.dropped();
    last_drop_time_ = now;
  }
  if (tether_.outOfReachCount() > reported_out_of_reach_)
  {
    reported_out_of_reach_ = tether_.outOfReachCount();
    ROS_WARN("tether_node%s: %s", label_.c_str(), tether_.lastOutOfReach().c_str());
  }
  if (tether_.jumpCount() > reported_jumps_)
  {
    reported_jumps_ = tether_.jumpCount();
    if (jump_log_.due(now))
    {
      ROS_WARN(
          "tether_node%s: the vehicle pose jumped further than it could move (max_vehicle_speed %.2f m/s x dt + "
          "max_vehicle_jump %.2f m): cable re-laid",
          label_.c_str(), tether_.params().max_vehicle_speed, tether_.params().max_vehicle_jump);
    }
  }
}

void TetherDiagnostics::restarted()
{
  // The tether's solver effort starts again from zero.
  period_start_ = SolverEffort{};
  reported_unconverged_ = 0;
  last_unconverged_time_ = ros::Time();
  was_at_shortest_ = false;
}

void TetherDiagnostics::diagnose(diagnostic_updater::DiagnosticStatusWrapper& status)
{
  const TetherSummary summary = tether_.summary();
  status.summary(diagnostic_msgs::DiagnosticStatus::OK, "tether simulated");
  addMeasures(summary, status);
  mergeAlarms(summary, status);
  diagnoseTopology(status);
  if (extra_)
  {
    extra_(status);
  }
}

void TetherDiagnostics::addMeasures(const TetherSummary& summary, diagnostic_updater::DiagnosticStatusWrapper& status)
{
  const TetherSchedule& schedule = scheduler_.schedule(index_);
  const LoadGovernor& governor = schedule.governor;
  status.add("deployed length [m]", summary.deployed_length);
  status.add("tension at vehicle [N]", summary.tension_vehicle);
  status.add("force on vehicle [N]", summary.vehicle_force.norm());
  status.add("force on spool [N]", summary.spool_force.norm());
  status.add("max tension [N]", summary.max_tension);
  status.add("step time [us]", schedule.step_seconds * 1e6);
  status.add("physics real-time factor", schedule.real_time_factor);
  status.add("residual stretch", summary.mean_strain);
  status.add("poses taken", pose_input_.accepted());
  status.add("poses taken late", pose_input_.late());
  status.add("rejected poses", pose_input_.rejected());
  status.add("rejected poses stamped in the future", pose_input_.future());
  status.add("dropped poses", pose_input_.dropped());
  status.add("physics delay [s]", scheduler_.delay());
  status.add("resets", schedule.resets);
  status.add("vehicle jumps", tether_.jumpCount());
  status.add("solver", toString(tether_.params().solver));
  status.add("iterations", tether_.params().iterations);
  status.add("winch", toString(tether_.params().winch_mode));
  status.add("winch speed [m/s]", tether_.winchSpeed());
  status.add("physics load [% of wall time]", 100.0 * governor.physicsLoad());
  status.add("marker load [% of wall time]", 100.0 * governor.markerLoad());
  status.add("skips (fell behind)", schedule.skips);
  const SolverEffort& effort = tether_.solverEffort();
  if (effort.substeps > 0)
  {
    // The solver's effort (direct, which stops on solver_tolerance): the mean since the last report (NaN with
    // no sub-step since), the last sub-step's residual, and the counts since the start or the last reset.
    const std::uint64_t substeps = effort.substeps - period_start_.substeps;  // restarted() clears the start
    status.add("newton iterations per sub-step",
               substeps > 0
                   ? static_cast<double>(effort.iterations - period_start_.iterations) / static_cast<double>(substeps)
                   : std::numeric_limits<double>::quiet_NaN());
    status.add("newton residual, last sub-step [of a segment]", tether_.solverResidual());
    status.add("sub-steps short of solver_tolerance", effort.unconverged);
    status.add("sub-steps rescued", effort.rescued);
    period_start_ = effort;
  }
  status.add("simulation failures", tether_.recoveryCount());
  if (!tether_.lastFailure().empty())
  {
    status.add("last failure", tether_.lastFailure());
  }
}

void TetherDiagnostics::mergeAlarms(const TetherSummary& summary, diagnostic_updater::DiagnosticStatusWrapper& status)
{
  using diagnostic_msgs::DiagnosticStatus;
  const TetherSchedule& schedule = scheduler_.schedule(index_);
  const LoadGovernor& governor = schedule.governor;
  const ros::Time now = ros::Time::now();
  const ros::Time& last_pose_time = pose_input_.lastPoseTime();
  if (!tether_.vehicleAttached())
  {
    status.mergeSummary(DiagnosticStatus::WARN, "no vehicle pose yet");
  }
  else if (!last_pose_time.isZero() && (now - last_pose_time).toSec() > options_.stale_pose_timeout)
  {
    status.mergeSummaryf(DiagnosticStatus::WARN, "stale pose: none for %.1f s", (now - last_pose_time).toSec());
  }
  if (!last_drop_time_.isZero() && (now - last_drop_time_).toSec() < kFailureReportTime)
  {
    status.mergeSummaryf(DiagnosticStatus::WARN, "poses dropped: %llu so far (the physics stalled)",
                         static_cast<unsigned long long>(pose_input_.dropped()));
  }
  if (summary.max_tension > options_.max_tension_warning)
  {
    status.mergeSummaryf(DiagnosticStatus::WARN, "over-tension: %.1f N", summary.max_tension);
  }
  if (summary.deployed_length >= tether_.params().cable_length - 1e-9)
  {
    status.mergeSummary(DiagnosticStatus::WARN, "fully deployed");
  }
  if (!last_outrun_time_.isZero() && (now - last_outrun_time_).toSec() < kFailureReportTime)
  {
    status.mergeSummaryf(DiagnosticStatus::WARN, "the vehicle outruns the winch (max_winch_speed %.2f m/s)",
                         tether_.params().max_winch_speed);
  }
  if (!last_stall_time_.isZero() && (now - last_stall_time_).toSec() < kFailureReportTime)
  {
    status.mergeSummaryf(DiagnosticStatus::WARN, "the winch is held at its stall pull (%.4g N): it cannot reel in",
                         tether_.params().winchPull());
  }
  if (!last_unconverged_time_.isZero() && (now - last_unconverged_time_).toSec() < kFailureReportTime)
  {
    status.mergeSummaryf(DiagnosticStatus::WARN,
                         "solver short of solver_tolerance: residual %.3g of a segment after %d iterations",
                         last_unconverged_residual_, last_unconverged_iterations_);
  }
  if (!last_failure_time_.isZero() && (now - last_failure_time_).toSec() < kFailureReportTime)
  {
    status.mergeSummaryf(DiagnosticStatus::ERROR, "simulation failure, cable re-laid: %s",
                         tether_.lastFailure().c_str());
  }
  if (!governor.degraded().empty())
  {
    status.mergeSummaryf(DiagnosticStatus::WARN, "degraded to hold real time: %s (overload_policy %s)",
                         governor.degraded().c_str(), governor.policy().c_str());
  }
  if (governor.overloaded())
  {
    // Given up what it could, or nothing: either way the budget is not held, and it says so.
    status.mergeSummaryf(DiagnosticStatus::WARN, "over cpu_budget: physics %.1f%% + markers %.1f%% of %.3g%%",
                         100.0 * governor.physicsLoad(), 100.0 * governor.markerLoad(), 100.0 * options_.cpu_budget);
  }
  if (!schedule.last_skip_time.isZero() && (now - schedule.last_skip_time).toSec() < kFailureReportTime)
  {
    status.mergeSummary(DiagnosticStatus::ERROR, "fell behind real time by more than max_lag: skipped ahead");
  }
  if (schedule.real_time_factor > 0.0 && schedule.real_time_factor < 1.0)
  {
    status.mergeSummaryf(DiagnosticStatus::ERROR, "physics slower than real time (%.2fx)", schedule.real_time_factor);
  }
}

void TetherDiagnostics::diagnoseTopology(diagnostic_updater::DiagnosticStatusWrapper& status)
{
  using diagnostic_msgs::DiagnosticStatus;
  const World& world = topology_.world();
  const std::string who = "tether" + label_;
  for (const TopologyEntry& entry : topology_.current())
  {
    // A linking number is listed once per pair, under the lower index: it is the other tether's too.
    const bool mine = entry.tether == index_;
    const bool linked_to_me = entry.kind == TopologyEntry::Kind::LinkingNumber && entry.object == index_;
    if (!mine && !linked_to_me)
    {
      continue;
    }
    const std::size_t other_index = mine ? entry.object : entry.tether;
    const std::string other = entry.object_is_tether
                                  ? (other_index == index_ ? "itself" : "tether " + world.name(other_index))
                                  : world.obstacle(entry.object).name();
    const double value = entry.value;
    switch (entry.kind)
    {
      case TopologyEntry::Kind::WrapTurns:
        status.add("wrap turns around " + other, value);
        if (std::abs(value) >= options_.wrap_warning_turns)  // NaN (on the axis) never warns
        {
          status.mergeSummaryf(DiagnosticStatus::WARN, "%s wrapped %.2f turns around %s", who.c_str(), value,
                               other.c_str());
        }
        break;
      case TopologyEntry::Kind::WrapAngle:
        status.add("wrap angle around " + other + " [rad]", value);  // the turn building up: never warns
        break;
      case TopologyEntry::Kind::LinkingNumber:
        status.add("linking number with " + other, value);
        if (std::abs(value) >= 0.5)  // an integer up to rounding: any non-zero one
        {
          status.mergeSummaryf(DiagnosticStatus::WARN, "%s linked with %s (linking number %.2f)", who.c_str(),
                               other.c_str(), value);
        }
        break;
      case TopologyEntry::Kind::ContactAngle:
        status.add("contact angle on " + other + " [rad]", value);
        break;
      case TopologyEntry::Kind::CapstanRatio:
        status.add("capstan ratio on " + other, value);
        if (value > options_.snag_ratio)
        {
          status.mergeSummaryf(DiagnosticStatus::WARN, "%s snagged on %s: capstan ratio %.3f > snag_ratio %.3f",
                               who.c_str(), other.c_str(), value, options_.snag_ratio);
        }
        break;
    }
  }
}

}  // namespace rov_tether::ros_layer
