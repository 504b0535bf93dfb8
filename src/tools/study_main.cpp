// rov_tether_study: the speed-against-accuracy study and the stability map (docs/accuracy.md, "Speed against
// accuracy"). Runs every reference case for each method x resolution x effort and writes
// OUT/study.csv and OUT/stability.csv for scripts/figures.py.
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "rov_tether/scenario/output_files.hpp"
#include "rov_tether/study/study.hpp"

namespace
{

using rov_tether::SolverType;
using rov_tether::TetherParams;
using namespace rov_tether::study;

struct Effort
{
  int substeps;
  int iterations;
  double critical_fraction;  ///< lumped_mass: sub-step as a fraction of the critical step (else 0)
  double time_step;          ///< [s]; 0 = the case's step
  double relax = 1.0;        ///< pbd: over_relaxation
};

std::vector<int> resolutions(const std::string& name, bool quick)
{
  if (quick)
  {
    return {10, 20};
  }
  if (name == "axial_drag")
  {
    return {10, 25, 50, 100};
  }
  if (name == "catenary_100m")
  {
    return {1000};  // the 1,000-segment case: 0.1 m segments
  }
  if (name == "paper_experiment")
  {
    return {25, 50, 100};
  }
  if (name.rfind("catenary", 0) == 0)
  {
    return {10, 20, 40, 80};
  }
  return {10, 20, 40};
}

/// The efforts of a method. A case whose step is part of it (`keep_step`) takes each at its own step once: the
/// three steps ran every one of its configurations three times over.
std::vector<Effort> efforts(SolverType method, bool quick, bool keep_step)
{
  std::vector<Effort> out;
  const std::vector<double> steps = keep_step ? std::vector<double>{0.0}  // 0: the case's step
                                    : quick   ? std::vector<double>{0.005}
                                              : std::vector<double>{0.005, 0.02, 0.05};
  switch (method)
  {
    case SolverType::kPbd:
      for (double dt : steps)
      {
        for (int iterations : quick ? std::vector<int>{10, 50} : std::vector<int>{2, 5, 10, 20, 50, 100})
        {
          for (double relax : quick ? std::vector<double>{1.0} : std::vector<double>{1.0, 1.8})
          {
            out.push_back({1, iterations, 0.0, dt, relax});
          }
        }
      }
      break;
    case SolverType::kXpbd:
      for (double dt : steps)
      {
        for (auto [substeps, iterations] :
             quick ? std::vector<std::pair<int, int>>{{1, 20}, {4, 5}}
                   : std::vector<std::pair<int, int>>{{1, 5}, {1, 20}, {1, 100}, {4, 1}, {4, 5}, {16, 1}, {16, 5}})
        {
          out.push_back({substeps, iterations, 0.0, dt, 1.0});
        }
      }
      break;
    case SolverType::kDirect:
      // Newton stops on solver_tolerance; `iterations` only caps it. The step is the effort knob.
      for (double dt : steps)
      {
        out.push_back({1, 10, 0.0, dt, 1.0});
      }
      break;
    default:
      // The step does not matter: the sub-step is a fraction of the critical step.
      for (double fraction : quick ? std::vector<double>{0.5} : std::vector<double>{0.9, 0.5, 0.2})
      {
        out.push_back({0, 1, fraction, 0.0, 1.0});
      }
  }
  return out;
}

void writeResult(std::FILE* out, const Result& r)
{
  std::fprintf(out, "%s,%s,%d,%d,%d,%g,%g,%.6g,%.6g,%.6g,%d,%s\n", r.scenario.c_str(), r.method.c_str(), r.segments,
               r.iterations, r.substeps, r.over_relaxation, r.time_step, r.shape_error, r.tension_error, r.cost,
               r.failed ? 1 : 0, r.label.c_str());
  std::fflush(out);
}

void usage()
{
  std::fprintf(stderr,
               "usage: rov_tether_study --out DIR [--quick] [--case NAME] [--no-stability]\n"
               "  Runs the reference cases of docs/references.md for pbd, xpbd, lumped_mass and direct at several\n"
               "  resolutions and efforts; writes DIR/study.csv and DIR/stability.csv.\n");
}

/// The command line's choices.
struct Options
{
  std::string out_dir;
  std::string only;  ///< one case's name, or "" for all
  bool quick = false;
  bool with_stability = true;
};

/// Whether `name` is one of the study's cases.
bool isCase(const std::string& name)
{
  for (const Case& c : cases())
  {
    if (c.name == name)
    {
      return true;
    }
  }
  return false;
}

/// Reads the command line; false (after printing the usage or what is wrong) when it is wrong.
bool parseOptions(int argc, char** argv, Options* options)
{
  std::set<std::string> given;  // an option given twice is refused, not the first dropped without a word
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (!given.insert(arg).second && arg.rfind("--", 0) == 0)
    {
      std::fprintf(stderr, "rov_tether_study: %s given twice: give it once\n", arg.c_str());
      usage();
      return false;
    }
    if (arg == "--out" && i + 1 < argc)
    {
      options->out_dir = argv[++i];
    }
    else if (arg == "--case" && i + 1 < argc)
    {
      options->only = argv[++i];
    }
    else if (arg == "--quick")
    {
      options->quick = true;
    }
    else if (arg == "--no-stability")
    {
      options->with_stability = false;
    }
    else
    {
      usage();
      return false;
    }
  }
  if (options->out_dir.empty())
  {
    usage();
    return false;
  }
  if (!options->only.empty() && !isCase(options->only))
  {
    // It ran no case and wrote a study.csv of the header alone, with exit code 0.
    std::string names;
    for (const Case& c : cases())
    {
      names += (names.empty() ? "" : ", ") + c.name;
    }
    std::fprintf(stderr, "rov_tether_study: no case called '%s'; the cases: %s\n", options->only.c_str(),
                 names.c_str());
    return false;
  }
  return true;
}

