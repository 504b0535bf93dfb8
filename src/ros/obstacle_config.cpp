#include "rov_tether/ros/obstacle_config.hpp"

#include <ros/package.h>

#include <algorithm>
#include <iterator>
#include <set>
#include <tuple>
#include <utility>

namespace rov_tether::ros_layer
{
namespace
{

const char* const kObstacleFields[] = {"name", "type", "position", "orientation", "radius", "length",
                                       "size", "file", "scale",    "friction",    "frame"};

bool readNumber(const XmlRpc::XmlRpcValue& value, double* out)
{
  auto& v = const_cast<XmlRpc::XmlRpcValue&>(value);
  if (value.getType() == XmlRpc::XmlRpcValue::TypeDouble)
  {
    *out = static_cast<double>(v);
    return true;
  }
  if (value.getType() == XmlRpc::XmlRpcValue::TypeInt)
  {
    *out = static_cast<int>(v);
    return true;
  }
  return false;
}

bool readVector3(const XmlRpc::XmlRpcValue& value, Eigen::Vector3d* out)
{
  if (value.getType() != XmlRpc::XmlRpcValue::TypeArray || value.size() != 3)
  {
    return false;
  }
  for (int i = 0; i < 3; ++i)
  {
    if (!readNumber(value[i], &(*out)[i]))
    {
      return false;
    }
  }
  return true;
}

bool readText(const XmlRpc::XmlRpcValue& value, std::string* out)
{
  if (value.getType() != XmlRpc::XmlRpcValue::TypeString)
  {
    return false;
  }
  *out = static_cast<std::string>(const_cast<XmlRpc::XmlRpcValue&>(value));
  return true;
}

}  // namespace

std::string loadObstacleSpec(const XmlRpc::XmlRpcValue& entry, int index, ObstacleSpec* spec)
{
  const std::string entry_name = "obstacles[" + std::to_string(index) + "]";
  if (entry.getType() != XmlRpc::XmlRpcValue::TypeStruct)
  {
    return entry_name + ": expected a map (name, type, position, ...)";
  }
  auto& dict = const_cast<XmlRpc::XmlRpcValue&>(entry);
  ObstacleSpec candidate;
  std::string who = entry_name;
  if (!dict.hasMember("name") || !readText(dict["name"], &candidate.name) || candidate.name.empty())
  {
    return entry_name + " name: expected a non-empty string";
  }
  who = entry_name + " '" + candidate.name + "'";
  for (const auto& member : dict)
  {
    if (std::find(std::begin(kObstacleFields), std::end(kObstacleFields), member.first) == std::end(kObstacleFields))
    {
      return who + ": unknown field '" + member.first +
             "' (expected name, type, position, orientation, radius, length, size, file, scale, friction, frame)";
    }
  }
  std::string type;
  if (!dict.hasMember("type") || !readText(dict["type"], &type) || !parseShapeType(type, &candidate.type))
  {
    return who + " type: expected sphere, box, cylinder, capsule, plane or mesh";
  }
  for (const auto& [field, out, unit] : {std::tuple{"position", &candidate.position, "[x, y, z] in m"},
                                         std::tuple{"orientation", &candidate.orientation, "[roll, pitch, yaw] in rad"},
                                         std::tuple{"size", &candidate.size, "[x, y, z] in m"}})
  {
    if (dict.hasMember(field) && !readVector3(dict[field], out))
    {
      return who + " " + field + ": expected " + unit;
    }
  }
  for (const auto& [field, out] : {std::pair{"radius", &candidate.radius}, std::pair{"length", &candidate.length},
                                   std::pair{"scale", &candidate.scale}, std::pair{"friction", &candidate.friction}})
  {
    if (dict.hasMember(field) && !readNumber(dict[field], out))
    {
      return who + " " + field + ": expected a number";
    }
  }
  for (const auto& [field, out] : {std::pair{"file", &candidate.file}, std::pair{"frame", &candidate.frame}})
  {
    if (dict.hasMember(field) && !readText(dict[field], out))
    {
      return who + " " + field + ": expected a string";
    }
  }
  const Status status = validate(candidate);  // the core's checks: each names the obstacle and the field
  if (!status.ok)
  {
    return entry_name + ": " + status.message;
  }
  *spec = candidate;
  return "";
}

std::string loadWorldOptions(const XmlRpc::XmlRpcValue& dict, WorldOptions* options)
{
  if (dict.getType() != XmlRpc::XmlRpcValue::TypeStruct)
  {
    return "";
  }
  auto& map = const_cast<XmlRpc::XmlRpcValue&>(dict);
  WorldOptions candidate = *options;
  std::string errors;
  const auto fail = [&errors](const std::string& message) { errors += (errors.empty() ? "" : "; ") + message; };
  if (map.hasMember("tether_contact"))
  {
    if (map["tether_contact"].getType() != XmlRpc::XmlRpcValue::TypeBoolean)
    {
      fail("tether_contact: expected true or false");
    }
    else
    {
      candidate.tether_contact = static_cast<bool>(map["tether_contact"]);
    }
  }
  if (map.hasMember("obstacles"))
  {
    const XmlRpc::XmlRpcValue& list = map["obstacles"];
    candidate.obstacles.clear();
    if (list.getType() != XmlRpc::XmlRpcValue::TypeArray)
    {
      fail("obstacles: expected a list of maps (name, type, position, ...)");
    }
    std::set<std::string> names;
    for (int i = 0; list.getType() == XmlRpc::XmlRpcValue::TypeArray && i < list.size(); ++i)
    {
      ObstacleSpec spec;
      const std::string error = loadObstacleSpec(list[i], i, &spec);
      if (!error.empty())
      {
        fail(error);
        continue;
      }
      if (!names.insert(spec.name).second)
      {
        fail("obstacles[" + std::to_string(i) + "] '" + spec.name + "' name: taken by an earlier obstacle");
        continue;
      }
      candidate.obstacles.push_back(spec);
    }
  }
  if (errors.empty())
  {
    *options = candidate;
  }
  return errors;
}

std::string resolveMeshFile(const std::string& file, std::string* error)
{
  const std::string package_scheme = "package://", file_scheme = "file://";
  if (file.rfind(package_scheme, 0) == 0)
  {
    const std::string rest = file.substr(package_scheme.size());
    const std::size_t slash = rest.find('/');
    const std::string package = rest.substr(0, slash);
    const std::string directory = package.empty() ? "" : ros::package::getPath(package);
    if (directory.empty() || slash == std::string::npos)
    {
      *error = "'" + file + "': no package '" + package + "' found (ROS_PACKAGE_PATH)";
      return "";
    }
    return directory + rest.substr(slash);
  }
  const std::string path = file.rfind(file_scheme, 0) == 0 ? file.substr(file_scheme.size()) : file;
  if (path.empty() || path.front() != '/')
  {
    *error = "'" + file + "': expected an absolute path, file:///path or package://package/path";
    return "";
  }
  return path;
}

std::string meshResourceUri(const std::string& file)
{
  if (file.rfind("package://", 0) == 0 || file.rfind("file://", 0) == 0)
  {
    return file;
  }
  return "file://" + file;
}

}  // namespace rov_tether::ros_layer
