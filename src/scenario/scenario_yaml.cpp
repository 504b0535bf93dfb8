#include "rov_tether/scenario/scenario_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <tuple>
#include <utility>
#include <vector>

#include "rov_tether/scenario/world_spec.hpp"
#include "rov_tether/spec/camera_reader.hpp"
#include "rov_tether/spec/obstacle_reader.hpp"
#include "rov_tether/spec/tether_reader.hpp"
#include "rov_tether/spec/yaml_read.hpp"
#include "vehicle_yaml.hpp"

namespace rov_tether
{
namespace
{

using spec::readNumber;
using spec::readVector;

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

/// Applies every key of a YAML map to params (spec::readTetherParams, the node's reader too); collects
/// all problems (type and range) and prints the warnings.
std::string applyParamMap(const YAML::Node& map, const std::string& prefix, TetherParams* params)
{
  std::vector<std::string> warnings;
  const std::string error = spec::readTetherParams(map, prefix, spec::ParamKeys::kEvery, params, &warnings);
  for (const auto& warning : warnings)
  {
    std::fprintf(stderr, "rov_tether: warning: %s\n", warning.c_str());
  }
  return error;
}

/// The scenario's `cameras` (spec::readCameras, as the node's): each rides on the vehicle; at most 1e6
/// frames each over the run (a duration of 0, left out, has no end to count them to).
std::string readCameras(const YAML::Node& node, double duration, std::vector<ScenarioCamera>* cameras)
{
  std::vector<spec::CameraSpec> read;
  const std::string error = spec::readCameras(node, spec::CameraMount::kVehicle, &read);
  if (!error.empty())
  {
    return error;
  }
  for (std::size_t k = 0; k < read.size(); ++k)
  {
    const spec::CameraSpec& camera = read[k];
    if (duration > 0.0 && duration * camera.rate > kMaxOutputTimes)
    {
      return "cameras[" + std::to_string(k) + "].rate: duration x rate = " + std::to_string(duration * camera.rate) +
             ": more than 1e6 frames";
    }
    cameras->push_back(camera);
  }
  return "";
}

/// Reads a spool that rides on another tether's vehicle: `{on: name, outlet_offset: [x, y, z]}` (the offset
/// optional, zero by default).
std::string readSpoolMount(const YAML::Node& node, const std::string& field, ScenarioTether* tether)
{
  for (const auto& entry : node)
  {
    const std::string key = entry.first.as<std::string>();
    if (key != "on" && key != "outlet_offset")
    {
      return field + ": unknown field '" + key + "' (expected [x, y, z], or on and outlet_offset)";
    }
  }
  if (!node["on"])
  {
    return field + ".on: missing (the tether whose vehicle carries this spool)";
  }
  std::string error = spec::readText(node["on"], field + ".on", &tether->spool_on);
  if (error.empty() && node["outlet_offset"])
  {
    Position offset;
    error = spec::readPosition(node["outlet_offset"], field + ".outlet_offset", &offset);
    tether->spool_outlet_offset = offset;
  }
  return error;
}

/// Reads one entry of `tethers` (see ScenarioTether); "" or a message naming the field.
std::string readTether(const YAML::Node& node, const std::string& field, const std::string& base_dir,
                       ScenarioTether* tether)
{
  if (!node.IsMap())
  {
    return field + ": expected a map with name, params, spool, vehicle";
  }
  for (const auto& entry : node)
  {
    const std::string key = entry.first.as<std::string>();
    if (key != "name" && key != "params" && key != "spool" && key != "vehicle" && key != "max_tension_warning")
    {
      return field + ": unknown field '" + key + "' (expected name, params, spool, vehicle, max_tension_warning)";
    }
  }
  if (!node["name"])
  {
    return field + ".name: missing";
  }
  tether->name = node["name"].IsScalar() ? node["name"].Scalar() : "";
  if (!isTetherName(tether->name))  // the one rule (world_spec.hpp), said here where the entry is read
  {
    return field + ".name = '" + tether->name + "': expected " + kTetherNameRule + " (a directory name)";
  }
  if (node["params"])
  {
    const std::string error = applyParamMap(node["params"], field + ".params.", &tether->params);
    if (!error.empty())
    {
      return error;
    }
  }
  const std::string error = node["spool"] && node["spool"].IsMap()
                                ? readSpoolMount(node["spool"], field + ".spool", tether)
                                : spec::readPosition(node["spool"], field + ".spool", &tether->spool);
  if (!error.empty())
  {
    return error;
  }
  if (node["max_tension_warning"])
  {
    const std::string warning_error =
        readNumber(node["max_tension_warning"], field + ".max_tension_warning", &tether->max_tension_warning);
    if (!warning_error.empty() || !(tether->max_tension_warning >= 0.0))
    {
      return warning_error.empty() ? field + ".max_tension_warning: expected a tension >= 0 [N]" : warning_error;
    }
  }
  return node["vehicle"] ? scenario_yaml::readVehicle(node["vehicle"], field + ".vehicle", base_dir, &tether->vehicle,
                                                      &tether->dynamic)
                         : "";
}

std::string readTethers(const YAML::Node& node, const std::string& base_dir, std::vector<ScenarioTether>* tethers)
{
  if (!node.IsSequence() || node.size() == 0)
  {
    return "tethers: expected a non-empty list of maps (name, params, spool, vehicle)";
  }
  for (std::size_t k = 0; k < node.size(); ++k)
  {
    ScenarioTether tether;
    const std::string field = "tethers[" + std::to_string(k) + "]";
    const std::string error = readTether(node[k], field, base_dir, &tether);
    if (!error.empty())
    {
      return error;
    }
    tethers->push_back(tether);
  }
  return "";
}

/// The scenario's `obstacles` (spec::readObstacles): no tf frames; a mesh `file` is a path, relative ones
/// taken from `base_dir`. A mesh is read once, when the world is built (buildWorld), not here.
std::string readObstacles(const YAML::Node& node, const std::string& base_dir, std::vector<ObstacleSpec>* obstacles)
{
  spec::ObstacleReading reading;
  reading.file = [&base_dir](const std::string& file, std::string* error) -> std::string
  {
    if (file.find("://") != std::string::npos)
    {
      *error = "expected a path (absolute, or relative to the scenario file's directory); '" + file +
               "' is a URI, which only the node resolves";
      return "";
    }
    const std::filesystem::path path(file);
    return path.is_absolute() || base_dir.empty() ? file : (std::filesystem::path(base_dir) / path).string();
  };
  return spec::readObstacles(node, reading, obstacles);
}

/// "" when every top-level key of the scenario is known, else the message naming the first unknown one.
std::string checkScenarioKeys(const YAML::Node& root)
{
  for (const auto& entry : root)
  {
    const std::string key = entry.first.as<std::string>();
    if (key != "description" && key != "params" && key != "spool" && key != "vehicle" && key != "duration" &&
        key != "output_rate" && key != "cameras" && key != "obstacles" && key != "tethers" && key != "tether_contact")
    {
      return "unknown field '" + key +
             "' (expected description, params, spool, vehicle, duration, output_rate, cameras, obstacles, tethers, "
             "tether_contact)";
    }
  }
  return "";
}

/// The tethers: either the `tethers` list or one tether at the top level (params, spool, vehicle).
std::string readScenarioTethers(const YAML::Node& root, const std::string& base_dir, Scenario* result)
{
  if (root["tethers"])
  {
    // Either one tether at the top level or a list of them, never both: a top-level field beside the list
    // would be ambiguous (a default for each, or a tether of its own?).
    for (const char* single : {"params", "spool", "vehicle", "cameras"})
    {
      if (root[single])
      {
        return std::string(single) + ": not with `tethers` (each tether has its own params, spool and vehicle" +
               (std::string(single) == "cameras" ? "; cameras ride only on a single tether's vehicle)" : ")");
      }
    }
    return readTethers(root["tethers"], base_dir, &result->tethers);
  }
  if (root["params"])
  {
    const std::string error = applyParamMap(root["params"], "params.", &result->params);
    if (!error.empty())
    {
      return error;
    }
  }
  const std::string error = spec::readPosition(root["spool"], "spool", &result->spool);
  if (!error.empty())
  {
    return error;
  }
  return root["vehicle"]
             ? scenario_yaml::readVehicle(root["vehicle"], "vehicle", base_dir, &result->vehicle, &result->dynamic)
             : "";
}

/// `duration` (required unless `duration` says it is not: then 0 when left out) and `output_rate`, each in its
/// range, with at most kMaxOutputTimes output times over a duration given.
std::string readScenarioTimes(const YAML::Node& root, ScenarioDuration duration, Scenario* result)
{
  std::string error;
  if (root["duration"])
  {
    error = readNumber(root["duration"], "duration", &result->duration);
    if (!error.empty())
    {
      return error;
    }
    if (result->duration <= 0.0 || result->duration > 1.0e6)
    {
      return "duration = " + std::to_string(result->duration) + ": must be in (0, 1e6] s";
    }
  }
  else if (duration == ScenarioDuration::kRequired)
  {
    return "duration: missing (simulated time in s)";
  }
  if (root["output_rate"])
  {
    error = readNumber(root["output_rate"], "output_rate", &result->output_rate);
    if (!error.empty())
    {
      return error;
    }
  }
  if (result->output_rate <= 0.0 || result->output_rate > 1.0e4)
  {
    return "output_rate = " + std::to_string(result->output_rate) + ": must be in (0, 1e4] rows per s";
  }
  if (result->duration > 0.0 && result->duration * result->output_rate > kMaxOutputTimes)
  {
    return "duration x output_rate = " + std::to_string(result->duration * result->output_rate) +
           ": more than 1e6 output times";
  }
  return "";
}

/// `cameras` (each rides on the vehicle, so a vehicle path is needed), `tether_contact` and `obstacles`.
std::string readScenarioSurroundings(const YAML::Node& root, const std::string& base_dir, Scenario* result)
{
  if (root["cameras"])
  {
    const std::string error = readCameras(root["cameras"], result->duration, &result->cameras);
    if (!error.empty())
    {
      return error;
    }
    if (!result->cameras.empty() && result->vehicle.empty())
    {
      return "cameras: a camera rides on the vehicle, and this scenario has no vehicle path";
    }
    if (!result->cameras.empty() && result->dynamic)
    {
      return "cameras: not with a dynamic vehicle (a camera rides on the path's poses, not on the body's)";
    }
  }
  if (root["tether_contact"])
  {
    const YAML::Node node = root["tether_contact"];
    if (!node.IsScalar() || node.Tag() == "!" || !YAML::convert<bool>::decode(node, result->tether_contact))
    {
      return "tether_contact: expected true or false";
    }
  }
  return root["obstacles"] ? readObstacles(root["obstacles"], base_dir, &result->obstacles) : "";
}

std::string parseScenarioNode(const YAML::Node& root, const std::string& base_dir, Scenario* scenario,
                              ScenarioDuration duration = ScenarioDuration::kRequired)
{
  if (!root.IsMap())
  {
    return "scenario: expected a map with params, spool, vehicle, duration, output_rate";
  }
  std::string error = checkScenarioKeys(root);
  if (!error.empty())
  {
    return error;
  }
  Scenario result;
  if (root["description"])
  {
    result.description = root["description"].as<std::string>();
  }
  error = readScenarioTethers(root, base_dir, &result);
  if (error.empty())
  {
    error = readScenarioTimes(root, duration, &result);
  }
  if (error.empty())
  {
    error = readScenarioSurroundings(root, base_dir, &result);
  }
  if (error.empty())
  {
    // Names across tethers, obstacles and cameras: the world's one check (buildWorld makes it again).
    error = validateWorldSpec(worldSpecOf(result));
  }
  if (!error.empty())
  {
    return error;
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

std::string parseScenario(const std::string& yaml_text, Scenario* scenario, ScenarioDuration duration)
{
  return guardYaml(
      [&]
      {
        YAML::Node root;
        const std::string error = spec::loadYamlText(yaml_text, &root);
        return error.empty() ? parseScenarioNode(root, "", scenario, duration) : error;
      });
}

std::string loadScenario(const std::string& path, Scenario* scenario)
{
  const std::string base_dir = std::filesystem::path(path).parent_path().string();
  return parseFile(path,
                   [&](const std::string& text)
                   {
                     return guardYaml(
                         [&]
                         {
                           YAML::Node root;
                           const std::string error = spec::loadYamlText(text, &root);
                           return error.empty() ? parseScenarioNode(root, base_dir, scenario) : error;
                         });
                   });
}

std::string parseParams(const std::string& yaml_text, TetherParams* params)
{
  return guardYaml(
      [&]
      {
        YAML::Node root;
        const std::string duplicate = spec::loadYamlText(yaml_text, &root);
        if (!duplicate.empty())
        {
          return duplicate;
        }
        TetherParams candidate = *params;
        const std::string error = applyParamMap(root, "", &candidate);
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
  return applyAssignments({assignment}, params);
}

std::string applyAssignments(const std::vector<std::string>& assignments, TetherParams* params)
{
  return guardYaml(
      [&]() -> std::string
      {
        YAML::Node root(YAML::NodeType::Map);
        const YAML::Node& given = root;  // reading a key through a non-const node would add it
        for (const std::string& assignment : assignments)
        {
          // The name without the spaces and tabs around it, as YAML drops them round a key (`--set 'noise = 0.001'`).
          const auto equals = assignment.find('=');
          std::string name = equals == std::string::npos ? "" : assignment.substr(0, equals);
          name.erase(name.find_last_not_of(" \t") + 1);
          name.erase(0, name.find_first_not_of(" \t"));
          if (name.empty())
          {
            return "'" + assignment + "': expected name=value";
          }
          if (given[name])
          {
            return "'" + name + "' given twice";
          }
          YAML::Node value;
          const std::string duplicate = spec::loadYamlText(assignment.substr(equals + 1), &value);
          if (!duplicate.empty())
          {
            return name + ": " + duplicate;
          }
          root[name] = value;
        }
        TetherParams candidate = *params;
        const std::string error = applyParamMap(root, "", &candidate);
        if (error.empty())
        {
          *params = candidate;
        }
        return error;
      });
}

}  // namespace rov_tether
