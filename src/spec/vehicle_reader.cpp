#include "rov_tether/spec/vehicle_reader.hpp"

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include "rov_tether/core/status.hpp"
#include "rov_tether/spec/yaml_read.hpp"

namespace rov_tether::spec
{
namespace
{

// Where each field of a parameter file goes, and how many numbers it holds (1 = a plain number).
struct Field
{
  const char* name;
  std::size_t size;
  double* values;
};

std::vector<Field> fieldsOf(VehicleParams* p)
{
  return {{"mass", 1, &p->mass},
          {"displaced_volume", 1, &p->displaced_volume},
          {"water_density", 1, &p->water_density},
          {"gravity", 1, &p->gravity},
          {"inertia", 3, p->inertia.data()},
          {"center_of_gravity", 3, p->center_of_gravity.data()},
          {"center_of_buoyancy", 3, p->center_of_buoyancy.data()},
          {"added_mass", 6, p->added_mass.data()},
          {"linear_damping", 6, p->linear_damping.data()},
          {"quadratic_damping", 6, p->quadratic_damping.data()},
          {"thrust_limit", 6, p->thrust_limit.data()},
          {"size", 3, p->size.data()}};
}

}  // namespace

std::string readControllerGains(const YAML::Node& map, const std::string& prefix, const VehicleParams& vehicle,
                                ControllerGains* gains)
{
  const std::string file = prefix.empty() ? "" : prefix + ": ";
  const std::string at = file + "controller: ";
  const char* const keys =
      "bandwidth, damping_ratio, integral_ratio, level_bandwidth, proportional, integral, derivative, integral_limit";
  if (!map.IsMap())
  {
    return at + "expected a map (" + keys + ")";
  }
  // The design keys, then the gain keys (read into `given`, copied over the design where given).
  ControllerDesign design;
  ControllerGains given;
  const std::vector<Field> fields = {
      {"bandwidth", 4, design.bandwidth.data()},      {"damping_ratio", 1, &design.damping_ratio},
      {"integral_ratio", 1, &design.integral_ratio},  {"level_bandwidth", 1, &design.level_bandwidth},
      {"proportional", 4, given.proportional.data()}, {"integral", 4, given.integral.data()},
      {"derivative", 4, given.derivative.data()},     {"integral_limit", 4, given.integral_limit.data()}};
  std::vector<std::string> problems;
  std::set<std::string> seen;
  for (const auto& entry : map)
  {
    const std::string key = entry.first.Scalar();
    if (!seen.insert(key).second)
    {
      problems.push_back(at + key + ": given twice");
      continue;
    }
    const auto field = std::find_if(fields.begin(), fields.end(), [&](const Field& f) { return key == f.name; });
    if (field == fields.end())
    {
      problems.push_back(at + key + ": no controller setting of that name (" + keys + ")");
      continue;
    }
    const std::string error = field->size == 1 ? readNumber(entry.second, key, field->values)
                                               : readVector(entry.second, key, field->size, field->values);
    if (!error.empty())
    {
      problems.push_back(at + error);
    }
  }
  if (!problems.empty())
  {
    return joinMessages(problems);
  }
  ControllerGains candidate;
  const Status designed = ControllerGains::design(vehicle, design, &candidate);
  if (!designed)
  {
    return file + designed.message;  // "controller design: ..."
  }
  const std::pair<const char*, Vector4 ControllerGains::*> gain_keys[] = {
      {"proportional", &ControllerGains::proportional},
      {"integral", &ControllerGains::integral},
      {"derivative", &ControllerGains::derivative},
      {"integral_limit", &ControllerGains::integral_limit}};
  for (const auto& [name, member] : gain_keys)
  {
    if (seen.count(name) != 0)
    {
      candidate.*member = given.*member;
    }
  }
  VehicleController check;
  const Status accepted = check.configure(vehicle, candidate);
  if (!accepted)
  {
    return file + accepted.message;  // "controller: ..."
  }
  *gains = candidate;
  return "";
}

std::string readVehicleParams(const YAML::Node& map, const std::string& prefix, VehicleParams* params,
                              ControllerGains* gains)
{
  const std::string at = prefix.empty() ? "" : prefix + ": ";
  if (!map.IsMap())
  {
    return at + "expected a map of the vehicle's parameters (mass, displaced_volume, ...)";
  }
  VehicleParams candidate;
  const std::vector<Field> fields = fieldsOf(&candidate);
  std::vector<std::string> problems;
  std::set<std::string> seen;
  YAML::Node controller;
  bool has_controller = false;
  for (const auto& entry : map)
  {
    const std::string key = entry.first.Scalar();
    if (!seen.insert(key).second)
    {
      problems.push_back(at + key + ": given twice");
      continue;
    }
    if (key == "controller")
    {
      controller = entry.second;
      has_controller = true;
      continue;
    }
    const auto field = std::find_if(fields.begin(), fields.end(), [&](const Field& f) { return key == f.name; });
    if (field == fields.end())
    {
      problems.push_back(at + key + ": no vehicle parameter of that name");
      continue;
    }
    const std::string error = field->size == 1 ? readNumber(entry.second, key, field->values)
                                               : readVector(entry.second, key, field->size, field->values);
    if (!error.empty())
    {
      problems.push_back(at + error);
    }
  }
  for (const auto& field : fields)
  {
    if (seen.count(field.name) == 0)
    {
      problems.push_back(at + field.name + ": missing" +
                         (field.size == 1 ? "" : " (expected a list of " + std::to_string(field.size) + " numbers)"));
    }
  }
  if (problems.empty())
  {
    const Status valid = candidate.validate();
    if (!valid)
    {
      problems.push_back(at + valid.message);
    }
  }
  // The controller: the block's gains, or without one the default design for this vehicle.
  ControllerGains candidate_gains;
  if (problems.empty() && has_controller)
  {
    const std::string error = readControllerGains(controller, prefix, candidate, &candidate_gains);
    if (!error.empty())
    {
      problems.push_back(error);
    }
  }
  else if (problems.empty())
  {
    const Status designed = ControllerGains::design(candidate, ControllerDesign{}, &candidate_gains);
    if (!designed)
    {
      problems.push_back(at + designed.message);
    }
    else
    {
      // The designed gains must pass the controller's own check, as a block's do (readControllerGains): a
      // mass of 1e300 kg designs infinite gains, which the controller refused only when the run started (an abort).
      VehicleController check;
      const Status accepted = check.configure(candidate, candidate_gains);
      if (!accepted)
      {
        problems.push_back(at + "the controller designed for this vehicle: " + accepted.message);
      }
    }
  }
  if (problems.empty())
  {
    *params = candidate;
    if (gains != nullptr)
    {
      *gains = candidate_gains;
    }
  }
  return joinMessages(problems);
}

std::string loadVehicleParamsFile(const std::string& path, VehicleParams* params, ControllerGains* gains)
{
  std::ifstream file(path);
  if (!file)
  {
    return path + ": cannot be read";
  }
  std::stringstream text;
  text << file.rdbuf();
  try
  {
    YAML::Node root;
    const std::string problem = loadYamlText(text.str(), &root);  // a repeated key, a second document
    return problem.empty() ? readVehicleParams(root, path, params, gains) : path + ": " + problem;
  }
  catch (const YAML::Exception& e)
  {
    return path + ": YAML error: " + e.what();
  }
}

}  // namespace rov_tether::spec
