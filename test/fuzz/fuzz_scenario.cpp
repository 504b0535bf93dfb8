// libFuzzer target: the scenario and parameter file parsers (YAML text from the fuzzer). A file that
// parses must describe a valid model (validate() empty) and a short run of it must be accepted and stay finite.
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "rov_tether/core/direct_solver.hpp"
#include "rov_tether/scenario/scenario_runner.hpp"
#include "rov_tether/scenario/scenario_yaml.hpp"

using namespace rov_tether;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  TetherParams params;
  if (parseParams(text, &params).empty() && !params.validate().empty())
  {
    std::abort();  // accepted parameters must be valid
  }
  Scenario scenario;
  if (!parseScenario(text, &scenario).empty())
  {
    return 0;
  }
  if (!scenario.params.validate().empty())
  {
    std::abort();
  }
  // Run what parsed, briefly and only when small (the fuzzer must stay fast under its 10 s timeout): the work
  // is sub-steps x segments x solver iterations, at most 2e5. A 40-iteration xpbd run with bending at 1,000
  // segments (1.6e6) took 14 s in the sanitized fuzz build, 0.14 s at -O3
  // (test/fuzz/corpus/fuzz_scenario/timeout-xpbd-40-iterations): 2e5 keeps such a run under 2 s. A `direct`
  // sub-step that diverges goes on for up to kRescueBudget times its iterations more: counted as if every one did.
  const TetherParams& p = scenario.params.resolved();
  const int rescue = p.solver == SolverType::kDirect ? 1 + DirectSolver::kRescueBudget : 1;
  const double work = 0.2 / p.time_step * p.substeps * static_cast<double>(p.segmentCount()) *
                      static_cast<double>(std::max(p.iterations, 1) * rescue);
  if (work > 2e5)
  {
    return 0;
  }
  PathDriver driver(scenario);
  Tether sim = driver.makeSimulation();
  if (!driver.advanceTo(sim, 0.2).ok)
  {
    std::abort();  // a path that parsed was validated: the simulation must accept its samples
  }
  for (std::size_t k = 0; k < sim.deployedParticleCount(); ++k)
  {
    if (!sim.particle(k).allFinite())
    {
      std::abort();
    }
  }
  return 0;
}
