#include "rov_tether/scenario_runner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace rov_tether
{

const char* const kStateCsvHeader = "t,deployed_length,tension_spool,tension_vehicle,max_tension,max_strain";
const char* const kShapeCsvHeader = "t,i,x,y,z,tension";

std::string runScenario(const Scenario& scenario, const std::string& out_dir, RunSummary* summary,
                        const std::vector<RunObserver*>& observers)
{
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec)
  {
    return "cannot create output directory '" + out_dir + "': " + ec.message();
  }
  const fs::path state_path = fs::path(out_dir) / "state.csv";
  const fs::path shape_path = fs::path(out_dir) / "shape.csv";
  const fs::path state_tmp = fs::path(out_dir) / ".state.csv.partial";
  const fs::path shape_tmp = fs::path(out_dir) / ".shape.csv.partial";
  std::FILE* state_file = std::fopen(state_tmp.c_str(), "w");
  std::FILE* shape_file = state_file ? std::fopen(shape_tmp.c_str(), "w") : nullptr;
  if (state_file == nullptr || shape_file == nullptr)
  {
    if (state_file)
    {
      std::fclose(state_file);
      fs::remove(state_tmp, ec);
    }
    return "cannot write in '" + out_dir + "'";
  }

  PathDriver driver(scenario);
  Tether sim = driver.makeSimulation();
  RunSummary result;
  result.deployed_start = sim.deployedLength();
  std::fprintf(state_file, "%s\n", kStateCsvHeader);
  std::fprintf(shape_file, "%s\n", kShapeCsvHeader);

  std::vector<double> tensions;
  std::vector<Position> positions;
  double cpu = 0.0;
  std::string observer_error;
  // Lets the observers look at every time of theirs up to `until` [s], in time order.
  const auto observe = [&](double until)
  {
    while (observer_error.empty())
    {
      RunObserver* next = nullptr;
      for (RunObserver* observer : observers)
      {
        if (observer->nextTime() <= until + 1e-9 && (!next || observer->nextTime() < next->nextTime()))
        {
          next = observer;
        }
      }
      if (next == nullptr)
      {
        return;
      }
      const auto start = std::chrono::steady_clock::now();
      driver.advanceTo(sim, next->nextTime());
      cpu += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      observer_error = next->observe(sim);
    }
  };
  const auto outputs = static_cast<std::size_t>(std::floor(scenario.duration * scenario.output_rate + 1e-9));
  for (std::size_t k = 0; k <= outputs; ++k)
  {
    const double t_out = static_cast<double>(k) / scenario.output_rate;
    observe(t_out);
    const auto start = std::chrono::steady_clock::now();
    driver.advanceTo(sim, t_out);
    cpu += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    sim.computeSegmentTensions(tensions);
    const TetherSummary s = sim.summarize(tensions);
    sim.copyPositions(positions);
    std::fprintf(state_file, "%.6f,%.6f,%.6g,%.6g,%.6g,%.6g\n", t_out, s.deployed_length, s.tension_spool,
                 s.tension_vehicle, s.max_tension, s.max_strain);
    for (std::size_t i = 0; i < positions.size(); ++i)
    {
      std::fprintf(shape_file, "%.6f,%zu,%.6f,%.6f,%.6f,", t_out, i, positions[i].x(), positions[i].y(),
                   positions[i].z());
      if (i < tensions.size())
      {
        std::fprintf(shape_file, "%.6g", tensions[i]);
      }
      std::fputc('\n', shape_file);
    }
    ++result.state_rows;
    result.shape_rows += positions.size();
    result.deployed_max = std::max(result.deployed_max, s.deployed_length);
    result.max_tension = std::max(result.max_tension, s.max_tension);
    result.max_tension_vehicle = std::max(result.max_tension_vehicle, s.tension_vehicle);
    result.max_strain = std::max(result.max_strain, s.max_strain);
  }
  observe(scenario.duration);
  const bool written = observer_error.empty() && std::ferror(state_file) == 0 && std::ferror(shape_file) == 0;
  const bool state_closed = std::fclose(state_file) == 0;
  const bool closed = std::fclose(shape_file) == 0 && state_closed;
  if (!written || !closed)
  {
    fs::remove(state_tmp, ec);
    fs::remove(shape_tmp, ec);
    return observer_error.empty() ? "error while writing in '" + out_dir + "'" : observer_error;
  }
  fs::rename(state_tmp, state_path, ec);
  if (!ec)
  {
    fs::rename(shape_tmp, shape_path, ec);
  }
  if (ec)
  {
    return "cannot move the output into place in '" + out_dir + "': " + ec.message();
  }
  result.steps = sim.stepCount();
  result.cpu_seconds = cpu;
  result.deployed_end = sim.deployedLength();
  result.jumps = sim.jumpCount();
  if (summary != nullptr)
  {
    *summary = result;
  }
  return "";
}

}  // namespace rov_tether
