// rov_tether_run: runs a scenario offline (no ROS master) and writes state.csv and shape.csv (per tether, and
// topology.csv, for a scenario with obstacles or several tethers).
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "rov_tether/core/direct_solver.hpp"
#include "rov_tether/scenario/camera_dataset.hpp"
#include "rov_tether/scenario/scenario_runner.hpp"
#include "rov_tether/scenario/scenario_yaml.hpp"
#include "rov_tether/scenario/world_spec.hpp"

namespace
{

void usage(std::FILE* out)
{
  std::fprintf(
      out,
      "usage: rov_tether_run SCENARIO.yaml --out DIR [--set name=value]...   (or --out=DIR, --set=name=value)\n"
      "       rov_tether_run --parameters[=markdown|yaml|cfg]   (prints the README's parameter table,\n"
      "         config/default.yaml or cfg/Tether.cfg as the parameter table generates them)\n"
      "  Runs the scenario and writes DIR/state.csv and DIR/shape.csv, and with `cameras:` the\n"
      "  dataset DIR/cameras/<name>/mask_NNNNNN.png, depth_NNNNNN.png (mm) and index.csv.\n"
      "  With `tethers:`, DIR/<name>/state.csv and shape.csv per tether; with `tethers:`,\n"
      "  `obstacles:` or `tether_contact: true`, also DIR/topology.csv; with a dynamic vehicle\n"
      "  (`vehicle: {model: dynamic, ...}`), DIR/vehicle.csv.\n"
      "  --set overrides a model parameter after the scenario's own params (every tether's); each\n"
      "  parameter and each option once.\n"
      "  --max-tension-warning N: warn of a tension above N newtons (default 500, the node's), for\n"
      "                          each tether that does not set its own max_tension_warning.\n"
      "  Warnings (stderr, as the node logs them): simulation failures, a vehicle out of its cable's reach,\n"
      "  over-tension, an outrun winch, a reel-in held at the winch's stall pull.\n"
      "  Exit codes: 0 success, 2 bad scenario or arguments, 1 a simulation that refused to go on or an\n"
      "  output error. Stopped by SIGINT (Ctrl-C) or SIGTERM it writes no CSV output and ends by that\n"
      "  signal (the shell's 130 or 143); a second Ctrl-C ends it at once.\n");
}

/// The signal that asked the run to stop (SIGINT, SIGTERM; the first of them), 0 while none: set by onStopSignal,
/// read between the stretches the run advances (ScenarioStepper::setInterrupt).
volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void onStopSignal(int signal_number)
{
  if (g_stop_signal == 0)
  {
    g_stop_signal = signal_number;
  }
}

/// From here on, SIGINT and SIGTERM ask the run to stop where it can leave the output directory as it was. Each
/// handler is taken once (SA_RESETHAND), so that a second Ctrl-C ends the program at once, as it would have; a
/// signal the program was started ignoring (a job started in the background by a shell) stays ignored.
void stopOnSignals()
{
  struct sigaction action = {};
  action.sa_handler = onStopSignal;
  sigemptyset(&action.sa_mask);
  sigaddset(&action.sa_mask, SIGINT);
  sigaddset(&action.sa_mask, SIGTERM);
  action.sa_flags = SA_RESETHAND | SA_RESTART;
  for (const int signal_number : {SIGINT, SIGTERM})
  {
    struct sigaction was = {};
    if (sigaction(signal_number, nullptr, &was) == 0 && was.sa_handler != SIG_IGN)
    {
      sigaction(signal_number, &action, nullptr);
    }
  }
}

/// The command line's choices.
struct Options
{
  std::string scenario_path;
  std::string out_dir;
  std::vector<std::string> assignments;  ///< the --set name=value, in order
  double max_tension_warning = rov_tether::kDefaultMaxTensionWarning;
};

/// Prints the generated parameter file asked for by `--parameters[=FORMAT]`; the exit code.
int printParameters(const std::string& arg)
{
  // The files generated from the parameter table (scripts/generate_parameters.py writes them).
  const std::string format = arg == "--parameters" ? "markdown" : arg.substr(std::strlen("--parameters="));
  if (format != "markdown" && format != "yaml" && format != "cfg")
  {
    std::fprintf(stderr, "rov_tether_run: --parameters=%s: expected markdown, yaml or cfg\n", format.c_str());
    return 2;
  }
  std::fputs((format == "markdown" ? rov_tether::parameterTableMarkdown()
              : format == "yaml"   ? rov_tether::defaultYaml()
                                   : rov_tether::dynamicReconfigureCfg())
                 .c_str(),
             stdout);
  return 0;
}

/// Reads the command line into options; -1 to go on, else the exit code (help, --parameters or a bad argument).
int parseArguments(int argc, char** argv, Options* options)
{
  // What each option and each --set parameter was given as, so that a second one is refused rather than the
  // first dropped without a word.
  std::map<std::string, std::string> given;
  const auto once = [&given](const std::string& key, const std::string& text)
  {
    const auto [where, first] = given.emplace(key, text);
    if (!first)
    {
      std::fprintf(stderr, "rov_tether_run: %s given twice ('%s' and '%s'): give it once\n", key.c_str(),
                   where->second.c_str(), text.c_str());
    }
    return first;
  };
  for (int i = 1; i < argc; ++i)
  {
    std::string arg = argv[i];
    // An option's value after it (`--set name=value`) or joined by '=' (`--set=name=value`).
    std::string joined;
    bool is_joined = false;
    for (const char* name : {"--out", "--set", "--max-tension-warning"})
    {
      const std::string prefix = std::string(name) + "=";
      if (arg.rfind(prefix, 0) == 0 && arg.size() > prefix.size())
      {
        joined = arg.substr(prefix.size());
        arg = name;
        is_joined = true;
      }
    }
    const bool has_value = is_joined || i + 1 < argc;
    auto value = [&]() -> std::string { return is_joined ? joined : argv[++i]; };
    if (arg == "-h" || arg == "--help")
    {
      usage(stdout);
      return 0;
    }
    if (arg == "--parameters" || arg.rfind("--parameters=", 0) == 0)
    {
      return printParameters(arg);
    }
    if (arg == "--max-tension-warning" && has_value)
    {
      const std::string text = value();
      if (!once(arg, text))
      {
        return 2;
      }
      char* end = nullptr;
      options->max_tension_warning = std::strtod(text.c_str(), &end);
      if (end == text.c_str() || *end != '\0' || !(options->max_tension_warning >= 0.0))
      {
        std::fprintf(stderr, "rov_tether_run: --max-tension-warning '%s': expected a number >= 0 [N]\n", text.c_str());
        return 2;
      }
    }
    else if ((arg == "--out" || arg == "--set") && has_value)
    {
      const std::string text = value();
      // A parameter's name is what comes before its '=', without the spaces around it, which applyAssignments
      // drops too (a malformed assignment is applyAssignments' to refuse).
      std::string name = text.substr(0, text.find('='));
      name.erase(name.find_last_not_of(" \t") + 1);
      name.erase(0, name.find_first_not_of(" \t"));
      if (!once(arg == "--out" ? arg : "--set " + name, text))
      {
        return 2;
      }
      (arg == "--out" ? options->out_dir : options->assignments.emplace_back()) = text;
    }
    else if (!arg.empty() && arg[0] != '-' && options->scenario_path.empty())
    {
      options->scenario_path = arg;
    }
    else
    {
      std::fprintf(stderr, "rov_tether_run: unexpected argument '%s'\n", arg.c_str());
      usage(stderr);
      return 2;
    }
  }
  if (options->scenario_path.empty() || options->out_dir.empty())
  {
    usage(stderr);
    return 2;
  }
  return -1;
}

/// Loads the scenario and applies the --set assignments, all together (their order does not matter), to the
/// scenario's tether or, with `tethers:`, to each of them (the scenario's own parameters are then not used, and a
/// value they would refuse is none of the run's business); "" or the error, naming the tether.
std::string loadScenarioWithOverrides(const Options& options, rov_tether::Scenario* scenario)
{
  const auto checked = [scenario]
  {
    const std::string rate = scenario->checkOutputRate();
    return rate.empty() ? scenario->checkRunSize() : rate;
  };
  const std::string loaded = rov_tether::loadScenario(options.scenario_path, scenario);
  if (!loaded.empty() || options.assignments.empty())
  {
    return loaded.empty() ? checked() : loaded;
  }
  if (scenario->tethers.empty())
  {
    const std::string error = rov_tether::applyAssignments(options.assignments, &scenario->params);
    return error.empty() ? checked() : "--set " + error;
  }
  for (auto& tether : scenario->tethers)
  {
    const std::string error = rov_tether::applyAssignments(options.assignments, &tether.params);
    if (!error.empty())
    {
      return "--set, tether " + tether.name + ": " + error;
    }
  }
  return checked();
}

/// Decimals that print `seconds` as it is, 2 to 6 (50.00 s; a step of 0.005 s ends at 0.015 s, not "0.01").
int decimals(double seconds)
{
  int d = 2;
  while (d < 6 && std::abs(std::round(seconds * std::pow(10.0, d)) - seconds * std::pow(10.0, d)) > 1e-6)
  {
    ++d;
  }
  return d;
}

/// Prints what ran: the scenario, its tethers, the model (the first tether's, `auto` resolved) and the figures.
void printRun(const rov_tether::Scenario& scenario, const std::string& scenario_path, const rov_tether::RunSummary& s)
{
  // What ran (`auto` replaced by its choice): the first tether's model, for a `tethers` list.
  const rov_tether::TetherParams p =
      (scenario.tethers.empty() ? scenario.params : scenario.tethers.front().params).resolved();
  std::printf("scenario        %s%s%s\n", scenario_path.c_str(), scenario.description.empty() ? "" : ": ",
              scenario.description.c_str());
  if (!scenario.tethers.empty())
  {
    std::printf(
        "tethers         %zu in one world, %zu obstacles, contact between tethers %s; the lines up to "
        "max strain are the first tether's, '%s' (the steps: all tethers)\n",
        scenario.tethers.size(), scenario.obstacles.size(), scenario.tether_contact ? "on" : "off",
        scenario.tethers.front().name.c_str());
  }
  std::printf(
      "model           solver %s, %d iterations, bending %s, drag %.3g, noise %.3g m, dt %.4g s, "
      "segment %.3g m\n",
      rov_tether::toString(p.solver).c_str(), p.iterations, p.bending ? "on" : "off", p.drag, p.noise, p.time_step,
      p.segment_length);
  std::printf("simulated       %.*f s in %llu steps, %.3f s CPU (%.0fx real time)\n", decimals(s.simulated),
              s.simulated, static_cast<unsigned long long>(s.steps), s.cpu_seconds,
              s.cpu_seconds > 0 ? s.simulated / s.cpu_seconds : 0.0);
  std::printf("deployed length start %.3f m, end %.3f m, max %.3f m (cable %.3f m, winch %s)\n", s.deployed_start,
              s.deployed_end, s.deployed_max, p.cable_length, rov_tether::toString(p.winch_mode).c_str());
  std::printf("tension         max %.4g N anywhere, max %.4g N at the vehicle\n", s.max_tension, s.max_tension_vehicle);
  std::printf("max strain      %.4g%s\n", s.max_strain, s.jumps ? "" : "");
  if (s.solver.substeps > 0)
  {
    std::printf(
        "newton          %.2f iterations per sub-step, at most %d (of %d); residual at most %.3g of a segment\n",
        s.solver.meanIterations(), s.solver.max_iterations, p.iterations, s.solver.max_residual);
    if (s.solver.rescued > 0)
    {
      std::printf(
          "                %llu sub-step%s diverged within the %d iterations and went on past them (rescue: up "
          "to %dx as many more, at most %d)\n",
          static_cast<unsigned long long>(s.solver.rescued), s.solver.rescued == 1 ? " had" : "s had", p.iterations,
          rov_tether::DirectSolver::kRescueBudget, rov_tether::DirectSolver::kMaxRescueIterations);
    }
    if (s.solver.unconverged > 0)
    {
      std::printf(
          "                %llu sub-step%s stopped short of solver_tolerance %.3g (state.csv's newton_residual "
          "shows when)\n",
          static_cast<unsigned long long>(s.solver.unconverged), s.solver.unconverged == 1 ? "" : "s",
          p.solver_tolerance);
    }
  }
  if (s.jumps > 0)
  {
    std::printf("vehicle jumps   %llu (cable re-laid)\n", static_cast<unsigned long long>(s.jumps));
  }
}

/// Prints the files written: per tether, the topology and each camera's dataset.
void printWritten(const rov_tether::Scenario& scenario, const std::string& out_dir, const rov_tether::RunSummary& s,
                  const rov_tether::CameraDataset* dataset)
{
  if (scenario.tethers.empty())
  {
    std::printf("wrote           %s/state.csv (%zu rows), %s/shape.csv (%zu rows)\n", out_dir.c_str(), s.state_rows,
                out_dir.c_str(), s.shape_rows);
  }
  for (const auto& t : scenario.tethers.empty() ? std::vector<rov_tether::RunSummary>{} : s.tethers)
  {
    std::printf(
        "tether %-8s deployed end %.3f m, max tension %.4g N; wrote %s/%s/state.csv (%zu rows), shape.csv "
        "(%zu rows)\n",
        t.name.c_str(), t.deployed_end, t.max_tension, out_dir.c_str(), t.name.c_str(), t.state_rows, t.shape_rows);
  }
  for (const auto& t : s.tethers.empty() ? std::vector<rov_tether::RunSummary>{s} : s.tethers)
  {
    if (t.vehicle_rows > 0)
    {
      std::printf("wrote           %s%s/vehicle.csv (%zu rows): a dynamic vehicle\n", out_dir.c_str(),
                  scenario.tethers.empty() ? "" : ("/" + t.name).c_str(), t.vehicle_rows);
    }
  }
  if (scenario.usesWorld())
  {
    std::printf("wrote           %s/topology.csv (%zu rows)\n", out_dir.c_str(), s.topology_rows);
  }
  for (const auto& camera : dataset ? dataset->summary() : std::vector<rov_tether::CameraDataset::CameraSummary>{})
  {
    std::printf("camera %-8s %s/cameras/%s/: %zu frames, tether in %zu, coverage mean %.4f, max %.4f\n",
                camera.name.c_str(), out_dir.c_str(), camera.name.c_str(), camera.frames, camera.frames_with_tether,
                camera.mean_coverage, camera.max_coverage);
  }
}

}  // namespace

