#pragma once
// Moving a world built from a scenario along its tethers' paths: the loop of the offline runner
// (scenario_runner.hpp) and of the Python API. No YAML and no output files here.

#include <csignal>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "rov_tether/core/world.hpp"
#include "rov_tether/scenario/scenario.hpp"
#include "rov_tether/scenario/vehicle_driver.hpp"

namespace rov_tether
{

/// Something that looks at a run at times of its own (the camera dataset writer): the runner advances the
/// simulation there between its own output times. Looking changes nothing in the run.
class RunObserver
{
 public:
  virtual ~RunObserver() = default;
  /// The simulated time it wants to look at next [s]; +inf when it is done.
  virtual double nextTime() const = 0;
  /// Looks at the simulation, advanced to the last step at or before nextTime(). Returns "" or an error,
  /// which ends the run.
  virtual std::string observe(const Tether& sim) = 0;

  // An observer that writes outputs of its own (the camera dataset), as runScenario writes its CSV files: under
  // temporary names, moved into place with them only when the whole run succeeded.

  /// Once runScenario has opened its CSV files, before the first step: "" or the error, which ends the run before
  /// it starts.
  virtual std::string startWriting() { return ""; }
  /// Once the run has stepped to its end (or stopped), before the CSV files move: "" or the error (a file that
  /// could not be written), which fails the run: nothing moves into place.
  virtual std::string finishWriting() { return ""; }
  /// Once the CSV files have moved into place or been removed (with runScenario's `interrupt`, SIGINT and SIGTERM
  /// held through both), whether they moved (`keep`): the observer's outputs move into place too, or are removed. ""
  /// or the error; an earlier output moved aside that could not be removed goes to `left`. Called once on every
  /// path that called startWriting, whatever it returned, after finishWriting.
  virtual std::string commit(bool /*keep*/, std::vector<std::string>* /*left*/) { return ""; }
};

/**
 * Advances a World that buildWorld built from worldSpecOf(scenario) along the scenario's tethers: each
 * kinematic vehicle path fed as samples a little ahead of the simulation (PathDriver), each dynamic vehicle's
 * thrust set before every step of its tether (VehicleDriver: a thrust schedule, or its controller following
 * the path), and observers let look at their own times. Keeps the first error of each kind. The world must
 * outlive it; it keeps its own copy of the scenario's tether list (the drivers refer into it), so it can be
 * neither copied nor moved.
 */
class ScenarioStepper
{
 public:
  ScenarioStepper(const Scenario& scenario, World& world);
  ScenarioStepper(const ScenarioStepper&) = delete;
  ScenarioStepper& operator=(const ScenarioStepper&) = delete;

  /// Feeds every tether's path up to t [s] and advances the world there, in chunks as PathDriver::advanceTo
  /// does (for one tether, the very same calls: a world of one tether without contact steps as that tether).
  /// False, with runError() set, when a sample or an advance is refused.
  bool advance(double t);
  /// Lets the observers look at every time of theirs up to `until` [s], in time order.
  void observe(const std::vector<RunObserver*>& observers, double until);

  /// Tells `observer` around every step the world takes from now on (World::advanceTo's StepObserver); nullptr:
  /// none. It must outlive the stepper's advances.
  void setStepObserver(StepObserver* observer) { step_observer_ = observer; }

  /// Stops driving tether i's dynamic vehicle (its thrust schedule or controller): from now on its thrust is the
  /// caller's (Tether::setVehicleThrust, held until changed). False when the scenario gives it no dynamic vehicle.
  bool releaseVehicle(std::size_t i);

  /// Stops advancing once `*flag` is non-zero (a signal handler's: rov_tether_run's SIGINT and SIGTERM), before the
  /// next stretch the world is advanced by (at most 0.25 s of simulated time; a step, with dynamic vehicles):
  /// advance() then fails with runError() "interrupted at t = T s" and interrupted() is true. nullptr: never.
  void setInterrupt(const volatile std::sig_atomic_t* flag) { interrupt_ = flag; }
  /// The run stopped at the interrupt flag (setInterrupt).
  bool interrupted() const { return interrupted_; }

  /// The scenario's tethers (Scenario::tetherList), in World order.
  const std::vector<ScenarioTether>& tethers() const { return tethers_; }
  /// The dynamic vehicles' drivers with their tethers' indices, in scenario order.
  const std::vector<std::pair<std::size_t, VehicleDriver>>& vehicles() const { return vehicles_; }
  /// The first refused sample or advance (a path or time that was not validated), naming the tether of a
  /// `tethers` list: the runner stops there, writes nothing more and returns this message.
  const std::string& runError() const { return run_error_; }
  /// The first observer's error ("" while none).
  const std::string& observerError() const { return observer_error_; }
  /// Time spent advancing [s].
  double cpuSeconds() const { return cpu_; }

 private:
  /// With dynamic vehicles: one step at a time, as World::advanceTo orders them (the tether whose next step
  /// comes first), each dynamic vehicle's thrust set before its tether steps (VehicleDriver::beforeStep) and
  /// the kinematic paths fed up to it. False, with runError() set, when something is refused.
  bool advanceStepByStep(double t);
  /// Feeds every kinematic path up to t; false, with runError() set, when a sample is refused.
  bool feedUpTo(double t);
  /// World::advanceTo(t); false, with runError() set, when it is refused.
  bool advanceWorld(double t);

  bool named_;  ///< A `tethers` list: errors name the tether.
  const std::vector<ScenarioTether> tethers_;
  World& world_;
  std::vector<PathDriver> drivers_;
  std::vector<std::pair<std::size_t, VehicleDriver>> vehicles_;
  std::vector<bool> released_;  ///< Per tether: its dynamic vehicle's thrust is the caller's (releaseVehicle).
  double cpu_ = 0.0;
  StepObserver* step_observer_ = nullptr;
  const volatile std::sig_atomic_t* interrupt_ = nullptr;
  bool interrupted_ = false;
  std::string run_error_;
  std::string observer_error_;
};

}  // namespace rov_tether
