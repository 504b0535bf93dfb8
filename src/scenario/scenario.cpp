#include "rov_tether/scenario.hpp"

#include <yaml-cpp/yaml.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace rov_tether
{

const char* const kStateCsvHeader = "t,deployed_length,tension_spool,tension_vehicle,max_tension,max_strain";
const char* const kShapeCsvHeader = "t,i,x,y,z,tension";

namespace
{

/// Largest number of output rows a scenario may ask for (both files together stay manageable).
constexpr double kMaxOutputTimes = 1.0e6;

std::string readFile(const std::string& path, std::string* text)
{
  std::ifstream in(path);
  if (!in)
  {
    return "cannot read '" + path + "'";
  }
  std::ostringstream buffer;
  buffer << in.rdbuf();
  *text = buffer.str();
  return "";
}

/// Converts a YAML scalar to the most specific ParamValue: bool, integer, number, then string.
ParamValue scalarValue(const YAML::Node& node)
{
  const std::string& text = node.Scalar();
  if (node.Tag() != "!")  // unquoted: may be a bool or a number
  {
    bool b;
    std::int64_t i;
    double d;
    if (YAML::convert<bool>::decode(node, b) && text.find_first_of("0123456789") == std::string::npos)
    {
      return b;
    }
    if (YAML::convert<std::int64_t>::decode(node, i))
    {
      return i;
    }
    if (YAML::convert<double>::decode(node, d))
    {
      return d;
    }
  }
  return text;
}

/// Reads a finite number; returns "" or a message naming `field`.
std::string readNumber(const YAML::Node& node, const std::string& field, double* value)
{
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, *value))
  {
    return field + ": expected a number";
  }
  if (!std::isfinite(*value))
  {
    return field + ": must be finite";
  }
  return "";
}

std::string readVector(const YAML::Node& node, const std::string& field, std::size_t size, double* values)
{
  if (!node.IsSequence() || node.size() != size)
  {
    return field + ": expected a list of " + std::to_string(size) + " numbers";
  }
  for (std::size_t i = 0; i < size; ++i)
  {
    const std::string error = readNumber(node[i], field + "[" + std::to_string(i) + "]", &values[i]);
    if (!error.empty())
    {
      return error;
    }
  }
  return "";
}

/// Applies every key of a YAML map to params; collects all problems (type and range).
std::string applyParamMap(const YAML::Node& map, const std::string& prefix, TetherParams* params)
{
  if (!map.IsMap())
  {
    return prefix.empty() ? "parameters: expected a map of name: value" : prefix + ": expected a map of name: value";
  }
  std::vector<std::string> errors;
  for (const auto& entry : map)
  {
    const std::string name = entry.first.as<std::string>();
    ParamValue value;
    if (entry.second.IsSequence())
    {
      std::vector<double> list;
      for (const auto& item : entry.second)
      {
        double number = 0.0;
        if (!item.IsScalar() || !YAML::convert<double>::decode(item, number))
        {
          list.clear();
          break;
        }
        list.push_back(number);
      }
      if (list.size() != entry.second.size())
      {
        errors.push_back(prefix + name + ": expected a list of numbers");
        continue;
      }
      value = list;
    }
    else if (entry.second.IsScalar())
    {
      value = scalarValue(entry.second);
    }
    else
    {
      errors.push_back(prefix + name + ": expected a single value or a list of numbers");
      continue;
    }
    const std::string error = setParameter(*params, name, value);
    if (!error.empty())
    {
      errors.push_back(prefix + error);
    }
  }
  if (errors.empty())
  {
    for (const auto& error : params->validate())
    {
      errors.push_back(prefix + error);
    }
  }
  std::string joined;
  for (const auto& error : errors)
  {
    joined += (joined.empty() ? "" : "; ") + error;
  }
  return joined;
}

std::string parseScenarioNode(const YAML::Node& root, Scenario* scenario)
{
  if (!root.IsMap())
  {
    return "scenario: expected a map with params, spool, vehicle, duration, output_rate";
  }
  for (const auto& entry : root)
  {
    const std::string key = entry.first.as<std::string>();
    if (key != "description" && key != "params" && key != "spool" && key != "vehicle" && key != "duration" &&
        key != "output_rate")
    {
      return "unknown field '" + key + "' (expected description, params, spool, vehicle, duration, output_rate)";
    }
  }
  Scenario result;
  if (root["description"])
  {
    result.description = root["description"].as<std::string>();
  }
  if (root["params"])
  {
    const std::string error = applyParamMap(root["params"], "params.", &result.params);
    if (!error.empty())
    {
      return error;
    }
  }
  if (!root["spool"])
  {
    return "spool: missing (expected [x, y, z] in m)";
  }
  std::string error = readVector(root["spool"], "spool", 3, result.spool.data());
  if (!error.empty())
  {
    return error;
  }
  if (root["vehicle"])
  {
    const YAML::Node path = root["vehicle"];
    if (!path.IsSequence() || path.size() == 0)
    {
      return "vehicle: expected a non-empty list of [t, x, y, z] waypoints (omit it for a free end)";
    }
    for (std::size_t k = 0; k < path.size(); ++k)
    {
      double values[4];
      const std::string field = "vehicle[" + std::to_string(k) + "]";
      error = readVector(path[k], field, 4, values);
      if (!error.empty())
      {
        return error;
      }
      if (values[0] < 0.0)
      {
        return field + ": time " + std::to_string(values[0]) + " s must be >= 0";
      }
      if (!result.vehicle.empty() && values[0] < result.vehicle.back().time)
      {
        return field + ": time " + std::to_string(values[0]) + " s is before the previous waypoint's";
      }
      result.vehicle.push_back({values[0], Position(values[1], values[2], values[3])});
    }
  }
  if (!root["duration"])
  {
    return "duration: missing (simulated time in s)";
  }
  error = readNumber(root["duration"], "duration", &result.duration);
  if (!error.empty())
  {
    return error;
  }
  if (result.duration <= 0.0 || result.duration > 1.0e6)
  {
    return "duration = " + std::to_string(result.duration) + ": must be in (0, 1e6] s";
  }
  if (root["output_rate"])
  {
    error = readNumber(root["output_rate"], "output_rate", &result.output_rate);
    if (!error.empty())
    {
      return error;
    }
  }
  if (result.output_rate <= 0.0 || result.output_rate > 1.0e4)
  {
    return "output_rate = " + std::to_string(result.output_rate) + ": must be in (0, 1e4] rows per s";
  }
  if (result.duration * result.output_rate > kMaxOutputTimes)
  {
    return "duration x output_rate = " + std::to_string(result.duration * result.output_rate) +
           ": more than 1e6 output times";
  }
  *scenario = result;
  return "";
}

