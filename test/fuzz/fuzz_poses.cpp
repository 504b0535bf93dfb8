// libFuzzer target: random pose sequences, times, spool moves, winch commands, parameter changes and
// resets fed into the core. Invariants after every operation: no crash, every deployed particle finite,
// the deployed length within [min_deployed_length, cable_length], tensions finite.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "fuzz_input.hpp"
#include "rov_tether/core/tether.hpp"

using namespace rov_tether;

namespace
{

[[noreturn]] void fail(const char* what)
{
  std::fprintf(stderr, "invariant broken: %s\n", what);
  std::abort();
}

void check(const Tether& sim, std::vector<double>& tensions)
{
  const TetherParams& p = sim.params();
  const double deployed = sim.deployedLength();
  if (!(deployed >= p.min_deployed_length - 1e-9 && deployed <= p.cable_length + 1e-9))
  {
    fail("deployed length outside [min_deployed_length, cable_length]");
  }
  for (std::size_t k = 0; k < sim.deployedParticleCount(); ++k)
  {
    if (!sim.particle(k).allFinite())
    {
      fail("non-finite particle");
    }
  }
  sim.computeSegmentTensions(tensions);
  for (double t : tensions)
  {
    if (!std::isfinite(t))
    {
      fail("non-finite tension");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  fuzz::Input in(data, size);
  TetherParams params;
  params.cable_length = 20.0;
  params.segment_length = 0.5;
  params.initial_deployed_length = 3.0;
  // Every solver and every winch mode: the last enumerator + 1. The asserts catch one inserted before the last;
  // one added after kDirect or kStrain must raise the count and the assert by hand.
  static_assert(static_cast<int>(SolverType::kDirect) == 4, "fuzz every solver: update the count");
  static_assert(static_cast<int>(WinchMode::kStrain) == 4, "fuzz every winch mode: update the count");
  params.solver = static_cast<SolverType>(in.byte() % 5);
  params.drag_model = in.byte() & 1 ? DragModel::kMorison : DragModel::kDamping;
  params.winch_mode = static_cast<WinchMode>(in.byte() % 5);
  params.weight_in_water = in.number(5.0);
  params.current = {in.number(1.0), in.number(1.0), in.number(1.0)};
  if (in.byte() & 1)
  {
    params.seabed_z = in.number(10.0);
  }
  if (params.solver == SolverType::kLumpedMass)
  {
    params.substeps = 1 + in.byte() % 80;  // below and above the critical step
  }
  if (!params.validate().empty())
  {
    return 0;  // the fuzz_params target covers refused sets
  }
  Tether sim(params, Position(0.0, 0.0, -1.0));
  std::vector<double> tensions;
  double t = 0.0;
  double budget = 5e5;  // particle sub-steps: about a second under the sanitizers
  for (int op = 0; op < 64 && !in.empty(); ++op)
  {
    switch (in.byte() % 8)
    {
      case 0:
      case 1:
      case 2:
        t += in.byte() & 1 ? in.number(0.5) : in.rawDouble();  // any time: backwards, NaN, huge
        // Here and below, a refusal is an expected answer to fuzzed input (the Status is dropped on purpose):
        // what is checked is that refused or not, the invariants hold after every operation (check).
        static_cast<void>(sim.addVehicleSample(t, Position(in.number(30.0), in.number(30.0), in.number(30.0))));
        break;
      case 3:
      {
        const double dt = in.byte() & 1 ? in.number(0.3) : in.rawDouble();
        // Particle sub-steps this advance takes; an input may take kWork of them in all (tiny steps in many
        // lumped_mass sub-steps once took a minute: a timeout that says nothing about correctness).
        const TetherParams& p = sim.params();
        const double work = std::abs(dt) / p.time_step * p.substeps * static_cast<double>(sim.deployedParticleCount());
        if ((std::abs(dt) < 0.3 || !std::isfinite(dt)) && !(work > budget))
        {
          static_cast<void>(sim.advance(dt));  // negative and non-finite are refused
          budget -= std::isfinite(work) ? work : 0.0;
        }
        break;
      }
      case 4:
        static_cast<void>(sim.setSpoolPosition(Position(in.number(5.0), in.number(5.0), in.number(5.0))));
        break;
      case 5:
        static_cast<void>(sim.setTargetLength(in.number(25.0)));
        break;
      case 6:
      {
        TetherParams changed = sim.params();
        changed.drag = in.number(1.0);
        changed.iterations = 1 + in.byte() % 30;
        changed.time_step = std::abs(in.number(0.02));
        changed.winch_speed = in.number(2.0);
        static_cast<void>(sim.setParams(changed));  // refused when invalid
        break;
      }
      default:
        if (in.byte() % 8 == 0)
        {
          static_cast<void>(sim.reset(std::isfinite(t) ? t : 0.0));  // refused beyond Tether::kMaxTime
        }
    }
    check(sim, tensions);
  }
  return 0;
}
