#include "rov_tether/spec/vehicle_reader.hpp"

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

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

std::string joined(const std::vector<std::string>& problems)
{
  std::string text;
  for (const auto& problem : problems)
  {
    text += (text.empty() ? "" : "; ") + problem;
  }
  return text;
}

}  // namespace

std::string readVehicleParams(const YAML::Node& map, const std::string& prefix, VehicleParams* params)
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
  if (problems.empty())
  {
    *params = candidate;
  }
  return joined(problems);
}

std::string loadVehicleParamsFile(const std::string& path, VehicleParams* params)
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
    return readVehicleParams(YAML::Load(text.str()), path, params);
  }
  catch (const YAML::Exception& e)
  {
    return path + ": YAML error: " + e.what();
  }
}

}  // namespace rov_tether::spec
