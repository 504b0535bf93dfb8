#pragma once
// Running a scenario offline and writing its CSV files (state.csv, shape.csv; per tether, and topology.csv, for
// a world's scenario). No YAML here: the scenario comes from scenario_yaml.hpp or is built in code.

#include <csignal>
#include <cstdint>
#include <string>
#include <vector>

#include "rov_tether/core/world.hpp"
#include "rov_tether/scenario/scenario.hpp"
#include "rov_tether/scenario/scenario_stepper.hpp"

namespace rov_tether
{

/// What a scenario run produced: for a `tethers` list, the first tether's figures, every tether's in
/// `tethers`; steps and CPU time are the whole world's.
struct RunSummary
{
  std::string name;  ///< The tether's ("tether" for a single-tether scenario).
  std::uint64_t steps = 0;
  double cpu_seconds = 0.0;  ///< Time spent in the simulation (output excluded) [s].
  /// The time the run simulated to [s]: the duration, to a whole step of the first tether (a step that would end
  /// past the duration is not taken).
  double simulated = 0.0;
  std::size_t state_rows = 0;
  std::size_t shape_rows = 0;
  double deployed_start = 0.0;  ///< [m]
  double deployed_end = 0.0;    ///< [m]
  // The maxima are over every state the run simulated: the start and every step's (between and after the output
  // rows too), not only the rows'.
  double deployed_max = 0.0;         ///< Largest deployed length [m].
  double max_tension = 0.0;          ///< Largest segment tension [N].
  double max_tension_vehicle = 0.0;  ///< Largest tension at the vehicle [N].
  double max_strain = 0.0;           ///< Largest geometric strain [-].
  std::uint64_t jumps = 0;           ///< Vehicle jumps handled.
  /// Times the vehicle landed out of its cable's reach during the run (a jump; Tether::outOfReachCount from the
  /// world's build on: a path's start out of reach is in world_warnings), the time of the step that first said it
  /// [s] (negative: none) and what the tether said the last time (Tether::lastOutOfReach).
  std::uint64_t out_of_reach = 0;
  double first_out_of_reach_time = -1.0;
  std::string last_out_of_reach;
  double max_tension_time = 0.0;  ///< The time of the state (a step's, or the start) of max_tension [s].
  std::uint64_t recoveries = 0;   ///< Simulation failures (the cable re-laid), Tether::recoveryCount().
  SolverEffort solver;            ///< Newton iterations and residuals over the run (direct), Tether::solverEffort().
  std::string last_failure;       ///< Tether::lastFailure() ("" for none).
  /// The steps' time, in all, at whose end the vehicle outran the winch (Tether::winchOutrun) [s].
  double outrun_seconds = 0.0;
  double first_outrun_time = -1.0;  ///< The end of the first such step [s]; negative: none.
  /// The steps' time, in all, at whose end the stall pull held the reel-in (Tether::winchStalled) [s].
  double stall_seconds = 0.0;
  double first_stall_time = -1.0;  ///< The end of the first such step [s]; negative: none.
  double first_stall_speed = 0.0;  ///< The speed the winch was commanded then [m/s] (Tether::winchCommandedSpeed).
  /// The end of the first step at which the cable ran out: the winch paid out the last of cable_length where some
  /// was on the spool since the cable was laid (RunOutWatch) [s]; negative: never.
  double first_full_time = -1.0;
  /// The steps' time, in all, at whose end a `speed` winch asked to reel in stood at min_deployed_length
  /// (Tether::winchAtShortest) [s], and the end of the first such step [s] (negative: none).
  double shortest_seconds = 0.0;
  double first_shortest_time = -1.0;
  std::size_t topology_rows = 0;    ///< Rows of topology.csv (0: not written).
  std::size_t vehicle_rows = 0;     ///< Rows of the tether's vehicle.csv (0: not written: no dynamic vehicle).
  std::vector<RunSummary> tethers;  ///< Each tether's own figures (steps: its own), in scenario order.
  /// What building the world said (buildWorld's warnings: a vehicle out of its cable's reach), for runWarnings.
  std::vector<std::string> world_warnings;
  /// The output directory's files of an earlier run that this run did not replace (earlierOutputs).
  std::vector<std::string> earlier_outputs;
  /// The earlier files this run replaced whose copies moved aside (.<name>.earlier) could not be removed.
  std::vector<std::string> replaced_left;
  /// The run stopped at runScenario's `interrupt` (its error says when). With replaced_left (when an observer's
  /// outputs could not move into place after the CSV files had), the only fields set when a run fails.
  bool interrupted = false;
};

/// Runs `scenario` and writes out_dir/state.csv and out_dir/shape.csv, or with a `tethers` list
/// out_dir/<name>/state.csv and shape.csv for each, and for a world's scenario (Scenario::usesWorld)
/// out_dir/topology.csv; all moved into place together at the end, all or none (should a move fail, every earlier
/// file is put back and the error says so), so a failed run leaves no partial file and no mix of new and earlier
/// files. An observer that writes outputs of its own (rov_tether_run's camera dataset) writes them under temporary
/// names too, and they move into place after the CSV files, only where those did (RunObserver::startWriting,
/// finishWriting, commit). Each observer looks at the first tether at its own times up to the scenario's duration.
/// Returns "" on success, otherwise the error (an obstacle that cannot be built: naming it; a vehicle sample or an
/// advance the simulation refused, in a scenario that was not validated: the run stops there and writes nothing).
[[nodiscard]] std::string runScenario(const Scenario& scenario, const std::string& out_dir, RunSummary* summary,
                                      const std::vector<RunObserver*>& observers = {});
/// As above, in `world`, which buildWorld built from worldSpecOf(scenario) and nothing has stepped yet (so a
/// caller can tell a world that cannot be built from a run that failed). Once `*interrupt` is non-zero (a signal
/// handler's; nullptr: never) the run stops before the next stretch it advances (ScenarioStepper::setInterrupt)
/// and fails as any run does, with "interrupted at t = T s" and summary->interrupted set: no CSV output written,
/// earlier ones left as they were. With an `interrupt`, SIGINT and SIGTERM are held while the outputs move into
/// place, so that a second signal, whose default action ends the program, cannot split the move.
[[nodiscard]] std::string runScenario(const Scenario& scenario, World& world, const std::string& out_dir,
                                      RunSummary* summary, const std::vector<RunObserver*>& observers = {},
                                      const volatile std::sig_atomic_t* interrupt = nullptr);

/// The node's default `max_tension_warning` [N]: the runner warns above the same tension.
constexpr double kDefaultMaxTensionWarning = 500.0;

/// What the node warns of, for a run (each tether's, named when there are several): simulation failures,
/// a tension above `max_tension_warning` [N] (over-tension; a tether's own ScenarioTether::max_tension_warning
/// instead, where it sets one), a vehicle that lands out of its cable's reach during the run (a jump), the
/// vehicle outrunning the winch, a `speed` winch's reel-in held at the motor's
/// stall pull, a `speed` winch asked to reel in past min_deployed_length (once, with the time it got there and how
/// long it stood) and the cable running out (all of cable_length paid out, where some was on the spool at the
/// start); and an earlier run's outputs left in the output directory. Empty when the run gave none.
std::vector<std::string> runWarnings(const Scenario& scenario, const RunSummary& summary, double max_tension_warning);

/// The CSV headers, part of the documented format.
extern const char* const kStateCsvHeader;
extern const char* const kShapeCsvHeader;
extern const char* const kTopologyCsvHeader;

}  // namespace rov_tether