/// Sets the effort's iterations, sub-steps, over-relaxation and (unless it is 0) time step on p.
void applyEffort(const Effort& effort, TetherParams& p)
{
  if (effort.time_step > 0.0)
  {
    p.time_step = effort.time_step;
  }
  p.iterations = effort.iterations;
  p.substeps = effort.substeps;
  p.over_relaxation = effort.relax;
  if (effort.critical_fraction > 0.0)
  {
    p.substeps = static_cast<int>(std::ceil(p.time_step / (effort.critical_fraction * p.criticalStep())));
  }
}

/// Runs case c for every method x resolution x effort, writing each row; keeps the cheapest accurate run
/// (shape 1%, tension 2%) per method in `best`.
void sweepCase(const Case& c, bool quick, std::FILE* out, std::map<std::string, Result>& best)
{
  for (SolverType method : {SolverType::kPbd, SolverType::kXpbd, SolverType::kLumpedMass, SolverType::kDirect})
  {
    for (int segments : resolutions(c.name, quick))
    {
      // The paper's step is part of its case.
      for (const Effort& effort : efforts(method, quick, c.name == "paper_experiment"))
      {
        TetherParams p = c.base(segments);
        p.solver = method;
        applyEffort(effort, p);
        if (p.substeps > 10000)
        {
          continue;
        }
        const Result r = c.run(p);
        writeResult(out, r);
        const bool accurate = r.shape_error <= 0.01 && !(r.tension_error > 0.02);
        if (accurate && (best.count(r.method) == 0 || r.cost < best[r.method].cost))
        {
          best[r.method] = r;
        }
      }
    }
  }
}

/// The automatic choice on case c (catenary_s8) for pbd, the paper's solver, whose iterations `iterations: auto`
/// chooses: resolution from a shape tolerance on the catenary's tightest radius a = H / w, effort from a stretch
/// tolerance; writes and prints each run.
void runAutomaticChoice(const Case& c, std::FILE* out)
{
  Catenary reference;
  reference.stiffness = 1e5;
  reference.solve(8.0);
  for (double shape : {0.01, 0.001})
  {
    for (double stretch : {0.01, 0.001})
    {
      TetherParams p = c.base(10);
      p.solver = SolverType::kPbd;  // before resolved(): the iterations it chooses are pbd's
      p.segment_length_auto = true;
      p.shape_tolerance = shape;
      p.min_bend_radius = reference.horizontal / reference.weight;
      p.iterations_auto = true;
      p.stretch_tolerance = stretch;
      p = p.resolved();
      p.min_deployed_length = p.segment_length;
      Result r = c.run(p);
      r.label = "auto";
      writeResult(out, r);
      std::printf(
          "   auto, %s (shape %g m, stretch %g): %d segments, %d iterations: sag %.3f%%, tension %.3f%%, %.0f us/s\n",
          r.method.c_str(), shape, stretch, r.segments, r.iterations, 100 * r.shape_error, 100 * r.tension_error,
          r.cost);
    }
  }
}

