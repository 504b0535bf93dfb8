#include "vehicle_yaml.hpp"

#include <cmath>
#include <filesystem>

#include "rov_tether/spec/vehicle_reader.hpp"
#include "rov_tether/spec/yaml_read.hpp"

namespace rov_tether::scenario_yaml
{
namespace
{

using spec::readVector;

constexpr const char* kDynamicKeys = "model, params, start, attachment_offset, path, wrench, controller";

bool withinReach(double value) { return std::abs(value) <= Tether::kMaxCoordinate; }

/// A thrust schedule of [t, Fx, Fy, Fz, Mx, My, Mz] rows, times >= 0 and never going back.
std::string readWrenchSchedule(const YAML::Node& node, const std::string& field, std::vector<WrenchPoint>* schedule)
{
  if (!node.IsSequence() || node.size() == 0)
  {
    return field + ": expected a non-empty list of [t, Fx, Fy, Fz, Mx, My, Mz] rows (body frame, N and N m)";
  }
  for (std::size_t k = 0; k < node.size(); ++k)
  {
    double values[7];
    const std::string row = field + "[" + std::to_string(k) + "]";
    const std::string error = readVector(node[k], row, 7, values);
    if (!error.empty())
    {
      return error;
    }
    if (values[0] < 0.0)
    {
      return row + ": time " + std::to_string(values[0]) + " s must be >= 0";
    }
    if (!schedule->empty() && values[0] < schedule->back().time)
    {
      return row + ": time " + std::to_string(values[0]) + " s is before the previous row's";
    }
    Wrench wrench;
    wrench << values[1], values[2], values[3], values[4], values[5], values[6];
    schedule->push_back({values[0], wrench});
  }
  return "";
}

/// `params`: a vehicle file (a string, relative to base_dir) or a map; the gains of its `controller:` block, or
/// the default design for it.
std::string readBodyParams(const YAML::Node& node, const std::string& field, const std::string& base_dir,
                           DynamicVehicle* vehicle)
{
  if (node.IsMap())
  {
    return spec::readVehicleParams(node, field, &vehicle->params, &vehicle->controller);
  }
  std::string file;
  if (!spec::readText(node, field, &file).empty())
  {
    return field +
           ": expected a vehicle file (a path, relative to the scenario file's directory) or a map of "
           "the vehicle's parameters";
  }
  const std::filesystem::path path(file);
  const std::string resolved =
      path.is_absolute() || base_dir.empty() ? file : (std::filesystem::path(base_dir) / path).string();
  const std::string error = spec::loadVehicleParamsFile(resolved, &vehicle->params, &vehicle->controller);
  return error.empty() ? "" : field + ": " + error;
}

/// `start: [x, y, z, yaw]` [m, rad].
std::string readStart(const YAML::Node& node, const std::string& field, DynamicVehicle* vehicle)
{
  double values[4];
  const std::string error = readVector(node, field, 4, values);
  if (!error.empty())
  {
    return error + " ([x, y, z, yaw] in m and rad)";
  }
  if (!withinReach(values[0]) || !withinReach(values[1]) || !withinReach(values[2]))
  {
    return field + ": each coordinate must be within +-1e6 m";
  }
  vehicle->start = Position(values[0], values[1], values[2]);
  vehicle->start_yaw = values[3];
  return "";
}

/// The keys of a dynamic vehicle's block, each read into `vehicle` or `path`.
std::string readDynamic(const YAML::Node& node, const std::string& field, const std::string& base_dir,
                        std::vector<Waypoint>* path, DynamicVehicle* vehicle)
{
  if (!node["params"])
  {
    return field + ".params: missing (a vehicle file such as config/vehicles/bluerov2_heavy.yaml, or a map)";
  }
  const bool has_path = static_cast<bool>(node["path"]);
  const bool has_wrench = static_cast<bool>(node["wrench"]);
  if (has_path == has_wrench)
  {
    return field + ": give either path (the controller's setpoints) or wrench (a thrust schedule, no controller)" +
           (has_path ? ", not both" : "");
  }
  std::string error = readBodyParams(node["params"], field + ".params", base_dir, vehicle);
  if (error.empty() && has_path)
  {
    error = readPath(node["path"], field + ".path", path);
  }
  if (error.empty() && has_wrench)
  {
    error = readWrenchSchedule(node["wrench"], field + ".wrench", &vehicle->wrench);
  }
  if (error.empty() && node["controller"])
  {
    error = has_wrench ? field + ".controller: no controller runs under a wrench schedule"
                       : spec::readControllerGains(node["controller"], field, vehicle->params, &vehicle->controller);
  }
  if (error.empty() && node["attachment_offset"])
  {
    error = readVector(node["attachment_offset"], field + ".attachment_offset", 3, vehicle->attachment_offset.data());
    if (error.empty() && vehicle->attachment_offset.norm() > VehicleParams::kMaxOffset)
    {
      error = field + ".attachment_offset: must be within 100 m of the body origin";
    }
  }
  if (!error.empty())
  {
    return error;
  }
  if (node["start"])
  {
    return readStart(node["start"], field + ".start", vehicle);
  }
  if (!has_path)
  {
    return field + ".start: missing (with a wrench schedule there is no path to start from)";
  }
  vehicle->start = path->front().position;  // heading 0
  return "";
}

}  // namespace

std::string readPath(const YAML::Node& path, const std::string& field, std::vector<Waypoint>* vehicle)
{
  if (!path.IsSequence() || path.size() == 0)
  {
    return field + ": expected a non-empty list of [t, x, y, z] waypoints (omit it for a free end)";
  }
  for (std::size_t k = 0; k < path.size(); ++k)
  {
    double values[4];
    const std::string point = field + "[" + std::to_string(k) + "]";
    const std::string error = readVector(path[k], point, 4, values);
    if (!error.empty())
    {
      return error;
    }
    if (values[0] < 0.0)
    {
      return point + ": time " + std::to_string(values[0]) + " s must be >= 0";
    }
    if (!vehicle->empty() && values[0] < vehicle->back().time)
    {
      return point + ": time " + std::to_string(values[0]) + " s is before the previous waypoint's";
    }
    if (!withinReach(values[1]) || !withinReach(values[2]) || !withinReach(values[3]))
    {
      return point + ": each coordinate must be within +-1e6 m";
    }
    vehicle->push_back({values[0], Position(values[1], values[2], values[3])});
  }
  return "";
}

std::string readVehicle(const YAML::Node& node, const std::string& field, const std::string& base_dir,
                        std::vector<Waypoint>* path, std::optional<DynamicVehicle>* dynamic)
{
  if (node.IsSequence())
  {
    return readPath(node, field, path);
  }
  if (!node.IsMap())
  {
    return field + ": expected a list of [t, x, y, z] waypoints or a map {" + kDynamicKeys + "}";
  }
  for (const auto& entry : node)
  {
    const std::string key = entry.first.Scalar();
    if (key != "model" && key != "params" && key != "start" && key != "attachment_offset" && key != "path" &&
        key != "wrench" && key != "controller")
    {
      return field + ": unknown field '" + key + "' (expected " + kDynamicKeys + ")";
    }
  }
  std::string model;
  if (!node["model"] || !spec::readText(node["model"], field + ".model", &model).empty() ||
      (model != "kinematic" && model != "dynamic"))
  {
    return field + ".model: expected kinematic or dynamic" + (model.empty() ? "" : " (got '" + model + "')");
  }
  std::vector<Waypoint> read_path;
  if (model == "kinematic")
  {
    for (const char* only_dynamic : {"params", "start", "attachment_offset", "wrench", "controller"})
    {
      if (node[only_dynamic])
      {
        return field + "." + only_dynamic + ": only with model: dynamic (a kinematic vehicle follows its path)";
      }
    }
    if (!node["path"])
    {
      return field + ".path: missing (a kinematic vehicle follows a path; omit `vehicle` for a free end)";
    }
    const std::string error = readPath(node["path"], field + ".path", &read_path);
    if (error.empty())
    {
      *path = read_path;
      dynamic->reset();
    }
    return error;
  }
  DynamicVehicle vehicle;
  const std::string error = readDynamic(node, field, base_dir, &read_path, &vehicle);
  if (error.empty())
  {
    *path = read_path;
    *dynamic = vehicle;
  }
  return error;
}

}  // namespace rov_tether::scenario_yaml
