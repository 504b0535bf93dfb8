#include "rov_tether/scenario/scenario_runner.hpp"

#include <pthread.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <utility>

#include "rov_tether/core/run_out_watch.hpp"
#include "rov_tether/scenario/earlier_outputs.hpp"
#include "rov_tether/scenario/output_files.hpp"
#include "rov_tether/scenario/scenario_stepper.hpp"
#include "rov_tether/scenario/vehicle_driver.hpp"
#include "rov_tether/scenario/world_spec.hpp"

namespace rov_tether
{

const char* const kStateCsvHeader =
    "t,deployed_length,tension_spool,tension_vehicle,spool_force,vehicle_force,max_tension,max_strain,newton_mean,"
    "newton_max,newton_residual";
const char* const kShapeCsvHeader = "t,i,x,y,z,tension";
const char* const kTopologyCsvHeader = "t,tether,object,kind,value";

namespace
{

namespace fs = std::filesystem;

/// Folds a tether's state into its summary's maxima (deployed length, tension anywhere and at the vehicle, strain).
void takeMaxima(const TetherSummary& s, double t, RunSummary* result)
{
  result->deployed_max = std::max(result->deployed_max, s.deployed_length);
  if (s.max_tension > result->max_tension)
  {
    result->max_tension = s.max_tension;
    result->max_tension_time = t;
  }
  result->max_tension_vehicle = std::max(result->max_tension_vehicle, s.tension_vehicle);
  result->max_strain = std::max(result->max_strain, s.max_strain);
}

/// What the summary takes at every step each tether takes, not only at the output rows: the maxima (a tension that
/// peaks between two rows, or after the last, which the runner simulates up to the duration), an outrun winch, a
/// reel-in held at the stall pull (for how long, from when), a speed winch asked to reel in past min_deployed_length
/// (the same), a cable that runs out, and a vehicle that lands out of
/// its cable's reach (a jump: Tether::outOfReachCount, counted from here on; a path's start out of reach is said
/// when the world is built, among buildWorld's warnings), each with the time of the step that first said it.
/// Its own time is kept apart (seconds()), so that the summary's CPU time stays the simulation's.
class StepRecord : public StepObserver
{
 public:
  StepRecord(const World& world, std::vector<RunSummary>& each) : world_(world), each_(each)
  {
    for (std::size_t i = 0; i < world.size(); ++i)
    {
      out_of_reach_.push_back(world.tether(i).outOfReachCount());
      last_time_.push_back(world.tether(i).time());
      run_out_.emplace_back().update(world.tether(i));  // the cable as it is laid at the start
    }
  }
  void beforeStep(std::size_t /*tether*/) override {}
  void afterStep(std::size_t i) override
  {
    const auto start = std::chrono::steady_clock::now();
    const Tether& sim = world_.tether(i);
    sim.computeSegmentTensions(tensions_);
    const TetherSummary state = sim.summarize(tensions_);
    takeMaxima(state, sim.time(), &each_[i]);
    RunSummary& s = each_[i];
    const double step = sim.time() - last_time_[i];
    last_time_[i] = sim.time();
    if (sim.winchOutrun())
    {
      s.first_outrun_time = s.outrun_seconds > 0.0 ? s.first_outrun_time : sim.time();
      s.outrun_seconds += step;
    }
    if (sim.winchStalled())
    {
      s.first_stall_speed = s.stall_seconds > 0.0 ? s.first_stall_speed : sim.winchCommandedSpeed();
      s.first_stall_time = s.stall_seconds > 0.0 ? s.first_stall_time : sim.time();
      s.stall_seconds += step;
    }
    if (sim.winchAtShortest())
    {
      s.first_shortest_time = s.shortest_seconds > 0.0 ? s.first_shortest_time : sim.time();
      s.shortest_seconds += step;
    }
    if (run_out_[i].update(sim) && s.first_full_time < 0.0)
    {
      s.first_full_time = sim.time();
    }
    if (sim.outOfReachCount() > out_of_reach_[i])
    {
      s.first_out_of_reach_time = s.out_of_reach == 0 ? sim.time() : s.first_out_of_reach_time;
      s.out_of_reach += sim.outOfReachCount() - out_of_reach_[i];
      s.last_out_of_reach = sim.lastOutOfReach();
      out_of_reach_[i] = sim.outOfReachCount();
    }
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  double seconds() const { return seconds_; }

 private:
  const World& world_;
  std::vector<RunSummary>& each_;
  std::vector<std::uint64_t> out_of_reach_;  ///< Each tether's Tether::outOfReachCount() taken so far.
  std::vector<RunOutWatch> run_out_;         ///< Whether each tether's cable has run out.
  std::vector<double> last_time_;            ///< Each tether's time at its last step (or the start) [s].
  std::vector<double> tensions_;
  double seconds_ = 0.0;
};

/// A tether's state row and shape rows at t_out, and its running maxima; the row's Newton effort is the
/// sub-steps' since the previous row (the tether's mark is moved on).
void writeTether(Tether& sim, double t_out, std::FILE* state_file, std::FILE* shape_file, std::vector<double>& tensions,
                 std::vector<Position>& positions, RunSummary* result)
{
  sim.computeSegmentTensions(tensions);
  const TetherSummary s = sim.summarize(tensions);
  sim.copyPositions(positions);
  std::fprintf(state_file, "%.6f,%.6f,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,", t_out, s.deployed_length, s.tension_spool,
               s.tension_vehicle, s.spool_force.norm(), s.vehicle_force.norm(), s.max_tension, s.max_strain);
  const SolverEffort& effort = sim.solverEffortSinceMark();
  if (effort.substeps > 0)
  {
    std::fprintf(state_file, "%.4g,%d,%.3g\n", effort.meanIterations(), effort.max_iterations, effort.max_residual);
  }
  else
  {
    std::fputs("nan,nan,nan\n", state_file);  // no sub-step since the last row, or a solver without Newton
  }
  sim.markSolverEffort();
  // The shape rows are most of what a run writes: formatted by std::to_chars, whose fixed and general
  // formats with a precision are printf's "%.6f" and "%.6g" to the byte, at a fraction of fprintf's cost
  // (7% of scenarios/spool_payout.yaml's CPU time went to printf's number formatting).
  for (std::size_t i = 0; i < positions.size(); ++i)
  {
    char row[2048];  // room for the four fixed fields at the largest double (309 digits each), i and tension
    char* end = row + sizeof row;
    char* p = row;
    auto put = [&](double v, std::chars_format format)
    {
      p = std::to_chars(p, end, v, format, 6).ptr;
      *p++ = ',';
    };
    put(t_out, std::chars_format::fixed);
    p = std::to_chars(p, end, i).ptr;
    *p++ = ',';
    put(positions[i].x(), std::chars_format::fixed);
    put(positions[i].y(), std::chars_format::fixed);
    put(positions[i].z(), std::chars_format::fixed);
    if (i < tensions.size())
    {
      put(tensions[i], std::chars_format::general);
      --p;  // the last field has no comma after it
    }
    *p++ = '\n';
    std::fwrite(row, 1, static_cast<std::size_t>(p - row), shape_file);
  }
  ++result->state_rows;
  result->shape_rows += positions.size();
  takeMaxima(s, t_out, result);  // the start's state (every step's, and the winch's warnings: StepRecord)
}

/// The world's topology at t_out as rows of topology.csv; returns how many.
std::size_t writeTopology(const World& world, double t_out, std::FILE* file, std::vector<TopologyEntry>& entries)
{
  world.topology(entries);
  for (const TopologyEntry& e : entries)
  {
    const std::string& object = e.object_is_tether ? world.name(e.object) : world.obstacle(e.object).name();
    std::fprintf(file, "%.6f,%s,%s,%s,%.6g\n", t_out, world.name(e.tether).c_str(), object.c_str(),
                 topologyKindName(e.kind), e.value);
  }
  return entries.size();
}

/// state.csv and shape.csv per tether (in out_dir itself for a single-tether scenario), vehicle.csv per dynamic
/// vehicle (beside its tether's), then topology.csv.
std::vector<OutputFile> outputFilesOf(const Scenario& scenario, const std::vector<ScenarioTether>& tethers,
                                      const std::string& out_dir)
{
  std::vector<OutputFile> files;
  for (const ScenarioTether& tether : tethers)
  {
    const fs::path dir = scenario.tethers.empty() ? fs::path(out_dir) : fs::path(out_dir) / tether.name;
    files.push_back({dir / "state.csv", {}, nullptr});
    files.push_back({dir / "shape.csv", {}, nullptr});
  }
  for (const ScenarioTether& tether : tethers)
  {
    if (tether.dynamic)
    {
      const fs::path dir = scenario.tethers.empty() ? fs::path(out_dir) : fs::path(out_dir) / tether.name;
      files.push_back({dir / "vehicle.csv", {}, nullptr});
    }
  }
  if (scenario.usesWorld())
  {
    files.push_back({fs::path(out_dir) / "topology.csv", {}, nullptr});
  }
  return files;
}

/// Writes every file's CSV header; returns each tether's summary with its name and starting length.
std::vector<RunSummary> startOutputs(const std::vector<ScenarioTether>& tethers, const World& world,
                                     const std::vector<OutputFile>& files, std::FILE* topology_file)
{
  std::vector<RunSummary> each(tethers.size());
  for (std::size_t i = 0; i < tethers.size(); ++i)
  {
    each[i].name = tethers[i].name;
    each[i].deployed_start = world.tether(i).deployedLength();
    std::fprintf(files[2 * i].file, "%s\n", kStateCsvHeader);
    std::fprintf(files[2 * i + 1].file, "%s\n", kShapeCsvHeader);
  }
  std::size_t vehicle_file = 2 * tethers.size();
  for (const ScenarioTether& tether : tethers)
  {
    if (tether.dynamic)
    {
      std::fprintf(files[vehicle_file++].file, "%s\n", kVehicleCsvHeader);
    }
  }
  if (topology_file != nullptr)
  {
    std::fprintf(topology_file, "%s\n", kTopologyCsvHeader);
  }
  return each;
}

/// Steps to every output time, writing each tether's rows (and the topology's); returns the topology rows.
std::size_t writeOutputs(const Scenario& scenario, World& world, ScenarioStepper& stepper,
                         const std::vector<RunObserver*>& observers, const std::vector<OutputFile>& files,
                         std::FILE* topology_file, std::vector<RunSummary>& each)
{
  std::size_t topology_rows = 0;
  std::vector<double> tensions;
  std::vector<Position> positions;
  std::vector<TopologyEntry> entries;
  const auto outputs = static_cast<std::size_t>(std::floor(scenario.duration * scenario.output_rate + 1e-9));
  for (std::size_t k = 0; k <= outputs; ++k)
  {
    const double t_out = static_cast<double>(k) / scenario.output_rate;
    stepper.observe(observers, t_out);
    if (!stepper.runError().empty() || !stepper.advance(t_out))
    {
      break;
    }
    // Each row holds the state of the last step at or before t_out and says that step's time (3 rows per s on 5 ms
    // steps: 0.33 s, not 0.333333 s, which no step reached); t_out itself where a step lands on it (to rounding:
    // 60 steps of 0.005 s are 0.30000000000000004 s).
    const auto rowTime = [t_out](double state) { return std::abs(state - t_out) <= 1e-9 ? t_out : state; };
    for (std::size_t i = 0; i < each.size(); ++i)
    {
      Tether& tether = world.tether(i);
      writeTether(tether, rowTime(tether.time()), files[2 * i].file, files[2 * i + 1].file, tensions, positions,
                  &each[i]);
    }
    for (std::size_t j = 0; j < stepper.vehicles().size(); ++j)
    {
      const auto& [i, driver] = stepper.vehicles()[j];
      writeVehicleRow(files[2 * each.size() + j].file, rowTime(world.tether(i).time()), world.tether(i), driver);
      ++each[i].vehicle_rows;
    }
    if (topology_file != nullptr)
    {
      topology_rows += writeTopology(world, rowTime(world.time()), topology_file, entries);
    }
  }
  stepper.observe(observers, scenario.duration);
  // The whole duration, past the last output time (a duration that is no whole number of output periods: 0.01 s at
  // 10 rows per second had its one row at t = 0 and simulated no step).
  if (stepper.runError().empty() && stepper.observerError().empty())
  {
    (void)stepper.advance(scenario.duration);
  }
  return topology_rows;
}

/// The run's summary: the first tether's figures with the whole world's steps, CPU time and topology rows.
RunSummary summaryOf(const World& world, std::vector<RunSummary> each, std::size_t topology_rows, double cpu)
{
  std::uint64_t steps = 0;
  for (std::size_t i = 0; i < each.size(); ++i)
  {
    each[i].steps = world.tether(i).stepCount();
    each[i].deployed_end = world.tether(i).deployedLength();
    each[i].jumps = world.tether(i).jumpCount();
    each[i].recoveries = world.tether(i).recoveryCount();
    each[i].solver = world.tether(i).solverEffort();
    each[i].last_failure = world.tether(i).lastFailure();
    steps += each[i].steps;
  }
  RunSummary result = each.front();
  result.steps = steps;
  result.simulated = world.size() > 0 ? world.tether(0).time() : 0.0;
  result.cpu_seconds = cpu;
  result.topology_rows = topology_rows;
  result.tethers = std::move(each);
  return result;
}

}  // namespace

std::string runScenario(const Scenario& scenario, const std::string& out_dir, RunSummary* summary,
                        const std::vector<RunObserver*>& observers)
{
  // The world: tethers in scenario order, then the obstacles (built before any file is opened).
  World world;
  std::vector<std::string> world_warnings;
  const std::string error = buildWorld(worldSpecOf(scenario), &world, &world_warnings);
  const std::string run = error.empty() ? runScenario(scenario, world, out_dir, summary, observers) : error;
  if (run.empty() && summary != nullptr)
  {
    summary->world_warnings = std::move(world_warnings);
  }
  return run;
}

std::string runScenario(const Scenario& scenario, World& world, const std::string& out_dir, RunSummary* summary,
                        const std::vector<RunObserver*>& observers, const volatile std::sig_atomic_t* interrupt)
{
  const std::string rate_error = scenario.checkOutputRate();
  if (!rate_error.empty())
  {
    return rate_error;
  }
  const std::string size_error = scenario.checkRunSize();
  if (!size_error.empty())
  {
    return size_error;
  }
  ScenarioStepper stepper(scenario, world);
  stepper.setInterrupt(interrupt);
  const std::vector<ScenarioTether>& tethers = stepper.tethers();
  if (world.size() != tethers.size())
  {
    return "tethers: the world holds " + std::to_string(world.size()) + ", the scenario " +
           std::to_string(tethers.size());
  }

  std::vector<OutputFile> files = outputFilesOf(scenario, tethers, out_dir);
  std::vector<fs::path> written;
  for (const OutputFile& file : files)
  {
    written.push_back(file.path);
  }
  std::vector<std::string> earlier = earlierOutputs(scenario, out_dir, written);
  const std::string open_error = openAll(files);
  if (!open_error.empty())
  {
    return open_error;
  }
  // From here on every way out, an exception's too (a value the core refuses that no check of the scenario did, an
  // observer's), leaves no temporary behind: the CSV files' and the observers' own (a camera dataset: started after
  // the CSV files, moved into place with them), each observer started committed once.
  std::size_t started = 0;
  bool committed = false;
  sigset_t held, before;
  sigemptyset(&held);
  sigaddset(&held, SIGINT);
  sigaddset(&held, SIGTERM);
  bool blocked = false;
  const auto commitObservers = [&](bool keep, std::vector<std::string>* left)
  {
    committed = true;
    std::string error;
    for (std::size_t i = 0; i < started; ++i)
    {
      const std::string done = observers[i]->commit(keep, left);
      error = error.empty() ? done : error;
    }
    return error;
  };
  const auto finishObservers = [&]
  {
    std::string error;
    for (std::size_t i = 0; i < started; ++i)
    {
      const std::string finished = observers[i]->finishWriting();
      error = error.empty() ? finished : error;
    }
    return error;
  };
  const auto abandon = [&]
  {
    discardAll(files);
    if (!committed)
    {
      std::vector<std::string> left;
      finishObservers();
      commitObservers(false, &left);
    }
    if (blocked)
    {
      pthread_sigmask(SIG_SETMASK, &before, nullptr);
      blocked = false;
    }
  };
  std::string start_error, finish_error, close_error, commit_error;
  std::vector<std::string> replaced_left;
  std::vector<RunSummary> each;
  std::size_t topology_rows = 0;
  double recording_seconds = 0.0;
  try
  {
    for (; started < observers.size() && start_error.empty(); ++started)
    {
      start_error = observers[started]->startWriting();
    }
    if (!start_error.empty())
    {
      abandon();
      return start_error;
    }
    std::FILE* const topology_file = scenario.usesWorld() ? files.back().file : nullptr;
    each = startOutputs(tethers, world, files, topology_file);
    StepRecord every_step(world, each);
    stepper.setStepObserver(&every_step);
    topology_rows = writeOutputs(scenario, world, stepper, observers, files, topology_file, each);
    stepper.setStepObserver(nullptr);
    recording_seconds = every_step.seconds();
    finish_error = finishObservers();
    const bool ok = stepper.observerError().empty() && stepper.runError().empty() && finish_error.empty();
    if (interrupt != nullptr)
    {
      pthread_sigmask(SIG_BLOCK, &held, &before);  // a signal now waits until the outputs are in place, or all gone
      blocked = true;
    }
    close_error = closeAll(files, ok, out_dir, &replaced_left);
    // After the CSV files, the observers' outputs: moved into place only where the CSV files were.
    const bool kept = ok && close_error.empty();
    commit_error = commitObservers(kept, &replaced_left);
    if (!commit_error.empty() && kept)
    {
      commit_error += ". The CSV outputs are this run's";
    }
    if (blocked)
    {
      pthread_sigmask(SIG_SETMASK, &before, nullptr);
      blocked = false;
    }
  }
  catch (...)
  {
    stepper.setStepObserver(nullptr);
    abandon();
    throw;
  }
  if (!stepper.runError().empty())
  {
    if (summary != nullptr && stepper.interrupted())
    {
      summary->interrupted = true;
    }
    return stepper.runError();
  }
  if (!stepper.observerError().empty())
  {
    return stepper.observerError();
  }
  if (!finish_error.empty())
  {
    return finish_error;
  }
  if (!close_error.empty())
  {
    return close_error;
  }
  if (!commit_error.empty())
  {
    if (summary != nullptr)
    {
      summary->replaced_left = std::move(replaced_left);  // the CSV files' copies moved aside, said with the error
    }
    return commit_error;
  }
  RunSummary result = summaryOf(world, std::move(each), topology_rows, stepper.cpuSeconds() - recording_seconds);
  result.earlier_outputs = std::move(earlier);
  result.replaced_left = std::move(replaced_left);
  if (summary != nullptr)
  {
    *summary = result;
  }
  return "";
}

std::vector<std::string> runWarnings(const Scenario& scenario, const RunSummary& summary, double max_tension_warning)
{
  std::vector<std::string> warnings = summary.world_warnings;
  const auto listed = [](const std::vector<std::string>& items)
  {
    std::string list;
    for (const std::string& item : items)
    {
      list += (list.empty() ? "" : "; ") + item;
    }
    return list;
  };
  if (!summary.earlier_outputs.empty())
  {
    warnings.push_back("the output directory holds an earlier run's outputs that this run did not replace: " +
                       listed(summary.earlier_outputs) +
                       ". They are left as they were: remove them, or write to an empty directory");
  }
  if (!summary.replaced_left.empty())
  {
    warnings.push_back("this run replaced earlier outputs but could not remove the copies it moved aside: " +
                       listed(summary.replaced_left) +
                       ". Delete them: the next run into this directory refuses to start while they are there");
  }
  const std::vector<ScenarioTether> tethers = scenario.tetherList();
  const std::vector<RunSummary>& each = summary.tethers.empty() ? std::vector<RunSummary>{summary} : summary.tethers;
  for (std::size_t i = 0; i < each.size() && i < tethers.size(); ++i)
  {
    const RunSummary& s = each[i];
    const TetherParams& p = tethers[i].params;
    const std::string who = scenario.tethers.empty() ? "" : "tether " + s.name + ": ";
    char line[512];
    if (s.recoveries > 0)
    {
      warnings.push_back(who + "simulation failure (" + std::to_string(s.recoveries) +
                         "), the last: " + s.last_failure);
    }
    if (s.out_of_reach > 0)
    {
      // As the node warns of it (TetherDiagnostics), with the run's time and count.
      std::snprintf(line, sizeof line, "vehicle out of the cable's reach (%llu) from t = %.2f s, the last: ",
                    static_cast<unsigned long long>(s.out_of_reach), s.first_out_of_reach_time);
      warnings.push_back(who + line + s.last_out_of_reach);
    }
    const double warn_above =
        std::isnan(tethers[i].max_tension_warning) ? max_tension_warning : tethers[i].max_tension_warning;
    if (s.max_tension > warn_above)
    {
      std::snprintf(line, sizeof line,
                    "over-tension: %.4g N at t = %.2f s, above max_tension_warning = %.4g N (max strain %.3g)",
                    s.max_tension, s.max_tension_time, warn_above, s.max_strain);
      warnings.push_back(who + line);
    }
    if (s.outrun_seconds > 0.0)
    {
      std::snprintf(line, sizeof line,
                    "the vehicle outruns the winch for %.3g s in all from t = %.2f s: it pays out at "
                    "max_winch_speed = %.3g m/s and the cable stretches",
                    s.outrun_seconds, s.first_outrun_time, p.max_winch_speed);
      warnings.push_back(who + line);
    }
    if (s.first_full_time >= 0.0)
    {
      std::snprintf(line, sizeof line,
                    "the cable runs out at t = %.2f s: all of cable_length = %.4g m is paid out, and from then on "
                    "the winch has no more to give (the cable stretches where the vehicle pulls on)",
                    s.first_full_time, p.cable_length);
      warnings.push_back(who + line);
    }
    if (s.stall_seconds > 0.0)
    {
      std::snprintf(line, sizeof line,
                    "the winch cannot reel in at its commanded %.3g m/s for %.3g s in all from t = %.2f s: the "
                    "spool tension holds it at the motor's stall pull of %.4g N (max_winch_pull%s)",
                    s.first_stall_speed, s.stall_seconds, s.first_stall_time, p.winchPull(),
                    p.max_winch_pull > 0.0 ? ""
                                           : " 0: 1.25 x the larger of target_tension + tension_deadband and "
                                             "brake_tension");
      warnings.push_back(who + line);
    }
    if (s.shortest_seconds > 0.0)
    {
      std::snprintf(line, sizeof line,
                    "the winch stands at min_deployed_length = %.4g m for %.3g s in all from t = %.2f s: winch_speed = "
                    "%.3g m/s asks it to reel in further, which it does not (it slowed down to stop there)",
                    p.min_deployed_length, s.shortest_seconds, s.first_shortest_time, p.winch_speed);
      warnings.push_back(who + line);
    }
  }
  return warnings;
}

}  // namespace rov_tether
