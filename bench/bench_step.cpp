// Speed of one simulation step (Google Benchmark). See docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "banded.hpp"
#include "rov_tether/core/tether.hpp"
#include "rov_tether/core/vehicle_body.hpp"
#include "rov_tether/core/vehicle_coupling.hpp"

namespace
{

using rov_tether::DragModel;
using rov_tether::Position;
using rov_tether::SolverType;
using rov_tether::Tether;
using rov_tether::TetherParams;

/// The paper's cable scaled to `segments` segments of 0.1 m, fully deployed, slack between spool and
/// vehicle (80% of its length apart), 10 iterations, bending on, noise on, neutrally buoyant; `change`
/// then edits the parameters. A refused start skips the benchmark (`state`) with the reason.
Tether makeCable(benchmark::State& state, int segments, const std::function<void(TetherParams&)>& change = {})
{
  TetherParams params;
  params.segment_length = 0.1;
  params.cable_length = 0.1 * segments;
  params.initial_deployed_length = params.cable_length;
  params.min_deployed_length = 0.1;
  params.iterations = 10;
  params.winch_mode = rov_tether::WinchMode::kLocked;
  if (change)
  {
    change(params);
  }
  const double deployed = params.initial_deployed_length;
  Tether sim(params, Position::Zero(), Position(0.8 * deployed, 0.0, 0.0));
  const rov_tether::Status status = sim.advance(1.0);  // let the laid-out shape start moving
  if (!status.ok)
  {
    state.SkipWithError(("setting up the cable: " + status.message).c_str());
  }
  return sim;
}

void run(benchmark::State& state, Tether& sim, double projections_per_step)
{
  for (auto _ : state)
  {
    sim.step();
    benchmark::DoNotOptimize(sim.state().x.data());
  }
  if (projections_per_step > 0.0)
  {
    state.counters["ns_per_projection"] =
        benchmark::Counter(static_cast<double>(state.iterations()) * projections_per_step,
                           benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  }
}

void stepBenchmark(benchmark::State& state, SolverType solver, bool bending)
{
  Tether sim = makeCable(state, static_cast<int>(state.range(0)),
                         [&](TetherParams& p)
                         {
                           p.solver = solver;
                           p.bending = bending;
                         });
  run(state, sim, static_cast<double>(state.range(0)) * (bending ? 2.0 : 1.0) * 10.0);
}

void BM_StepPbd(benchmark::State& state) { stepBenchmark(state, SolverType::kPbd, true); }
void BM_StepPbdSequential(benchmark::State& state) { stepBenchmark(state, SolverType::kPbdSequential, true); }
void BM_StepPbdNoBending(benchmark::State& state) { stepBenchmark(state, SolverType::kPbd, false); }

/// xpbd with the same effort (10 iterations) and a bending stiffness, so it projects as many constraints.
/// Second arg 1: Morison drag, whose added mass acts across the cable only, so each joint's projection solves
/// a 3x3 system (projectJointAnisotropic) instead of dividing by a scalar.
void BM_StepXpbd(benchmark::State& state)
{
  const bool morison = state.range(1) == 1;
  Tether sim = makeCable(state, static_cast<int>(state.range(0)),
                         [morison](TetherParams& p)
                         {
                           p.solver = SolverType::kXpbd;
                           p.bending_stiffness = 1e-3;
                           p.drag_model = morison ? DragModel::kMorison : DragModel::kDamping;
                         });
  run(state, sim, static_cast<double>(state.range(0)) * 20.0);
}

/// lumped_mass on the same cable (EA = 1e5 N, mu = 0.1 kg/m, dL = 0.1 m: critical step 0.1 ms): one
/// 5 ms step needs ceil(5 / 0.09) = 56 sub-steps at 0.9 of the critical step.
void BM_StepLumpedMass(benchmark::State& state)
{
  Tether sim = makeCable(state, static_cast<int>(state.range(0)),
                         [](TetherParams& p)
                         {
                           p.solver = SolverType::kLumpedMass;
                           p.noise = 0.0;
                           p.substeps = static_cast<int>(std::ceil(p.time_step / (0.9 * p.criticalStep())));
                         });
  state.counters["substeps"] = sim.params().substeps;
  run(state, sim, 0.0);
}

/// direct: Newton with an exact tridiagonal solve, same cable, no bending stiffness (the chain alone).
/// The counter is the Newton iterations of the last sub-step (it stops on solver_tolerance).
void BM_StepDirect(benchmark::State& state)
{
  Tether sim = makeCable(state, static_cast<int>(state.range(0)),
                         [](TetherParams& p)
                         {
                           p.solver = SolverType::kDirect;
                           p.bending_stiffness = 0.0;
                         });
  run(state, sim, 0.0);
  state.counters["newton_iterations"] = sim.solverIterations();
}

/// What sections and attachments cost (issue 22), like for like: BM_StepDirect's cable (second arg 0 as it is;
/// 1 the same cable with an attachment of no mass, buoyancy or drag, which puts it on the per-segment material
/// path with the same physics; 2 a real one: three sections of their own weight and EA, a float and a clump
/// weight, under a water surface it crosses; third arg 0 the paper's damping, 1 Morison). The counter is the
/// Newton iterations of the last sub-step: 0 and 1 take the same.
void BM_StepDirectSections(benchmark::State& state)
{
  const int kind = static_cast<int>(state.range(1));
  const bool morison = state.range(2) == 1;
  Tether sim = makeCable(state, static_cast<int>(state.range(0)),
                         [&](TetherParams& p)
                         {
                           p.solver = SolverType::kDirect;
                           p.bending_stiffness = 0.0;
                           p.drag_model = morison ? DragModel::kMorison : DragModel::kDamping;
                           rov_tether::CableAttachment none;
                           none.name = "none";
                           none.arc_length_from_vehicle = 0.5 * p.cable_length;
                           none.drag_coefficient = 0.0;
                           if (kind == 1)
                           {
                             p.attachments = {none};
                           }
                           if (kind == 2)
                           {
                             const double third = 0.1 * std::round(p.cable_length / 0.3);
                             p.sections = {{third, {{"weight_in_water", 0.5}, {"axial_stiffness", 5e4}}},
                                           {third, {{"weight_in_water", -0.3}, {"diameter", 0.05}}},
                                           {}};
                             rov_tether::CableAttachment buoy = none, clump = none;
                             buoy.name = "float", buoy.net_buoyancy = 2.0, buoy.mass = 0.2, buoy.drag_area = 0.01;
                             clump.name = "clump", clump.net_buoyancy = -1.0, clump.mass = 0.3;
                             clump.arc_length_from_vehicle = 0.2 * p.cable_length;
                             p.attachments = {buoy, clump};
                             p.water_surface_z = 0.0;  // the cable lies about z = 0: it crosses
                           }
                         });
  run(state, sim, 0.0);
  state.counters["newton_iterations"] = sim.solverIterations();
}

/// The end's linearisation for an external simulator (Tether::vehicleEndLinearisation) alone, one call an
/// iteration on BM_StepDirect's cable (no bending stiffness) made heavy in water (1 N/m), so that it hangs and
/// its last segment pulls (a slack end would return K = 0 without a solve): an assembly of the step's Hessian,
/// one block factorisation and three solves. Compare with BM_StepDirect at the same size.
void BM_EndLinearisation(benchmark::State& state)
{
  Tether sim = makeCable(state, static_cast<int>(state.range(0)),
                         [](TetherParams& p)
                         {
                           p.solver = SolverType::kDirect;
                           p.bending_stiffness = 0.0;
                           p.weight_in_water = 1.0;
                         });
  rov_tether::EndLinearisation linearised;
  if (!sim.vehicleEndLinearisation(&linearised).ok || !linearised.taut)
  {
    state.SkipWithError("the hanging cable's end is not taut");
    return;
  }
  for (auto _ : state)
  {
    const rov_tether::Status status = sim.vehicleEndLinearisation(&linearised);
    benchmark::DoNotOptimize(status.ok);
    benchmark::DoNotOptimize(linearised.stiffness.data());
  }
}

/// direct with EI bending at the default 0.2 N m^2 (a 2 cm tether): the primal path, a block-banded system.
void BM_StepDirectBending(benchmark::State& state)
{
  Tether sim =
      makeCable(state, static_cast<int>(state.range(0)), [](TetherParams& p) { p.solver = SolverType::kDirect; });
  run(state, sim, 0.0);
  state.counters["newton_iterations"] = sim.solverIterations();
}

/// BM_StepDirectBending's cable (the default EI) with its vehicle end moving, as a vehicle drags its tether,
/// fed as a pose a step ahead. Second arg 0: the winch locked and the end 0.8 L from the spool, as in
/// BM_StepDirectBending, moving across the cable at 1 m/s. 1: a brake winch (5 N) with as much cable again on
/// the spool, the cable laid straight to the end, which drives away along it at 0.5 m/s, so the brake slips
/// and the winch pays out every step. Each iteration steps the same 1 s window from a fresh start, set up
/// outside the timing as BM_StepDirectBending's cable is (laid out, then 1 s with the end held), so runs of
/// any length compare the same motion. Issue 24 asks for a moving cable's step at N = 1000 to cost at most 3x the
/// static one's (BM_StepDirectBending/1000 in the same run); newton_iterations is the mean a sub-step over the windows.
void BM_StepDirectBendingMoving(benchmark::State& state)
{
  const int segments = static_cast<int>(state.range(0));
  const bool paying_out = state.range(1) != 0;
  constexpr int kWindow = 200;  // 1 s at the default 5 ms
  std::optional<Tether> sim;
  rov_tether::SolverEffort effort;
  for (auto _ : state)
  {
    state.PauseTiming();
    TetherParams params;
    params.segment_length = 0.1;
    params.initial_deployed_length = 0.1 * segments;
    params.cable_length = (paying_out ? 2.0 : 1.0) * params.initial_deployed_length;
    params.min_deployed_length = 0.1;
    params.iterations = 10;
    params.solver = SolverType::kDirect;
    params.winch_mode = paying_out ? rov_tether::WinchMode::kBrake : rov_tether::WinchMode::kLocked;
    const Position end((paying_out ? 1.0 : 0.8) * params.initial_deployed_length, 0.0, 0.0);
    sim.emplace(params, Position::Zero(), end);
    if (!sim->advance(1.0).ok)
    {
      state.SkipWithError("setting up the cable failed");
      return;
    }
    const double h = params.time_step;
    const double start = sim->time();
    const rov_tether::SolverEffort before = sim->solverEffort();
    state.ResumeTiming();
    for (int i = 1; i <= kWindow; ++i)
    {
      const double t = h * i;
      const Position offset = paying_out ? Position(0.5 * t, 0.0, 0.0) : Position(0.0, 1.0 * t, 0.0);
      if (!sim->addVehicleSample(start + t, end + offset).ok)
      {
        state.SkipWithError("a vehicle sample was refused");
        return;
      }
      sim->step();
    }
    benchmark::DoNotOptimize(sim->state().x.data());
    effort.substeps += sim->solverEffort().substeps - before.substeps;
    effort.iterations += sim->solverEffort().iterations - before.iterations;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kWindow);  // steps: items_per_second
  state.counters["newton_iterations"] = effort.meanIterations();
  state.counters["paid_out_m"] = sim->deployedLength() - sim->params().initial_deployed_length;
  state.counters["steps_per_iteration"] = kWindow;
}

/// BM_StepDirectDynamicVehicle's cable: BM_StepDirect's, or BM_StepDirectBending's when `bending`.
Tether vehicleBenchCable(benchmark::State& state, bool bending)
{
  return makeCable(state, static_cast<int>(state.range(0)),
                   [&](TetherParams& p)
                   {
                     p.solver = SolverType::kDirect;
                     p.bending_stiffness = bending ? p.bending_stiffness : 0.0;
                   });
}

/// Attaches the BlueROV2 Heavy, at rest, at the cable's end; false when refused.
bool attachBodyAtEnd(Tether* sim)
{
  rov_tether::VehicleBody body;
  const Position end = sim->particle(sim->deployedParticleCount() - 1);
  return body.setState(end, Eigen::Quaterniond::Identity(), rov_tether::Twist::Zero()).ok &&
         sim->attachVehicleBody(body, Eigen::Vector3d::Zero()).ok;
}

/// Steps a copy of BM_StepDirectDynamicVehicle's dynamic set-up for 1 s and `window` steps more and feeds its
/// attachment point to `follower` as vehicle samples, one a step. Not inlined, so that scripts/vehicle_overhead.sh
/// can tell the leader's steps (called from here) from the benchmark's.
__attribute__((noinline)) std::string followDynamicPath(benchmark::State& state, bool bending, int window,
                                                        Tether* follower)
{
  Tether leader = vehicleBenchCable(state, bending);
  if (!attachBodyAtEnd(&leader))
  {
    return "the dynamic vehicle was refused";
  }
  const int steps = static_cast<int>(std::lround(1.0 / leader.params().time_step)) + window + 2;
  for (int i = 0; i <= steps; ++i)
  {
    if (i > 0)
    {
      leader.step();
    }
    if (!follower->addVehicleSample(leader.time(), leader.particle(leader.deployedParticleCount() - 1)).ok)
    {
      return "a vehicle sample was refused";
    }
  }
  return {};
}

/// The cost of a dynamic vehicle end, like for like: the same cable as BM_StepDirect (second arg 0: no bending
/// stiffness) or BM_StepDirectBending (second arg 1: the default EI), set up alike (1 s, then 1 s more), with
/// the vehicle end kinematic (third arg 0: pinned where it is, as in BM_StepDirect), dynamic (third arg 1:
/// the BlueROV2 Heavy at rest at that end, no thrust, attached before the second second), or kinematic along
/// the path the dynamic vehicle takes (third arg 2: its attachment point, stepped beforehand in a run of arg 1's
/// set-up, fed as vehicle samples at every step). The dynamic vehicle drifts (it is 2.4 N buoyant, and the
/// cable pulls it), so 2 tells whether that motion, rather than the coupling (VehicleCoupling: a body step and
/// the end's mobility per sub-step, and the free end in the chain's solve), is what a dynamic vehicle costs. It
/// is not: 2 costs what 0 does (docs/benchmarks.md). Issue 25 asks for at most 10% at 100 segments.
/// scripts/vehicle_overhead.sh counts the three in instructions.
void BM_StepDirectDynamicVehicle(benchmark::State& state)
{
  const bool bending = state.range(1) != 0;
  const bool dynamic = state.range(2) == 1;
  const bool replay = state.range(2) == 2;
  // Every iteration steps the same window from the same start (set up outside the timing), so the two
  // ends are compared over the same stretch of motion: stepped on from one start, the cable settles as the
  // benchmark runs, and the Newton iterations a step takes (1 or 2 here) would depend on how long it ran.
  constexpr int kWindow = 100;  // steps an iteration: 0.5 s at the default 5 ms
  const auto start = [&](std::optional<Tether>* sim)
  {
    sim->emplace(vehicleBenchCable(state, bending));
    if (dynamic && !attachBodyAtEnd(&**sim))
    {
      return std::string("the dynamic vehicle was refused");
    }
    if (replay)
    {
      const std::string refused = followDynamicPath(state, bending, kWindow, &**sim);
      if (!refused.empty())
      {
        return refused;
      }
    }
    const rov_tether::Status moving = (*sim)->advance(1.0);
    return moving.ok ? std::string() : "the cable did not start moving: " + moving.message;
  };
  std::optional<Tether> sim;  // built afresh for every window
  rov_tether::SolverEffort effort;
  for (auto _ : state)
  {
    state.PauseTiming();
    const std::string refused = start(&sim);
    if (!refused.empty())
    {
      state.SkipWithError(refused.c_str());
      return;
    }
    const rov_tether::SolverEffort before = sim->solverEffort();
    state.ResumeTiming();
    for (int i = 0; i < kWindow; ++i)
    {
      sim->step();
    }
    benchmark::DoNotOptimize(sim->state().x.data());
    effort.substeps += sim->solverEffort().substeps - before.substeps;
    effort.iterations += sim->solverEffort().iterations - before.iterations;
  }
  state.SetLabel(dynamic ? "dynamic vehicle" : "kinematic vehicle");
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kWindow);  // steps: items_per_second
  state.counters["newton_iterations"] = effort.meanIterations();
}

/// The direct solver's linear solves alone: the LDL^T sweep written in banded.cpp (Arg 0) against
/// LAPACK's dpttrf/dpttrs (Arg 1), on an SPD tridiagonal system of a chain's size.
void BM_TridiagonalSolve(benchmark::State& state)
{
  const auto n = static_cast<std::size_t>(state.range(0));
  const bool lapack = state.range(1) == 1;
  state.SetLabel(lapack ? "LAPACK dpttrf/dpttrs" : "sweep (banded.cpp)");
  std::vector<double> d0(n), e0(n), b0(n), d(n), e(n), b(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    d0[i] = 2.0 + 0.01 * static_cast<double>(i % 7);
    e0[i] = -0.9 - 0.01 * static_cast<double>(i % 5);
    b0[i] = std::sin(static_cast<double>(i));
  }
  for (auto _ : state)
  {
    d = d0, e = e0, b = b0;
    const bool ok = lapack ? rov_tether::banded::solveTridiagonalLapack(d.data(), e.data(), b.data(), n)
                           : rov_tether::banded::solveTridiagonalSweep(d.data(), e.data(), b.data(), n);
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(b.data());
  }
}

/// The same for the direct solver's banded systems, 3 rows per particle: half-bandwidth 5 (a cable,
/// Arg 2 = 5) or 8 (with bending stiffness, Arg 2 = 8). The L D L^T written in banded.cpp (Arg 1 = 0)
/// against LAPACK's Cholesky dpbtrf/dpbtrs (Arg 1 = 1).
void BM_BandedSolve(benchmark::State& state)
{
  const auto kd = static_cast<std::size_t>(state.range(2));
  const auto n = static_cast<std::size_t>(state.range(0));
  const bool lapack = state.range(1) == 1;
  state.SetLabel(lapack ? "LAPACK dpbtrf/dpbtrs" : "sweep (banded.cpp)");
  std::vector<double> ab0((kd + 1) * n, 0.0), b0(n), ab, b;
  for (std::size_t j = 0; j < n; ++j)
  {
    ab0[j * (kd + 1)] =
        static_cast<double>(kd) + 2.0;  // diagonally dominant: kd off-diagonals of at most 0.5 each side
    for (std::size_t r = 1; r <= kd && j + r < n; ++r)
    {
      ab0[r + j * (kd + 1)] = std::cos(static_cast<double>(j * 7 + r)) * 0.5;
    }
    b0[j] = std::sin(static_cast<double>(j));
  }
  for (auto _ : state)
  {
    ab = ab0, b = b0;
    const bool ok = lapack ? rov_tether::banded::solveBandedLapack(ab.data(), kd, b.data(), n)
                           : rov_tether::banded::solveBandedSweep(ab.data(), kd, b.data(), n);
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(b.data());
  }
}

/// What a scene skips (docs/model.md, "Model no more than the scene needs"): 100 segments, pbd, each variant
/// adds one piece of physics the baseline scene does not need.
void BM_Scene(benchmark::State& state)
{
  const int variant = static_cast<int>(state.range(0));
  const char* labels[] = {"baseline: neutral, still water, no seabed",
                          "weight_in_water 1e-9 N/m (weight term computed)",
                          "90 m more cable on the spool (10 m deployed)",
                          "uniform current 0.2 m/s",
                          "current_variation 0.1 m/s (per-particle field)",
                          "drag_model morison",
                          "seabed 50 m below (contact loop)"};
  state.SetLabel(labels[variant]);
  Tether sim = makeCable(state, 100,
                         [variant](TetherParams& p)
                         {
                           switch (variant)
                           {
                             case 1:
                               p.weight_in_water = 1e-9;
                               break;
                             case 2:
                               p.cable_length = 100.0;
                               break;
                             case 3:
                               p.current = {0.2, 0.0, 0.0};
                               break;
                             case 4:
                               p.current = {0.2, 0.0, 0.0};
                               p.current_variation = 0.1;
                               break;
                             case 5:
                               p.drag_model = DragModel::kMorison;
                               break;
                             case 6:
                               p.seabed_z = -50.0;
                               break;
                             default:
                               break;
                           }
                         });
  run(state, sim, 0.0);
}

/// One step of a vehicle's rigid body (VehicleBody, the BlueROV2 Heavy) at 100 Hz: tumbling in a current
/// under a thrust command and an external wrench, so every part of the step works (issue 25 adds it to
/// BM_StepDirect's step when the vehicle is dynamic).
void BM_VehicleBodyStep(benchmark::State& state)
{
  rov_tether::VehicleBody body;
  rov_tether::Twist velocity;
  velocity << 0.3, -0.1, 0.05, 0.2, -0.1, 0.4;
  rov_tether::Status setup =
      body.setState(Position::Zero(), Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX())), velocity);
  if (setup.ok)
  {
    setup = body.setCurrent(Position(0.2, 0.1, 0.0));
  }
  if (!setup.ok)
  {
    state.SkipWithError(("setting up the body: " + setup.message).c_str());
    return;
  }
  rov_tether::Wrench thrust;
  thrust << 40.0, 10.0, -5.0, 1.0, 0.5, 2.0;
  rov_tether::Wrench external;
  external << -20.0, 3.0, 1.0, 0.1, -0.2, 0.3;
  rov_tether::ThrustUsed used;
  for (auto _ : state)
  {
    const rov_tether::Status status = body.step(0.01, thrust, external, &used);
    benchmark::DoNotOptimize(status.ok);
    benchmark::DoNotOptimize(body.velocity().data());
  }
}

