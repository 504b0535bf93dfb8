#include "rov_tether/spec/obstacle_reader.hpp"

#include <algorithm>
#include <iterator>
#include <tuple>
#include <utility>

#include "rov_tether/core/tether.hpp"
#include "rov_tether/spec/yaml_read.hpp"

namespace rov_tether::spec
{
namespace
{

const char* const kFields[] = {"name", "type", "position", "orientation", "radius", "length",
                               "size", "file", "scale",    "friction",    "frame"};

std::string fieldList(bool frames)
{
  std::string list;
  for (const char* field : kFields)
  {
    if (frames || std::string(field) != "frame")
    {
      list += (list.empty() ? "" : ", ") + std::string(field);
    }
  }
  return list;
}

/// The entry's keys: each must be a field (`frame` only where the reading allows it).
std::string checkKeys(const YAML::Node& node, const std::string& who, bool frames)
{
  for (const auto& entry : node)
  {
    const std::string key = entry.first.as<std::string>();
    if (key == "frame" && !frames)
    {
      return who +
             " frame: node only (the tf frame an obstacle moves with); a scenario's obstacles stay "
             "where `position` and `orientation` put them";
    }
    if (std::find(std::begin(kFields), std::end(kFields), key) == std::end(kFields))
    {
      return who + ": unknown field '" + key + "' (expected " + fieldList(frames) + ")";
    }
  }
  return "";
}

/// The entry's shape fields (radius, length, size, file, scale): each must be one its type takes (a sphere's
/// `length` would be read by nothing).
std::string checkShapeFields(const YAML::Node& node, const std::string& who, ShapeType type)
{
  const auto takes = [type](const std::string& field)
  {
    switch (type)
    {
      case ShapeType::Sphere:
        return field == "radius";
      case ShapeType::Cylinder:
      case ShapeType::Capsule:
        return field == "radius" || field == "length";
      case ShapeType::Box:
        return field == "size";
      case ShapeType::Mesh:
        return field == "file" || field == "scale";
      default:
        return false;  // a plane: its position and orientation alone
    }
  };
  for (const char* field : {"radius", "length", "size", "file", "scale"})
  {
    if (node[field] && !takes(field))
    {
      return who + " " + field + ": a " + shapeTypeName(type) + " has no " + field +
             " (sphere: radius; cylinder, capsule: radius, length; box: size; mesh: file, scale; plane: none)";
    }
  }
  return "";
}

/// The numbers and strings of the entry into `candidate`; "" or the first problem.
std::string readFields(const YAML::Node& node, const std::string& who, const ObstacleReading& reading,
                       ObstacleSpec* candidate)
{
  for (const auto& [field, out, unit] :
       {std::tuple{"position", &candidate->position, "[x, y, z] in m"},
        std::tuple{"orientation", &candidate->orientation, "[roll, pitch, yaw] in rad"},
        std::tuple{"size", &candidate->size, "[x, y, z] in m"}})
  {
    if (node[field] && !readVector(node[field], field, 3, out->data()).empty())
    {
      return who + " " + field + ": expected " + unit;
    }
  }
  for (const auto& [field, out] : {std::pair{"radius", &candidate->radius}, std::pair{"length", &candidate->length},
                                   std::pair{"scale", &candidate->scale}, std::pair{"friction", &candidate->friction}})
  {
    if (node[field] && !readNumber(node[field], field, out).empty())
    {
      return who + " " + field + ": expected a number";
    }
  }
  if (node["frame"] && !readText(node["frame"], "frame", &candidate->frame).empty())
  {
    return who + " frame: expected a string";
  }
  if (node["file"])
  {
    std::string file;
    if (!readText(node["file"], "file", &file).empty())
    {
      return who + " file: expected a string";
    }
    std::string error;
    candidate->file = reading.file ? reading.file(file, &error) : file;
    if (candidate->file.empty())
    {
      return who + " file: " + error;
    }
  }
  return "";
}

}  // namespace

std::string readObstacle(const YAML::Node& node, std::size_t index, const ObstacleReading& reading, ObstacleSpec* spec)
{
  const std::string entry_name = "obstacles[" + std::to_string(index) + "]";
  if (!node.IsMap())
  {
    return entry_name + ": expected a map (name, type, position, ...)";
  }
  ObstacleSpec candidate;
  if (!node["name"] || !readText(node["name"], "name", &candidate.name).empty())
  {
    return entry_name + " name: expected a non-empty string";
  }
  const std::string who = entry_name + " '" + candidate.name + "'";
  std::string error = checkKeys(node, who, reading.frames);
  if (!error.empty())
  {
    return error;
  }
  if (!node["type"] || !node["type"].IsScalar() || !parseShapeType(node["type"].Scalar(), &candidate.type))
  {
    return who + " type: expected sphere, box, cylinder, capsule, plane or mesh";
  }
  error = checkShapeFields(node, who, candidate.type);
  error = error.empty() ? readFields(node, who, reading, &candidate) : error;
  if (!error.empty())
  {
    return error;
  }
  const Status status = validate(candidate);  // the core's checks: each names the obstacle and the field
  if (!status.ok)
  {
    return entry_name + ": " + status.message;
  }
  // Within the coordinates a tether may have (Tether::kMaxCoordinate).
  if (candidate.position.cwiseAbs().maxCoeff() > Tether::kMaxCoordinate ||
      std::max({candidate.radius, candidate.length, candidate.size.maxCoeff(), candidate.scale}) >
          Tether::kMaxCoordinate)
  {
    return who + ": position, radius, length, size and scale must be within 1e6 (m)";
  }
  *spec = candidate;
  return "";
}

std::string readObstacles(const YAML::Node& node, const ObstacleReading& reading, std::vector<ObstacleSpec>* obstacles)
{
  if (!node.IsSequence())
  {
    return "obstacles: expected a list of maps (name, type, position, ...)";
  }
  std::vector<ObstacleSpec> read;
  std::string errors;
  const auto fail = [&errors](const std::string& message) { errors += (errors.empty() ? "" : "; ") + message; };
  for (std::size_t k = 0; k < node.size(); ++k)
  {
    ObstacleSpec spec;
    const std::string error = readObstacle(node[k], k, reading, &spec);
    if (!error.empty())
    {
      fail(error);
      continue;
    }
    read.push_back(spec);
  }
  if (errors.empty())
  {
    *obstacles = std::move(read);
  }
  return errors;
}

}  // namespace rov_tether::spec