/// Reads `path` and parses its text; errors are prefixed with the path.
template <typename Parse>
std::string parseFile(const std::string& path, Parse parse)
{
  std::string text;
  const std::string error = readFile(path, &text);
  if (!error.empty())
  {
    return error;
  }
  const std::string parse_error = parse(text);
  return parse_error.empty() ? "" : path + ": " + parse_error;
}

template <typename Parse>
std::string guardYaml(Parse parse)
{
  try
  {
    return parse();
  }
  catch (const YAML::Exception& e)
  {
    return std::string("YAML error: ") + e.what();
  }
}

}  // namespace

Position Scenario::vehicleAt(double t) const
{
  if (vehicle.empty())
  {
    return Position::Zero();
  }
  if (t < vehicle.front().time)
  {
    return vehicle.front().position;
  }
  for (std::size_t k = vehicle.size(); k-- > 0;)
  {
    if (vehicle[k].time <= t)
    {
      if (k + 1 == vehicle.size())
      {
        return vehicle[k].position;
      }
      const Waypoint& a = vehicle[k];
      const Waypoint& b = vehicle[k + 1];
      const double alpha = (t - a.time) / (b.time - a.time);
      return a.position + alpha * (b.position - a.position);
    }
  }
  return vehicle.front().position;
}

Tether PathDriver::makeSimulation() const
{
  if (scenario_.vehicle.empty())
  {
    return Tether(scenario_.params, scenario_.spool, 0.0);
  }
  return Tether(scenario_.params, scenario_.spool, scenario_.vehicleAt(0.0), 0.0);
}

void PathDriver::advanceTo(Tether& sim, double t)
{
  if (!scenario_.vehicle.empty())
  {
    // Feed and advance in chunks of 100 samples, so a long interval never overfills the simulation's
    // sample buffer; the result is the same as feeding everything first.
    while (static_cast<double>(fed_samples_) * kSampleInterval < t + kSampleInterval)
    {
      for (int k = 0; k < 100 && static_cast<double>(fed_samples_) * kSampleInterval < t + kSampleInterval; ++k)
      {
        const double sample_time = static_cast<double>(++fed_samples_) * kSampleInterval;
        sim.addVehicleSample(sample_time, scenario_.vehicleAt(sample_time));
      }
      sim.advanceTo(std::min(t, static_cast<double>(fed_samples_ - 1) * kSampleInterval));
    }
  }
  sim.advanceTo(t);
}

std::string parseScenario(const std::string& yaml_text, Scenario* scenario)
{
  return guardYaml([&] { return parseScenarioNode(YAML::Load(yaml_text), scenario); });
}

std::string loadScenario(const std::string& path, Scenario* scenario)
{
  return parseFile(path, [scenario](const std::string& text) { return parseScenario(text, scenario); });
}

std::string parseParams(const std::string& yaml_text, TetherParams* params)
{
  return guardYaml(
      [&]
      {
        TetherParams candidate = *params;
        const std::string error = applyParamMap(YAML::Load(yaml_text), "", &candidate);
        if (error.empty())
        {
          *params = candidate;
        }
        return error;
      });
}

std::string loadParamsFile(const std::string& path, TetherParams* params)
{
  return parseFile(path, [params](const std::string& text) { return parseParams(text, params); });
}

std::string applyAssignment(const std::string& assignment, TetherParams* params)
{
  const auto equals = assignment.find('=');
  if (equals == std::string::npos || equals == 0)
  {
    return "'" + assignment + "': expected name=value";
  }
  return parseParams(assignment.substr(0, equals) + ": " + assignment.substr(equals + 1), params);
}

std::string runScenario(const Scenario& scenario, const std::string& out_dir, RunSummary* summary)
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
  const auto outputs = static_cast<std::size_t>(std::floor(scenario.duration * scenario.output_rate + 1e-9));
  for (std::size_t k = 0; k <= outputs; ++k)
  {
    const double t_out = static_cast<double>(k) / scenario.output_rate;
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
  const bool written = std::ferror(state_file) == 0 && std::ferror(shape_file) == 0;
  const bool state_closed = std::fclose(state_file) == 0;
  const bool closed = std::fclose(shape_file) == 0 && state_closed;
  if (!written || !closed)
  {
    fs::remove(state_tmp, ec);
    fs::remove(shape_tmp, ec);
    return "error while writing in '" + out_dir + "'";
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
