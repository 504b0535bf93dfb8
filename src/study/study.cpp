#include "rov_tether/study/study.hpp"

#include <time.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "rov_tether/core/tether.hpp"
#include "rov_tether/scenario/scenario.hpp"

namespace rov_tether::study
{
namespace
{

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Settling time of the 100 m catenary [s]: its slowest mode (pendulum-like, omega^2 ~ g / sag) is
/// overdamped by the drag's 5.3 1/s and creeps at omega^2 / gamma ~ 0.05 1/s.
constexpr double kLongSettle = 150.0;
constexpr double kPi = 3.14159265358979323846;

/// Relative error |value / reference - 1|, infinite for a non-finite value.
double relativeError(double value, double reference)
{
  const double error = std::abs(value / reference - 1.0);
  return std::isfinite(error) ? error : std::numeric_limits<double>::infinity();
}

/// Throws std::invalid_argument naming `where` when the simulation refused a call: the case cannot run as
/// asked. The study's own intervals and times are finite and positive, and the parameters it sets differ from
/// those the Tether was built with (and so validated) in drag only; what is left to refuse comes from the
/// caller (parameters, a speed), reported as the Tether's constructor reports bad parameters.
void require(const Status& status, const std::string& where)
{
  if (!status.ok)
  {
    throw std::invalid_argument(where + ": " + status.message);
  }
}

Result describe(const std::string& scenario, const TetherParams& p)
{
  Result r;
  r.scenario = scenario;
  r.method = toString(p.solver);
  r.segments = static_cast<int>(p.segmentCount());
  r.iterations = p.iterations;
  r.substeps = p.substeps;
  r.over_relaxation = p.over_relaxation;
  r.time_step = p.time_step;
  return r;
}

/// Marks the result failed when the simulation reported a failure or ended non-finite.
void finish(Result& r, const Tether& sim, double cpu, double simulated)
{
  r.cost = cpu / simulated * 1e6;
  r.solver_iterations = sim.maxSolverIterations();
  r.failed = sim.recoveryCount() > 0 || !std::isfinite(r.shape_error);
  if (r.failed)
  {
    r.shape_error = r.tension_error = std::numeric_limits<double>::infinity();
  }
}

// --- Statics: the catenary between level supports --------------------------------------------------

/// `length` of cable in `segments` segments, all deployed, winch locked, no bending, no noise: the
/// common ground of the reference cases.
TetherParams fullyDeployed(double length, int segments)
{
  TetherParams p;
  p.cable_length = length;
  p.segment_length = length / segments;
  p.initial_deployed_length = length;
  p.min_deployed_length = p.segment_length;
  p.bending = false;
  p.noise = 0.0;
  p.winch_mode = WinchMode::kLocked;
  p.max_vehicle_jump = 100.0;
  return p;
}

TetherParams catenaryBase(double length, double weight, double mass_per_length, double stiffness, int segments)
{
  TetherParams p = fullyDeployed(length, segments);
  p.drag = 0.9;
  p.weight_in_water = weight;
  p.mass_per_length = mass_per_length;
  p.axial_stiffness = stiffness;
  return p;
}

/// The reference is the elastic catenary at the cable's own EA (pbd, inextensible, is compared with it
/// too: at EA = 1e5 N and w = 1 N/m it differs from the inextensible row by 0.01%).
Result runCatenary(const std::string& name, TetherParams p, double span, double settle_time)
{
  Result r = describe(name, p);
  Catenary reference;
  reference.length = p.cable_length;
  reference.weight = p.weight_in_water;
  reference.stiffness = p.axial_stiffness;
  reference.solve(span);
  const double start = cpuSeconds();
  Tether sim(p, Position::Zero(), Position(span, 0.0, 0.0));
  require(sim.advance(settle_time - 1.0), name);
  std::vector<Position> before(sim.deployedParticleCount());
  for (std::size_t k = 0; k < before.size(); ++k)
  {
    before[k] = sim.particle(k);
  }
  require(sim.advance(1.0), name);
  const double cpu = cpuSeconds() - start;
  double motion = 0.0;  // RMS motion over the last second [m]
  for (std::size_t k = 0; k < before.size(); ++k)
  {
    motion += (sim.particle(k) - before[k]).squaredNorm();
  }
  motion = std::sqrt(motion / static_cast<double>(before.size()));
  double sag = 0.0;
  for (std::size_t k = 0; k < sim.deployedParticleCount(); ++k)
  {
    sag = std::max(sag, -sim.particle(k).z());
  }
  std::vector<double> tensions;
  sim.computeSegmentTensions(tensions);
  const double dl = sim.params().segment_length;
  r.shape_error = relativeError(sag, reference.sag());
  // The support segments' tensions against T(s) at their midpoints; the worse end counts.
  r.tension_error = std::max(relativeError(tensions.front(), reference.tension(0.5 * dl)),
                             relativeError(tensions.back(), reference.tension(p.cable_length - 0.5 * dl)));
  finish(r, sim, cpu, settle_time);
  if (motion > 1e-4 * reference.sag())
  {
    // Not at rest: a static reference says nothing about a cable that still moves (or jitters).
    r.failed = true;
    r.shape_error = r.tension_error = std::numeric_limits<double>::infinity();
  }
  return r;
}

// --- Straight cable under axial drag ------------------------------------------------------------------

TetherParams axialDragBase(int segments)
{
  TetherParams p = fullyDeployed(100.0, segments);
  p.drag_model = DragModel::kMorison;
  p.mass_per_length = 0.5;
  p.current = {0.0, 0.0, -1.0};  // along the cable, which hangs straight down from the spool
  return p;
}

Result runAxialDrag(TetherParams p)
{
  Result r = describe("axial_drag", p);
  const double speed = 1.0;
  const double resistance = 0.5 * p.water_density * p.tangential_drag_coefficient * kPi * p.diameter * speed * speed;
  const double settle = 20.0;
  const double start = cpuSeconds();
  Tether sim(p, Position::Zero());
  require(sim.advance(settle), r.scenario);
  const double cpu = cpuSeconds() - start;
  std::vector<double> tensions;
  sim.computeSegmentTensions(tensions);
  const double dl = sim.params().segment_length;
  const double length = p.cable_length;
  // T(s) = R_t (L - s): the spool segment's midpoint; the cable stretches by R_t L^2 / (2 EA) (xpbd,
  // lumped_mass; the pbd methods are inextensible).
  r.tension_error = relativeError(tensions.front(), resistance * (length - 0.5 * dl));
  const bool elastic = p.solver == SolverType::kXpbd || p.solver == SolverType::kLumpedMass;
  const double stretched = length + (elastic ? resistance * length * length / (2.0 * p.axial_stiffness) : 0.0);
  r.shape_error = relativeError(-sim.particle(sim.deployedParticleCount() - 1).z(), stretched);
  finish(r, sim, cpu, settle);
  return r;
}

// --- Dynamics ----------------------------------------------------------------------------------------

TetherParams tautStringBase(int segments)
{
  TetherParams p = fullyDeployed(10.0, segments);
  p.mass_per_length = 0.5;
  p.axial_stiffness = 1e5;
  return p;
}

Result runTautString(TetherParams p)
{
  // T = 100 N from a stretch of T / EA; a small uniform load deflects it (1.3 cm), then it swings free.
  Result r = describe("taut_string", p);
  const double tension = 100.0;
  const double span = p.cable_length * (1.0 + tension / p.axial_stiffness);
  const double reference = std::sqrt(tension / p.mass_per_length) / (2.0 * p.cable_length);  // f1 [Hz]
  TetherParams loaded = p;
  loaded.weight_in_water = 0.1;
  loaded.drag = 0.5;
  const double start = cpuSeconds();
  Tether sim(loaded, Position::Zero(), Position(span, 0.0, 0.0));
  require(sim.advance(4.0), r.scenario);
  TetherParams free = p;
  free.drag = 1.0;
  require(sim.setParams(free), r.scenario);
  const std::size_t middle = sim.deployedParticleCount() / 2;
  CrossingCounter counter;
  double tension_sum = 0.0;
  int samples = 0;
  const double duration = 10.0;
  std::vector<double> tensions;
  const int steps = static_cast<int>(std::lround(duration / p.time_step));
  const int every = std::max(1, static_cast<int>(std::lround(0.1 / p.time_step)));
  for (int k = 1; k <= steps; ++k)
  {
    sim.step();
    counter.add(sim.time(), sim.particle(middle).z());
    if (k % every == 0)
    {
      sim.computeSegmentTensions(tensions);
      tension_sum += tensions.front();
      ++samples;
    }
  }
  const double cpu = cpuSeconds() - start;
  r.shape_error = relativeError(1.0 / counter.period(), reference);
  r.tension_error = relativeError(tension_sum / samples, tension);
  finish(r, sim, cpu, 4.0 + duration);
  return r;
}

TetherParams hangingChainBase(int segments)
{
  TetherParams p = fullyDeployed(10.0, segments);
  p.mass_per_length = 1.0;
  p.weight_in_water = 9.81;  // in air: w / mu = g
  p.axial_stiffness = 1e5;
  return p;
}

Result runHangingChain(TetherParams p)
{
  // A slight current pushes the chain aside (mostly its first mode), then it swings free in air.
  Result r = describe("hanging_chain", p);
  const double reference = 2.0 * kPi / (2.4048 / 2.0 * std::sqrt(9.81 / p.cable_length));  // T1 [s]
  TetherParams pushed = p;
  pushed.current = {0.1, 0.0, 0.0};
  pushed.drag = 0.9;
  const double start = cpuSeconds();
  Tether sim(pushed, Position::Zero());
  require(sim.advance(8.0), r.scenario);
  TetherParams free = p;
  free.drag = 1.0;
  require(sim.setParams(free), r.scenario);
  const std::size_t end = sim.deployedParticleCount() - 1;
  CrossingCounter counter;
  const double duration = 30.0;
  const int steps = static_cast<int>(std::lround(duration / p.time_step));
  for (int k = 1; k <= steps; ++k)
  {
    sim.step();
    counter.add(sim.time(), sim.particle(end).x());
  }
  const double cpu = cpuSeconds() - start;
  r.shape_error = relativeError(counter.period(), reference);
  r.tension_error = kNaN;
  finish(r, sim, cpu, 8.0 + duration);
  return r;
}

// --- The paper's own 2D experiment ------------------------------------------------------------------

Scenario paperScenario()
{
  Scenario s;
  s.params.cable_length = 10.0;
  s.params.segment_length = 0.2;
  s.params.initial_deployed_length = 10.0;
  s.params.time_step = 0.02;
  s.params.iterations = 5;
  s.params.drag = 0.98;
  s.params.noise = 0.0005;
  s.params.winch_mode = WinchMode::kLocked;
  s.params.max_vehicle_jump = 100.0;
  s.params.min_deployed_length = 0.2;
  s.spool = Position(10.0, 0.0, 0.0);
  s.vehicle = {Waypoint{0.0, Position::Zero()}, Waypoint{0.6, Position(3.0, 3.0, 2.0)}};
  s.duration = 16.0;
  return s;
}

TetherParams paperBase(int segments)
{
  TetherParams p = paperScenario().params;
  p.segment_length = p.cable_length / segments;
  p.min_deployed_length = p.segment_length;
  return p;
}

Result runPaper(TetherParams p)
{
  // The error is the cable's mean residual stretch at 16 s (the paper's Fig. 4 measure): the paper's
  // cable is meant to be inextensible, and an elastic one at EA = 1e5 N stretches < 1e-5 here.
  Result r = describe("paper_experiment", p);
  Scenario s = paperScenario();
  s.params = p;
  PathDriver driver(s);
  const double start = cpuSeconds();
  Tether sim = driver.makeSimulation();
  require(driver.advanceTo(sim, s.duration), r.scenario);
  const double cpu = cpuSeconds() - start;
  double geometric = 0.0;
  for (std::size_t k = 0; k + 1 < sim.deployedParticleCount(); ++k)
  {
    geometric += (sim.particle(k + 1) - sim.particle(k)).norm();
  }
  r.shape_error = std::abs(geometric / sim.deployedLength() - 1.0);
  r.tension_error = kNaN;
  finish(r, sim, cpu, s.duration);
  return r;
}

}  // namespace

// --- Irvine's elastic catenary ------------------------------------------------------------------------

double Catenary::x(double s) const
{
  const double h = horizontal, w = weight;
  return h * s / stiffness + h / w * (std::asinh((vertical + w * s) / h) - std::asinh(vertical / h));
}

double Catenary::z(double s) const
{
  const double h = horizontal, w = weight, v = vertical;
  return (v * s + 0.5 * w * s * s) / stiffness +
         1.0 / w * (std::sqrt(h * h + (v + w * s) * (v + w * s)) - std::sqrt(h * h + v * v));
}

double Catenary::tension(double s) const
{
  const double v = vertical + weight * s;
  return std::sqrt(horizontal * horizontal + v * v);
}

bool Catenary::solve(double span)
{
  // Level supports: V_A = -w L / 2 by symmetry; Newton on H for x(L) = span.
  vertical = -0.5 * weight * length;
  horizontal = weight * length;  // any positive start; x(L) increases with H
  for (int i = 0; i < 200; ++i)
  {
    const double f = x(length) - span;
    const double dh = 1e-7 * horizontal;
    horizontal += dh;
    const double slope = (x(length) - span - f) / dh;
    horizontal -= dh;
    const double next = std::max(horizontal - f / slope, 0.1 * horizontal);
    if (std::abs(next - horizontal) < 1e-13 * horizontal)
    {
      horizontal = next;
      return true;
    }
    horizontal = next;
  }
  return false;
}

double cpuSeconds()
{
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

const std::vector<Case>& cases()
{
  static const std::vector<Case> all = {
      {"catenary_s8", "Statics, S = 8 (EA = 1e5 N, w = 1 N/m)",
       [](TetherParams p) { return runCatenary("catenary_s8", p, 8.0, 30.0); },
       [](int n) { return catenaryBase(10.0, 1.0, 0.1, 1e5, n); }},
      {"catenary_100m", "Statics, S = 8 scaled to a 100 m tether (span 80 m, EA = 1e5 N, w = 1 N/m)",
       [](TetherParams p) { return runCatenary("catenary_100m", p, 80.0, kLongSettle); },
       [](int n) { return catenaryBase(100.0, 1.0, 0.1, 1e5, n); }},
      {"catenary_ea100", "Statics, S = 8, EA = 100 N",
       [](TetherParams p) { return runCatenary("catenary_ea100", p, 8.0, 30.0); },
       [](int n) { return catenaryBase(10.0, 1.0, 0.1, 100.0, n); }},
      {"large_strain", "Large strain: span = length = 1 m, 0.2 kg, EA = 3.1416 N",
       [](TetherParams p) { return runCatenary("large_strain", p, 1.0, 30.0); },
       [](int n) { return catenaryBase(1.0, 1.962, 0.2, 3.1416, n); }},
      {"axial_drag", "Straight cable under axial drag: 100 m, 1 m/s, 25.8 N", runAxialDrag, axialDragBase},
      {"taut_string", "Taut string: T = 100 N, mu = 0.5 kg/m, L = 10 m, f1 = 0.7071 Hz", runTautString, tautStringBase},
      {"hanging_chain", "Hanging chain: L = 10 m in air, T1 = 5.276 s", runHangingChain, hangingChainBase},
      {"paper_experiment", "The paper's 2D experiment: residual stretch at 16 s", runPaper, paperBase},
  };
  return all;
}

const Case& findCase(const std::string& name)
{
  for (const auto& c : cases())
  {
    if (c.name == name)
    {
      return c;
    }
  }
  throw std::out_of_range("unknown study case '" + name + "'");
}

StabilityPoint stability(SolverType method, double time_step, double stiffness, double speed, double over_relaxation)
{
  // docs/references.md "Where methods fail": dL = 0.5 m, mu = 0.4 kg/m. A vehicle 5 m out pulls away at
  // `speed` for 2 s; the brake winch pays out at 10 N, up to 20 m/s.
  TetherParams p;
  p.cable_length = 50.0;
  p.segment_length = 0.5;
  p.initial_deployed_length = 6.0;
  p.min_deployed_length = 0.5;
  p.time_step = time_step;
  p.solver = method;
  p.noise = 0.0;
  p.bending = false;
  p.mass_per_length = 0.4;
  p.weight_in_water = 1.0;
  p.axial_stiffness = stiffness;
  p.over_relaxation = over_relaxation;
  p.max_winch_speed = 20.0;
  p.brake_tension = 10.0;
  p.max_vehicle_jump = 100.0;
  StabilityPoint point;
  point.method = toString(method);
  point.time_step = time_step;
  point.stiffness = stiffness;
  point.speed = speed;
  point.critical_step = p.criticalStep();
  Tether sim(p, Position::Zero(), Position(5.0, 0.0, -2.0));
  for (int k = 1; k <= 40; ++k)
  {
    const double t = 0.05 * k;
    require(sim.addVehicleSample(t, Position(5.0 + speed * t, 0.0, -2.0)), "stability");
    require(sim.advanceTo(t), "stability");
    const double strain = sim.summary().max_strain;
    point.max_strain = std::max(point.max_strain, std::isfinite(strain) ? strain : 1e300);
    if (sim.recoveryCount() > 0)
    {
      break;
    }
  }
  point.bounded = sim.recoveryCount() == 0 && point.max_strain < 1.0;
  return point;
}

}  // namespace rov_tether::study