/// Writes study.csv to `out`: every case (or only `only`) swept, with the cheapest accurate run per method
/// printed.
void writeStudy(const Options& options, std::FILE* out)
{
  std::fprintf(
      out,
      "scenario,method,segments,iterations,substeps,over_relaxation,time_step,shape_error,tension_error,cost_us_per_s,"
      "failed,label\n");
  // Cheapest run per case and method that meets the goal's accuracy (shape 1%, tension 2%).
  std::map<std::string, std::map<std::string, Result>> cheapest;
  for (const Case& c : cases())
  {
    if (!options.only.empty() && c.name != options.only)
    {
      continue;
    }
    std::printf("== %s (%s)\n", c.name.c_str(), c.reference.c_str());
    sweepCase(c, options.quick, out, cheapest[c.name]);
    if (c.name == "catenary_s8")
    {
      runAutomaticChoice(c, out);
    }
    for (const auto& [method, r] : cheapest[c.name])
    {
      std::printf(
          "   cheapest within 1%% shape / 2%% tension: %-11s %3d segments, %2d substeps x %3d iterations, "
          "SOR %.1f, dt %.3f s: %9.0f us per simulated s\n",
          method.c_str(), r.segments, r.substeps, r.iterations, r.over_relaxation, r.time_step, r.cost);
    }
  }
}

/// The cheapest accurate run (sag within 1%, end tension within 2%) per method on case c at axial stiffness
/// EA, and the cheapest pbd without over-relaxation as "pbd without over-relaxation".
std::map<std::string, Result> cheapestAtStiffness(const Case& c, double stiffness, bool quick)
{
  std::map<std::string, Result> best;
  for (SolverType method : {SolverType::kPbd, SolverType::kXpbd, SolverType::kLumpedMass, SolverType::kDirect})
  {
    for (int segments : {10, 20})
    {
      for (const Effort& effort : efforts(method, quick, false))
      {
        TetherParams p = c.base(segments);
        p.axial_stiffness = stiffness;
        p.solver = method;
        applyEffort(effort, p);
        const Result r = c.run(p);
        const bool accurate = r.shape_error <= 0.01 && r.tension_error <= 0.02;
        if (accurate && (best.count(r.method) == 0 || r.cost < best[r.method].cost))
        {
          best[r.method] = r;
        }
        const std::string plain = "pbd without over-relaxation";
        if (accurate && r.method == "pbd" && r.over_relaxation == 1.0 &&
            (best.count(plain) == 0 || r.cost < best[plain].cost))
        {
          best[plain] = r;
        }
      }
    }
  }
  return best;
}

/// Prints the goal's comparison lines for one stiffness from cheapestAtStiffness's runs.
void printGoal(double stiffness, std::map<std::string, Result>& best)
{
  if (best.count("direct") && best.count("lumped_mass") && best.count("xpbd"))
  {
    std::printf(
        "goal, catenary S = 8 at EA = %.0e N: cheapest direct %.0f us/s (%d segments, dt %g s): "
        "lumped_mass / direct = %.1f, xpbd / direct = %.1f\n",
        stiffness, best["direct"].cost, best["direct"].segments, best["direct"].time_step,
        best["lumped_mass"].cost / best["direct"].cost, best["xpbd"].cost / best["direct"].cost);
  }
  if (best.count("pbd") && best.count("lumped_mass") && best.count("xpbd"))
  {
    std::printf(
        "goal, catenary S = 8 at EA = %.0e N (sag within 1%%, end tension within 2%%): cheapest pbd %.0f us/s "
        "(%d segments, %d iterations, over-relaxation %g, dt %g s), xpbd %.0f us/s, lumped_mass %.0f us/s (%d "
        "segments, h %.3g ms): "
        "lumped_mass / pbd = %.1f, lumped_mass / xpbd = %.1f\n",
        stiffness, best["pbd"].cost, best["pbd"].segments, best["pbd"].iterations, best["pbd"].over_relaxation,
        best["pbd"].time_step, best["xpbd"].cost, best["lumped_mass"].cost, best["lumped_mass"].segments,
        1e3 * best["lumped_mass"].time_step / best["lumped_mass"].substeps, best["lumped_mass"].cost / best["pbd"].cost,
        best["lumped_mass"].cost / best["xpbd"].cost);
    const Result& plain = best["pbd without over-relaxation"];
    std::printf(
        "      pbd with the paper's projection (over_relaxation 1): %.0f us/s (%d segments, %d iterations, "
        "dt %g s): lumped_mass / pbd = %.1f\n",
        plain.cost, plain.segments, plain.iterations, plain.time_step, best["lumped_mass"].cost / plain.cost);
  }
}