/// The dynamic vehicle end's own calls in one sub-step of 5 ms, apart from the chain (VehicleCoupling: predict(),
/// inverseMass() along a last segment, finish() under a pull): the BlueROV2 Heavy moving and turning slowly
/// under a steady pull of 10 N, the state carried from sub-step to sub-step as in a run, so each sub-step waits
/// for the last (their serial latency, which is what a step pays). scripts/vehicle_overhead.sh prints it.
void BM_VehicleCouplingSubStep(benchmark::State& state)
{
  rov_tether::VehicleBody body;
  rov_tether::Twist velocity;
  velocity << 0.05, -0.01, 0.02, 0.01, -0.01, 0.02;
  const rov_tether::Status setup = body.setState(
      Position(1.0, 2.0, -3.0), Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ())), velocity);
  if (!setup.ok)
  {
    state.SkipWithError(("setting up the body: " + setup.message).c_str());
    return;
  }
  rov_tether::VehicleCoupling coupling(body, Eigen::Vector3d(0.2, 0.0, 0.05));
  const rov_tether::Force pull(-10.0, 1.0, 0.0);
  constexpr double kSubStep = 0.005;
  Position predicted, reached;
  for (auto _ : state)
  {
    const rov_tether::Status predicting = coupling.predict(kSubStep, &predicted);
    const double inverse_mass = coupling.inverseMass(predicted - Position(0.1, 0.0, 0.0), predicted, kSubStep);
    benchmark::DoNotOptimize(inverse_mass);
    const rov_tether::Status finishing = coupling.finish(kSubStep, pull, &reached);
    if (!predicting.ok || !finishing.ok)
    {
      state.SkipWithError("the coupling refused a sub-step");
      return;
    }
    benchmark::DoNotOptimize(reached.data());
  }
}

}  // namespace

BENCHMARK(BM_StepPbd)->Arg(100)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StepPbdSequential)->Arg(100)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StepPbdNoBending)->Arg(100)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StepXpbd)->ArgsProduct({{100}, {0, 1}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StepLumpedMass)->Arg(100)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StepDirect)->Arg(100)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StepDirectSections)->ArgsProduct({{100}, {0, 1, 2}, {0, 1}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_EndLinearisation)->Arg(100)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StepDirectBending)->Arg(100)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StepDirectBendingMoving)->ArgsProduct({{100, 1000}, {0, 1}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StepDirectDynamicVehicle)->ArgsProduct({{100}, {0, 1}, {0, 1, 2}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_TridiagonalSolve)->ArgsProduct({{100, 1000, 10000}, {0, 1}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BandedSolve)->ArgsProduct({{303, 3003}, {0, 1}, {5, 8}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Scene)->DenseRange(0, 6)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_VehicleBodyStep)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_VehicleCouplingSubStep)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
