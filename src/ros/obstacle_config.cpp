#include "rov_tether/ros/obstacle_config.hpp"

#include <ros/names.h>
#include <ros/package.h>

#include <algorithm>

#include "rov_tether/ros/xmlrpc_yaml.hpp"
#include "rov_tether/spec/obstacle_reader.hpp"

namespace rov_tether::ros_layer
{

WorldSpec namesOnly(const std::vector<std::string>& tether_names, const std::vector<ObstacleSpec>& obstacles,
                    const std::vector<spec::CameraSpec>& cameras)
{
  WorldSpec spec;
  for (const std::string& name : tether_names)
  {
    ScenarioTether tether;
    tether.name = name;
    spec.tethers.push_back(tether);
  }
  spec.obstacles = obstacles;
  spec.cameras = cameras;
  return spec;
}

std::string loadWorldOptions(const XmlRpc::XmlRpcValue& dict, WorldOptions* options,
                             const std::vector<std::string>& tether_names)
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
    // The one reader of obstacles (spec::readObstacles, as the scenario runner's): a mesh file stays as
    // written (a path or a URI: resolveMeshFile when it is built, meshResourceUri for rviz).
    spec::ObstacleReading reading;
    reading.frames = true;
    std::string error = spec::readObstacles(toYaml(map["obstacles"]), reading, &candidate.obstacles);
    error = error.empty() ? validateWorldSpec(namesOnly(tether_names, candidate.obstacles, {})) : error;
    if (!error.empty())
    {
      fail(error);
    }
  }
  if (errors.empty())
  {
    *options = candidate;
  }
  return errors;
}

std::string nodeWorldSpec(const std::vector<std::string>& names, const std::vector<TetherSetup>& setups,
                          const WorldOptions& options, WorldSpec* spec)
{
  WorldSpec result;
  for (std::size_t i = 0; i < setups.size() && i < names.size(); ++i)
  {
    ScenarioTether tether;
    tether.name = names[i];
    tether.params = setups[i].params;
    tether.spool = setups[i].options.spool_position;
    const NodeOptions& options = setups[i].options;
    tether.spool_moves = !options.spool_frame.empty();
    const auto carrier = std::find(names.begin(), names.end(), options.spool_on);
    if (!options.spool_on.empty() && carrier != names.end())
    {
      // Where the spool starts: the outlet of the carrier's vehicle at vehicle_start (checkSpoolMounts: it has one).
      const Eigen::Vector4d& start = setups[static_cast<std::size_t>(carrier - names.begin())].options.vehicle_start;
      tether.spool_on = options.spool_on;
      tether.spool_outlet_offset = options.spool_outlet_offset;
      tether.spool =
          start.head<3>() + Eigen::AngleAxisd(start[3], Eigen::Vector3d::UnitZ()) * options.spool_outlet_offset;
    }
    result.tethers.push_back(tether);
  }
  result.vehicles_attached_later = true;  // the node's VehicleIo starts each; WorldNode mounts the spools then
  result.tether_contact = options.tether_contact;
  for (ObstacleSpec obstacle : options.obstacles)
  {
    if (obstacle.type == ShapeType::Mesh)
    {
      std::string error;
      obstacle.file = resolveMeshFile(obstacle.file, &error);
      if (obstacle.file.empty())
      {
        return "obstacle '" + obstacle.name + "' file: " + error;
      }
    }
    result.obstacles.push_back(obstacle);
  }
  *spec = result;
  return "";
}

std::string checkNodeTetherName(const std::string& name)
{
  if (!isTetherName(name))
  {
    return "'" + name + "': expected " + kTetherNameRule;
  }
  std::string error;
  if (!ros::names::validate(name, error))
  {
    return "'" + name + "': not a ROS name (" + error + "): a letter first, then letters, digits or '_'";
  }
  return "";
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
