// Speed of the topology measures (Google Benchmark, in rov_tether_bench): the linking number of two
// tethers and the turns of one around an axis. See docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "rov_tether/core/topology.hpp"

namespace
{

using rov_tether::Position;
namespace topology = rov_tether::topology;

/// A tether of `n` segments: a helix of 2 turns around the z axis, offset by `dx`.
struct Helix
{
  std::vector<double> x, y, z;
  Helix(int n, double dx)
  {
    for (int i = 0; i <= n; ++i)
    {
      const double t = 4.0 * 3.14159265358979323846 * i / n;
      x.push_back(dx + std::cos(t));
      y.push_back(std::sin(t));
      z.push_back(0.1 * t);
    }
  }
  topology::Polyline view() const { return {x.data(), y.data(), z.data(), x.size()}; }
};

/// Two tethers of N segments each, wound around each other's axes: N^2 segment pairs.
void BM_LinkingNumber(benchmark::State& state)
{
  const Helix a(static_cast<int>(state.range(0)), 0.0), b(static_cast<int>(state.range(0)), 1.0);
  for (auto _ : state)
  {
    benchmark::DoNotOptimize(topology::linkingNumber(a.view(), b.view()));
  }
}

/// One tether of N segments around an axis.
void BM_WindingTurns(benchmark::State& state)
{
  const Helix a(static_cast<int>(state.range(0)), 0.0);
  for (auto _ : state)
  {
    benchmark::DoNotOptimize(topology::windingTurns(a.view(), Position::Zero(), Position::UnitZ()));
  }
}

}  // namespace

BENCHMARK(BM_LinkingNumber)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_WindingTurns)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);
