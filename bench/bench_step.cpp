// Speed of one simulation step (Google Benchmark). See README "Benchmarks".
#include <benchmark/benchmark.h>

#include "rov_tether/tether_simulation.hpp"

namespace
{

using rov_tether::Position;
using rov_tether::SolverType;
using rov_tether::TetherParams;
using rov_tether::TetherSimulation;

/// The paper's cable scaled to `segments` segments of 0.1 m, fully deployed, slack between spool and
/// vehicle (80% of its length apart), 10 iterations, bending on, noise on, neutrally buoyant.
TetherSimulation makeCable(int segments, SolverType solver, bool bending)
{
  TetherParams params;
  params.segment_length = 0.1;
  params.cable_length = 0.1 * segments;
  params.initial_deployed_length = params.cable_length;
  params.min_deployed_length = 0.1;
  params.iterations = 10;
  params.bending = bending;
  params.solver = solver;
  params.winch_mode = rov_tether::WinchMode::kLocked;
  TetherSimulation sim(params, Position::Zero(), Position(0.8 * params.cable_length, 0.0, 0.0));
  sim.advance(1.0);  // let the laid-out shape start moving
  return sim;
}

void stepBenchmark(benchmark::State& state, SolverType solver, bool bending)
{
  TetherSimulation sim = makeCable(static_cast<int>(state.range(0)), solver, bending);
  for (auto _ : state)
  {
    sim.step();
    benchmark::DoNotOptimize(sim.state().x.data());
  }
  const double projections_per_step = static_cast<double>(state.range(0)) * (bending ? 2.0 : 1.0) * 10.0;
  state.counters["ns_per_projection"] =
      benchmark::Counter(projections_per_step * static_cast<double>(state.iterations()),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert, benchmark::Counter::kIs1000);
  state.counters["ns_per_projection"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * projections_per_step,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_StepPbd(benchmark::State& state) { stepBenchmark(state, SolverType::kPbd, true); }
void BM_StepPbdSequential(benchmark::State& state) { stepBenchmark(state, SolverType::kPbdSequential, true); }
void BM_StepPbdNoBending(benchmark::State& state) { stepBenchmark(state, SolverType::kPbd, false); }

}  // namespace

BENCHMARK(BM_StepPbd)->Arg(100)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StepPbdSequential)->Arg(100)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StepPbdNoBending)->Arg(100)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
