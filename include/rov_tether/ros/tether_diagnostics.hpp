#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/node_handle.h>
#include <ros/time.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "rov_tether/core/run_out_watch.hpp"
#include "rov_tether/core/tether.hpp"
#include "rov_tether/ros/log_throttle.hpp"
#include "rov_tether/ros/param_loader.hpp"
#include "rov_tether/ros/pose_input.hpp"
#include "rov_tether/ros/scheduler.hpp"
#include "rov_tether/ros/world_report.hpp"

namespace rov_tether::ros_layer
{

/**
 * One tether's /diagnostics status ("tether", or "tether <name>" among several) and its error reports:
 * simulation failures, vehicle jumps, a vehicle outrunning the winch, a reel-in held at the stall pull and steps the
 * solver stopped short of solver_tolerance are logged (throttled) as the physics finds them. It reads the tether, its
 * pose input (poses taken, refused, dropped) and its schedule (resets, skips, load, what overload_policy gave up, the
 * physics' delay behind ROS time) and the world's topology report (wraps around obstacles, links with other tethers,
 * snags: warnings at wrap_warning_turns, any linking number, capstan ratios above snag_ratio).
 */
class TetherDiagnostics
{
 public:
  /// Everything referenced must outlive this. `index`: the tether's in the scheduler and the world.
  TetherDiagnostics(ros::NodeHandle& nh, ros::NodeHandle& private_nh, const NodeOptions& options,
                    const std::string& name, const Tether& tether, const PoseInput& pose_input,
                    const Scheduler& scheduler, std::size_t index, TopologyReport& topology);

  /// After the physics advanced at `now`: logs the failures and jumps it found.
  void report(const ros::Time& now);
  /// After the tether was reset or re-laid (TetherNode::restarted): its solver effort starts again.
  void restarted();
  /// Publishes /diagnostics when due.
  void publish() { updater_->update(); }
  /// More values and warnings for the status (a dynamic vehicle's: VehicleIo::diagnose), filled after the rest.
  void addExtra(std::function<void(diagnostic_updater::DiagnosticStatusWrapper&)> extra) { extra_ = std::move(extra); }
  /// Fills the status (the diagnostic_updater task).
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);

 private:
  /// The measured values (lengths, tensions, loads, counts).
  void addMeasures(const TetherSummary& summary, diagnostic_updater::DiagnosticStatusWrapper& status);
  /// The warnings and errors (stale pose, over-tension, outrun, failures, overload) merged into the summary.
  void mergeAlarms(const TetherSummary& summary, diagnostic_updater::DiagnosticStatusWrapper& status);
  /// This tether's lines of the topology report, as values and warnings.
  void diagnoseTopology(diagnostic_updater::DiagnosticStatusWrapper& status);

  NodeOptions options_;
  std::string label_;  ///< " name" for log messages, "" alone.
  const Tether& tether_;
  const PoseInput& pose_input_;
  const Scheduler& scheduler_;
  std::size_t index_;
  TopologyReport& topology_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  std::uint64_t reported_jumps_ = 0;         ///< Vehicle jumps already logged.
  std::uint64_t reported_out_of_reach_ = 0;  ///< Attachments out of the cable's reach already logged.
  RunOutWatch run_out_;                      ///< Whether the cable has run out since the last report.
  bool was_at_shortest_ = false;             ///< Tether::winchAtShortest() at the last report.
  std::uint64_t reported_failures_ = 0;      ///< Simulation failures (blow-ups) already logged.
  ros::Time last_failure_time_;              ///< When the last failure was seen; diagnostics show ERROR for a while.
  ros::Time last_outrun_time_;               ///< When the vehicle last outran the winch; diagnostics WARN for a while.
  ros::Time last_stall_time_;                ///< When a reel-in was last held at the stall pull (WARN for a while).
  /// This tether's own log throttles (ROS_WARN_THROTTLE's belongs to the line, so one tether's warning hid every
  /// other tether's): outrun, stall and unconverged once per 5 s (kFailureReportTime), failures and jumps once a
  /// second.
  LogThrottle outrun_log_{5.0}, stall_log_{5.0}, unconverged_log_{5.0}, failure_log_{1.0}, jump_log_{1.0},
      run_out_log_{5.0}, shortest_log_{5.0};
  std::uint64_t reported_drops_ = 0;        ///< Dropped poses already seen.
  ros::Time last_drop_time_;                ///< When poses were last dropped; diagnostics show WARN for a while.
  std::uint64_t reported_unconverged_ = 0;  ///< Steps short of solver_tolerance already logged.
  ros::Time last_unconverged_time_;         ///< When the last above solver_residual_warning was seen (WARN).
  double last_unconverged_residual_ = 0.0;  ///< Its residual [-] and iterations, for the WARN.
  int last_unconverged_iterations_ = 0;
  SolverEffort period_start_;  ///< The solver's effort at the last report (for its mean since).
  std::function<void(diagnostic_updater::DiagnosticStatusWrapper&)> extra_;  ///< addExtra's; empty: none.
};

}  // namespace rov_tether::ros_layer