int run(int argc, char** argv)
{
  Options options;
  const int exit_code = parseArguments(argc, argv, &options);
  if (exit_code >= 0)
  {
    return exit_code;
  }
  const std::string& scenario_path = options.scenario_path;
  const std::string& out_dir = options.out_dir;

  rov_tether::Scenario scenario;
  std::string error = loadScenarioWithOverrides(options, &scenario);
  if (!error.empty())
  {
    std::fprintf(stderr, "rov_tether_run: %s\n", error.c_str());
    return 2;
  }
  // The world, built once from the scenario's description (each mesh file read here): one that cannot be
  // built is a bad scenario, as a field that cannot be read is.
  rov_tether::World world;
  std::vector<std::string> world_warnings;
  error = rov_tether::buildWorld(rov_tether::worldSpecOf(scenario), &world, &world_warnings);
  if (!error.empty())
  {
    std::fprintf(stderr, "rov_tether_run: %s: %s\n", scenario_path.c_str(), error.c_str());
    return 2;
  }

  std::unique_ptr<rov_tether::CameraDataset> dataset;
  std::vector<rov_tether::RunObserver*> observers;
  if (!scenario.cameras.empty())
  {
    std::string why;
    dataset = rov_tether::makeCameraDataset(scenario, out_dir, &why);
    if (!dataset)
    {
      std::fprintf(stderr, "rov_tether_run: %s: cameras: %s\n", scenario_path.c_str(), why.c_str());
      return 2;
    }
    observers.push_back(dataset.get());
  }
  rov_tether::RunSummary s;
  stopOnSignals();
  error = rov_tether::runScenario(scenario, world, out_dir, &s, observers, &g_stop_signal);
  const int stopped_by = g_stop_signal;
  const char* const signal_name = stopped_by == SIGINT ? "SIGINT" : "SIGTERM";
  if (!error.empty())
  {
    for (const std::string& warning : world_warnings)
    {
      std::fprintf(stderr, "rov_tether_run: warning: %s\n", warning.c_str());
    }
  }
  if (!error.empty() && s.interrupted)
  {
    // Stopped from outside: said as what it is, not as an output error (the CSVs' temporaries are removed, the
    // earlier outputs left as they were, as for any run that fails); then ended by the signal, as the program
    // would have been without its handler, so that a shell or a script that runs it sees the signal.
    std::fprintf(stderr,
                 "rov_tether_run: stopped by %s, %s of the scenario's %.6g s: no CSV output (state, shape, vehicle, "
                 "topology) was written, and the output directory's earlier ones are as they were%s\n",
                 signal_name, error.c_str(), scenario.duration,
                 dataset ? "; nor was any camera's dataset: cameras/ is as it was" : "");
    std::fflush(stderr);
    std::signal(stopped_by, SIG_DFL);
    std::raise(stopped_by);
    return 128 + stopped_by;  // not reached: the signal's default action ends the program
  }
  if (!error.empty())
  {
    std::fprintf(stderr, "rov_tether_run: %s\n", error.c_str());
    for (const std::string& left : s.replaced_left)
    {
      std::fprintf(stderr,
                   "rov_tether_run: warning: a replaced output moved aside could not be removed: %s. Delete it: the "
                   "next run into this directory refuses to start while it is there\n",
                   left.c_str());
    }
    return 1;
  }
  s.world_warnings = std::move(world_warnings);  // said with the run's warnings, after the summary
  if (stopped_by != 0)
  {
    // The signal came as the run finished (while its outputs moved into place): they are whole, and said so.
    s.world_warnings.push_back(std::string(signal_name) + " came after the run had finished: its outputs are complete");
  }
  printRun(scenario, scenario_path, s);
  printWritten(scenario, out_dir, s, dataset.get());
  for (const std::string& warning : rov_tether::runWarnings(scenario, s, options.max_tension_warning))
  {
    std::fprintf(stderr, "rov_tether_run: warning: %s\n", warning.c_str());
  }
  return 0;
}

int main(int argc, char** argv)
{
  // Every refusal the runner knows is a message and exit code 2 or 1; an exception that still gets here is a check
  // missing before the core (a value the core refuses that no reader did): said, not an abort.
  try
  {
    return run(argc, argv);
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "rov_tether_run: %s (refused by the simulation, not by a check of the scenario)\n", e.what());
    return 2;
  }
}