/// Writes stability.csv to `map`: each method's boundedness over step x stiffness and step x speed; prints the
/// counts.
void writeStabilityMap(std::FILE* map, bool quick)
{
  std::fprintf(map, "method,time_step,stiffness,speed,critical_step,bounded,max_strain\n");
  const std::vector<double> steps =
      quick ? std::vector<double>{1e-4, 1e-3, 1e-2}
            : std::vector<double>{1e-5, 2e-5, 5e-5, 1e-4, 2e-4, 5e-4, 1e-3, 2e-3, 5e-3, 1e-2, 2e-2};
  const std::vector<double> stiffnesses =
      quick ? std::vector<double>{1e3, 1e5} : std::vector<double>{1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8};
  const std::vector<double> speeds =
      quick ? std::vector<double>{1.0, 10.0} : std::vector<double>{0.5, 1.0, 2.0, 5.0, 10.0, 20.0};
  int bounded[4] = {0, 0, 0, 0}, total[4] = {0, 0, 0, 0};
  int index = 0;
  for (SolverType method : {SolverType::kPbd, SolverType::kXpbd, SolverType::kLumpedMass, SolverType::kDirect})
  {
    for (double dt : steps)
    {
      // Step x stiffness at 1 m/s, then step x speed at EA = 1e5 N.
      for (double ea : stiffnesses)
      {
        const StabilityPoint s = stability(method, dt, ea, 1.0);
        std::fprintf(map, "%s,%g,%g,%g,%g,%d,%g\n", s.method.c_str(), dt, ea, 1.0, s.critical_step, s.bounded,
                     s.max_strain);
        bounded[index] += s.bounded, ++total[index];
      }
      for (double v : speeds)
      {
        const StabilityPoint s = stability(method, dt, 1e5, v);
        std::fprintf(map, "%s,%g,%g,%g,%g,%d,%g\n", s.method.c_str(), dt, 1e5, v, s.critical_step, s.bounded,
                     s.max_strain);
        bounded[index] += s.bounded, ++total[index];
      }
    }
    std::printf("stability: %-11s bounded in %d of %d runs\n", rov_tether::toString(method).c_str(), bounded[index],
                total[index]);
    ++index;
  }
}

/// The temporary files the study writes (set once they are open), which a stop signal removes, and what it says
/// then for SIGINT and SIGTERM (made before the handler is set: a handler may only write what is ready).
const char* g_partial[2] = {nullptr, nullptr};
char g_stopped[2][200] = {};

/// SIGINT or SIGTERM during the study: removes its temporary files (unlink is safe in a handler), says so, and ends
/// by the signal, as the program would without the handler. The earlier study.csv and stability.csv stay as they were.
extern "C" void onStopSignal(int signal_number)
{
  for (const char* partial : g_partial)
  {
    if (partial != nullptr)
    {
      ::unlink(partial);
    }
  }
  const char* said = g_stopped[signal_number == SIGINT ? 0 : 1];
  const ssize_t written = ::write(2, said, std::strlen(said));
  static_cast<void>(written);
  ::raise(signal_number);  // delivered, at its default action (SA_RESETHAND), when the handler returns
}

/// What a study that stopped short says of its outputs.
std::string notWritten(const std::vector<rov_tether::OutputFile>& files)
{
  return files.size() > 1 ? "study.csv and stability.csv were not written, and the output directory's earlier ones "
                            "are as they were"
                          : "study.csv was not written, and the output directory's earlier one is as it was";
}

/// From here on, SIGINT and SIGTERM stop the study as onStopSignal says, which removes `files`' temporaries. A
/// signal the program was started ignoring (a job started in the background by a shell) stays ignored.
void catchStopSignals(const std::vector<rov_tether::OutputFile>& files)
{
  for (std::size_t i = 0; i < 2; ++i)
  {
    g_partial[i] = i < files.size() ? files[i].partial.c_str() : nullptr;
    std::snprintf(g_stopped[i], sizeof g_stopped[i], "rov_tether_study: stopped by %s: %s\n",
                  i == 0 ? "SIGINT" : "SIGTERM", notWritten(files).c_str());
  }
  struct sigaction action = {};
  action.sa_handler = onStopSignal;
  action.sa_flags = SA_RESETHAND;
  sigemptyset(&action.sa_mask);
  sigaddset(&action.sa_mask, SIGINT);
  sigaddset(&action.sa_mask, SIGTERM);
  for (const int signal_number : {SIGINT, SIGTERM})
  {
    struct sigaction was = {};
    if (sigaction(signal_number, nullptr, &was) == 0 && was.sa_handler != SIG_IGN)
    {
      sigaction(signal_number, &action, nullptr);
    }
  }
}

}  // namespace

