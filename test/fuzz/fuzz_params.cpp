// libFuzzer target: parameter setting and validation by name, with any value. Whatever validate()
// accepts must build a simulation that steps without a crash or a non-finite state; whatever it refuses
// must be refused by the simulation too.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>

#include "fuzz_input.hpp"
#include "rov_tether/core/tether.hpp"

using namespace rov_tether;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  fuzz::Input in(data, size);
  TetherParams params;
  params.cable_length = 5.0;  // small by default so accepted sets step quickly
  params.segment_length = 0.25;
  params.initial_deployed_length = 2.0;
  const auto& names = parameterNames();
  const int changes = in.byte() % 8;
  for (int i = 0; i < changes; ++i)
  {
    const std::string& name = names[in.byte() % names.size()];
    ParamValue value;
    switch (in.byte() % 6)
    {
      case 0:
        value = static_cast<bool>(in.byte() & 1);
        break;
      case 1:
      {
        const double d = in.number(2000.0);  // integers of any size; NaN becomes 0
        value = std::isfinite(d) ? static_cast<std::int64_t>(std::clamp(d, -1e15, 1e15)) : std::int64_t{0};
        break;
      }
      case 2:
        value = in.number(10.0);
        break;
      case 3:
        value = in.rawDouble();
        break;
      case 4:
        value = in.text(16);
        break;
      default:
        value = std::vector<double>{in.number(5.0), in.number(5.0), in.number(5.0)};
    }
    setParameter(params, name, value);  // may refuse; validate() has the last word
  }
  const bool valid = params.validate().empty();
  try
  {
    Tether sim(params, Position::Zero(), Position(1.0, 0.5, -1.0));
    if (!valid)
    {
      std::abort();  // the constructor must refuse what validate() refuses
    }
    const TetherParams& p = sim.params();
    if (static_cast<double>(p.segmentCount()) * p.substeps * p.iterations > 2e5)
    {
      return 0;  // valid but too slow to step here
    }
    for (int k = 0; k < 20; ++k)
    {
      sim.step();
    }
    const TetherSummary s = sim.summary();
    if (!std::isfinite(s.deployed_length) || s.deployed_length > p.cable_length + 1e-9)
    {
      std::abort();
    }
    for (std::size_t k = 0; k < sim.deployedParticleCount(); ++k)
    {
      if (!sim.particle(k).allFinite())
      {
        std::abort();
      }
    }
  }
  catch (const std::invalid_argument&)
  {
    if (valid)
    {
      std::abort();  // a valid set must be accepted
    }
  }
  return 0;
}