int main(int argc, char** argv)
{
  Options options;
  if (!parseOptions(argc, argv, &options))
  {
    return 2;
  }
  // Both files are opened before anything runs (a stability.csv that cannot be written was found only after the
  // whole study), under temporary names: an earlier run's files stay as they were until this run has written both
  // (a study stopped half-way truncated them).
  std::vector<rov_tether::OutputFile> files{{options.out_dir + "/study.csv", {}, nullptr}};
  if (options.with_stability)
  {
    files.push_back({options.out_dir + "/stability.csv", {}, nullptr});
  }
  // A signal while the temporaries are made waits for the handler that removes them.
  sigset_t stops, was;
  sigemptyset(&stops);
  sigaddset(&stops, SIGINT);
  sigaddset(&stops, SIGTERM);
  sigprocmask(SIG_BLOCK, &stops, &was);
  const std::string cannot = rov_tether::openAll(files);
  if (!cannot.empty())
  {
    sigprocmask(SIG_SETMASK, &was, nullptr);
    std::fprintf(stderr, "rov_tether_study: %s\n", cannot.c_str());
    return 1;
  }
  catchStopSignals(files);
  sigprocmask(SIG_SETMASK, &was, nullptr);
  // A case the simulation refused (study::require), or anything else thrown: said, the temporaries removed, the
  // earlier files kept. A stop signal meanwhile waits, then stops the program as it would have.
  const auto abandon = [&](const std::string& what)
  {
    sigprocmask(SIG_BLOCK, &stops, nullptr);
    rov_tether::discardAll(files);
    std::fprintf(stderr, "rov_tether_study: %s: %s\n", what.c_str(), notWritten(files).c_str());
    std::fflush(stderr);
    sigprocmask(SIG_SETMASK, &was, nullptr);
    return 1;
  };
  try
  {
    writeStudy(options, files[0].file);
    if (options.only.empty() || options.only == "catenary_s8")
    {
      // The goal: at equal accuracy (sag within 1%, end tension within 2%) the cheapest pbd run against
      // the cheapest lumped_mass run, on the S = 8 catenary, for a range of axial stiffness (lumped_mass's
      // critical step shrinks as 1 / sqrt(EA); pbd does not depend on EA).
      const Case& c = findCase("catenary_s8");
      for (double stiffness : options.quick ? std::vector<double>{1e5} : std::vector<double>{1e5, 1e6, 1e7})
      {
        std::map<std::string, Result> best = cheapestAtStiffness(c, stiffness, options.quick);
        printGoal(stiffness, best);
      }
    }
    if (options.with_stability)
    {
      writeStabilityMap(files[1].file, options.quick);
    }
  }
  catch (const std::exception& e)
  {
    return abandon(e.what());
  }
  catch (...)
  {
    return abandon("an unknown exception");
  }
  // The moves into place are not split by a signal: one that comes meanwhile waits, and is said after them.
  sigprocmask(SIG_BLOCK, &stops, &was);
  std::vector<std::string> left;
  const std::string error = rov_tether::closeAll(files, true, options.out_dir, &left);
  sigset_t pending;
  sigpending(&pending);
  for (const int signal_number : {SIGINT, SIGTERM})
  {
    // The handler's work is done: a signal from here on ends the program as it would have without one.
    const bool came = sigismember(&pending, signal_number) != 0;
    struct sigaction now = {};
    if (sigaction(signal_number, nullptr, &now) == 0 && now.sa_handler == onStopSignal)
    {
      std::signal(signal_number, came ? SIG_IGN : SIG_DFL);  // a pending one is taken off, and said
    }
    if (came && error.empty())
    {
      std::fprintf(stderr, "rov_tether_study: %s came after the study had finished: its outputs are complete\n",
                   signal_number == SIGINT ? "SIGINT" : "SIGTERM");
    }
  }
  sigprocmask(SIG_SETMASK, &was, nullptr);
  for (const std::string& warning : left)
  {
    std::fprintf(stderr, "rov_tether_study: warning: %s\n", warning.c_str());
  }
  if (!error.empty())
  {
    std::fprintf(stderr, "rov_tether_study: %s\n", error.c_str());
    return 1;
  }
  std::printf("wrote %s%s\n", files[0].path.c_str(), options.with_stability ? " and stability.csv" : "");
  return 0;
}
