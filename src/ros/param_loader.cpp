#include "rov_tether/ros/param_loader.hpp"

#include <ros/console.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "rov_tether/core/status.hpp"
#include "rov_tether/ros/obstacle_config.hpp"
#include "rov_tether/ros/xmlrpc_yaml.hpp"
#include "rov_tether/spec/tether_reader.hpp"
#include "rov_tether/spec/vehicle_reader.hpp"
#include "rov_tether/spec/yaml_read.hpp"

namespace rov_tether::ros_layer
{
namespace
{

const std::vector<std::string>& nodeOptionNames()
{
  static const std::vector<std::string> names = {"world_frame",
                                                 "pose_source",
                                                 "rov_frame",
                                                 "attachment_offset",
                                                 "spool_frame",
                                                 "spool_position",
                                                 "physics_rate",
                                                 "interpolation_delay",
                                                 "state_rate",
                                                 "marker_rate",
                                                 "marker_line_width",
                                                 "tension_full_scale",
                                                 "stripe_segments",
                                                 "stale_pose_timeout",
                                                 "max_tension_warning",
                                                 "pose_topic",
                                                 "overload_policy",
                                                 "min_iterations",
                                                 "cpu_budget",
                                                 "max_lag",
                                                 "spool_outlet_frame",
                                                 "cable_end_frame",
                                                 "wrap_warning_turns",
                                                 "snag_ratio",
                                                 "world_frame_from_pose",
                                                 "max_pose_future",
                                                 "vehicle_model",
                                                 "vehicle_params",
                                                 "cmd_wrench_timeout",
                                                 "vehicle_start",
                                                 "spool_on",
                                                 "spool_outlet_offset",
                                                 "solver_residual_warning",
                                                 "param_files"};
  return names;
}

bool readNumber(const XmlRpc::XmlRpcValue& value, double* out)
{
  if (value.getType() == XmlRpc::XmlRpcValue::TypeDouble)
  {
    *out = static_cast<double>(const_cast<XmlRpc::XmlRpcValue&>(value));
    return true;
  }
  if (value.getType() == XmlRpc::XmlRpcValue::TypeInt)
  {
    *out = static_cast<int>(const_cast<XmlRpc::XmlRpcValue&>(value));
    return true;
  }
  return false;
}

/// Collects problems while reading options; each reader names its parameter.
class OptionReader
{
 public:
  explicit OptionReader(const XmlRpc::XmlRpcValue& dict) : dict_(dict) {}

  void text(const std::string& name, std::string* out)
  {
    if (!has(name))
    {
      return;
    }
    const auto& value = dict_[name];
    if (value.getType() != XmlRpc::XmlRpcValue::TypeString)
    {
      errors_.push_back(name + ": expected a string");
      return;
    }
    *out = static_cast<std::string>(const_cast<XmlRpc::XmlRpcValue&>(value));
  }

  void flag(const std::string& name, bool* out)
  {
    if (!has(name))
    {
      return;
    }
    const auto& value = dict_[name];
    if (value.getType() != XmlRpc::XmlRpcValue::TypeBoolean)
    {
      errors_.push_back(name + ": expected true or false");
      return;
    }
    *out = static_cast<bool>(const_cast<XmlRpc::XmlRpcValue&>(value));
  }

  void number(const std::string& name, double* out, double min, double max)
  {
    double v = 0.0;
    if (bounded(name, min, max, false, &v))
    {
      *out = v;
    }
  }

  /// A whole number in [min, max] (2 or 2.0; 2.7 is refused, not truncated).
  void integer(const std::string& name, int* out, int min, int max)
  {
    double v = 0.0;
    if (bounded(name, min, max, true, &v))
    {
      *out = static_cast<int>(v);
    }
  }

  /// A list of strings ("" entries kept).
  void textList(const std::string& name, std::vector<std::string>* out)
  {
    if (!has(name))
    {
      return;
    }
    const auto& value = dict_[name];
    bool ok = value.getType() == XmlRpc::XmlRpcValue::TypeArray;
    std::vector<std::string> read;
    for (int i = 0; ok && i < value.size(); ++i)
    {
      ok = value[i].getType() == XmlRpc::XmlRpcValue::TypeString;
      if (ok)
      {
        read.push_back(static_cast<std::string>(const_cast<XmlRpc::XmlRpcValue&>(value[i])));
      }
    }
    if (!ok)
    {
      errors_.push_back(name + ": expected a list of strings");
      return;
    }
    *out = read;
  }

  /// A number in (above, max].
  void numberAbove(const std::string& name, double* out, double above, double max)
  {
    if (!has(name))
    {
      return;
    }
    double v = 0.0;
    if (!readNumber(dict_[name], &v) || !std::isfinite(v) || !(v > above) || v > max)
    {
      std::ostringstream message;
      message << name << ": expected a number in (" << above << ", " << max << "]";
      errors_.push_back(message.str());
      return;
    }
    *out = v;
  }

  void vector3(const std::string& name, Eigen::Vector3d* out)
  {
    if (!has(name))
    {
      return;
    }
    const auto& value = dict_[name];
    Eigen::Vector3d v;
    bool ok = value.getType() == XmlRpc::XmlRpcValue::TypeArray && value.size() == 3;
    for (int i = 0; ok && i < 3; ++i)
    {
      ok = readNumber(value[i], &v[i]) && std::isfinite(v[i]);
    }
    if (!ok)
    {
      errors_.push_back(name + ": expected [x, y, z] in m");
      return;
    }
    *out = v;
  }

  /// [x, y, z, yaw]: four finite numbers [m, m, m, rad]; `given` says whether it was there.
  void pose4(const std::string& name, Eigen::Vector4d* out, bool* given)
  {
    if (!has(name))
    {
      return;
    }
    const auto& value = dict_[name];
    Eigen::Vector4d v;
    bool ok = value.getType() == XmlRpc::XmlRpcValue::TypeArray && value.size() == 4;
    for (int i = 0; ok && i < 4; ++i)
    {
      ok = readNumber(value[i], &v[i]) && std::isfinite(v[i]);
    }
    if (!ok)
    {
      errors_.push_back(name + ": expected [x, y, z, yaw] in m and rad (four finite numbers)");
      return;
    }
    *out = v;
    *given = true;
  }

  void fail(const std::string& message) { errors_.push_back(message); }

  std::string result() const { return joinMessages(errors_); }

 private:
  /// Option `name`, when given, into v if it is a finite number in [min, max] (and `whole`, a whole one); false
  /// when it is not given, or (the error kept) not such a number.
  bool bounded(const std::string& name, double min, double max, bool whole, double* v)
  {
    if (!has(name))
    {
      return false;
    }
    if (!readNumber(dict_[name], v) || !std::isfinite(*v) || (whole && *v != std::floor(*v)) || *v < min || *v > max)
    {
      std::ostringstream message;
      message << name << ": expected a " << (whole ? "whole " : "") << "number in [" << min << ", " << max << "]";
      errors_.push_back(message.str());
      return false;
    }
    return true;
  }

  bool has(const std::string& name) const
  {
    return dict_.getType() == XmlRpc::XmlRpcValue::TypeStruct && dict_.hasMember(name);
  }

  const XmlRpc::XmlRpcValue& dict_;
  std::vector<std::string> errors_;
};

}  // namespace

std::string loadTetherParams(const XmlRpc::XmlRpcValue& dict, TetherParams* params)
{
  if (dict.getType() != XmlRpc::XmlRpcValue::TypeStruct)
  {
    return "parameters: expected a map of name: value";
  }
  // The one reader of model parameters (spec::readTetherParams, as the scenario runner's); the namespace's
  // other keys are node options and the world's (loadNodeOptions, unknownParameters).
  std::vector<std::string> warnings;
  const std::string error = spec::readTetherParams(toYaml(dict), "", spec::ParamKeys::kModelOnly, params, &warnings);
  for (const auto& warning : warnings)
  {
    ROS_WARN("tether_node: %s", warning.c_str());
  }
  return error;
}

std::string loadNodeOptions(const XmlRpc::XmlRpcValue& dict, NodeOptions* options)
{
  NodeOptions candidate = *options;
  OptionReader read(dict);
  read.text("world_frame", &candidate.world_frame);
  read.flag("world_frame_from_pose", &candidate.world_frame_from_pose);
  read.text("pose_source", &candidate.pose_source);
  read.text("rov_frame", &candidate.rov_frame);
  read.vector3("attachment_offset", &candidate.attachment_offset);
  read.text("spool_frame", &candidate.spool_frame);
  read.vector3("spool_position", &candidate.spool_position);
  read.text("spool_on", &candidate.spool_on);
  read.vector3("spool_outlet_offset", &candidate.spool_outlet_offset);
  read.number("physics_rate", &candidate.physics_rate, 1.0, 5000.0);
  read.number("interpolation_delay", &candidate.interpolation_delay, 0.0, 10.0);
  read.number("state_rate", &candidate.state_rate, 0.1, 1000.0);
  read.number("marker_rate", &candidate.marker_rate, 0.1, 1000.0);
  read.number("marker_line_width", &candidate.marker_line_width, 1e-4, 10.0);
  read.number("tension_full_scale", &candidate.tension_full_scale, 1e-6, 1e9);
  read.integer("stripe_segments", &candidate.stripe_segments, 1, 1000);
  read.number("stale_pose_timeout", &candidate.stale_pose_timeout, 0.01, 3600.0);
  read.number("max_pose_future", &candidate.max_pose_future, 0.0, 3600.0);
  read.number("max_tension_warning", &candidate.max_tension_warning, 0.0, 1e9);
  read.number("solver_residual_warning", &candidate.solver_residual_warning, 0.0, 1.0);
  read.text("pose_topic", &candidate.pose_topic);
  read.text("overload_policy", &candidate.overload_policy);
  read.integer("min_iterations", &candidate.min_iterations, 1, 1000);
  read.number("cpu_budget", &candidate.cpu_budget, 0.01, 1.0);
  read.number("max_lag", &candidate.max_lag, 0.01, 3600.0);
  read.text("spool_outlet_frame", &candidate.spool_outlet_frame);
  read.text("cable_end_frame", &candidate.cable_end_frame);
  read.numberAbove("wrap_warning_turns", &candidate.wrap_warning_turns, 0.0, 1e6);
  read.numberAbove("snag_ratio", &candidate.snag_ratio, 1.0, 1e9);  // a capstan ratio is at least 1
  read.text("vehicle_model", &candidate.vehicle_model);
  read.text("vehicle_params", &candidate.vehicle_params);
  read.numberAbove("cmd_wrench_timeout", &candidate.cmd_wrench_timeout, 0.0, 3600.0);
  read.pose4("vehicle_start", &candidate.vehicle_start, &candidate.has_vehicle_start);
  if (candidate.vehicle_model != "kinematic" && candidate.vehicle_model != "dynamic")
  {
    read.fail("vehicle_model = '" + candidate.vehicle_model + "': expected kinematic or dynamic");
  }
  if (candidate.overload_policy != "reduce_iterations" && candidate.overload_policy != "reduce_markers" &&
      candidate.overload_policy != "none")
  {
    read.fail("overload_policy = '" + candidate.overload_policy +
              "': expected reduce_iterations, reduce_markers or none");
  }
  if (candidate.pose_topic.empty())
  {
    read.fail("pose_topic: must not be empty");
  }
  if (candidate.pose_source != "topic" && candidate.pose_source != "tf")
  {
    read.fail("pose_source = '" + candidate.pose_source + "': expected topic or tf");
  }
  if (candidate.world_frame.empty())
  {
    read.fail("world_frame: must not be empty");
  }
  read.textList("param_files", &candidate.param_files);  // checked by checkParamFiles
  if (candidate.pose_source == "tf" && candidate.rov_frame.empty())
  {
    read.fail("rov_frame: must not be empty when pose_source is tf");
  }
  const std::string errors = read.result();
  if (errors.empty())
  {
    *options = candidate;
  }
  return errors;
}

std::string checkParamFiles(const std::vector<std::string>& files)
{
  for (const std::string& file : files)
  {
    if (file.empty())
    {
      continue;  // an optional file not given
    }
    // roslaunch read a relative path from the directory it was started in, which it passes on to its nodes as
    // PWD (the node itself runs in ROS_HOME).
    const char* started_in = std::getenv("PWD");
    const std::filesystem::path path = std::filesystem::path(file).is_relative() && started_in != nullptr
                                           ? std::filesystem::path(started_in) / file
                                           : std::filesystem::path(file);
    if (!std::ifstream(path).good())
    {
      // roslaunch has read it (from another machine's disk, say): the node cannot check it, and says so.
      ROS_WARN("tether_node: param_files: cannot read '%s' again to check it for a key given twice",
               path.string().c_str());
      continue;
    }
    const std::string problem = spec::checkYamlFile(path.string());
    if (!problem.empty())
    {
      return "param_files: " + problem;
    }
  }
  return "";
}

std::string unknownParameters(const XmlRpc::XmlRpcValue& dict)
{
  if (dict.getType() != XmlRpc::XmlRpcValue::TypeStruct)
  {
    return "";
  }
  std::string unknown;
  for (const auto& entry : const_cast<XmlRpc::XmlRpcValue&>(dict))
  {
    const std::string& name = entry.first;
    const auto& model = parameterNames();
    const auto& node = nodeOptionNames();
    bool tether_name = false;  // a map named in `tethers`
    if (dict.hasMember("tethers") && dict["tethers"].getType() == XmlRpc::XmlRpcValue::TypeArray)
    {
      auto& list = const_cast<XmlRpc::XmlRpcValue&>(dict)["tethers"];
      for (int i = 0; i < list.size(); ++i)
      {
        tether_name = tether_name || (list[i].getType() == XmlRpc::XmlRpcValue::TypeString &&
                                      static_cast<std::string>(list[i]) == name);
      }
    }
    const bool known = std::find(model.begin(), model.end(), name) != model.end() ||
                       std::find(node.begin(), node.end(), name) != node.end() || name == "tethers" ||
                       name == "cameras" || name == "obstacles" || name == "tether_contact" || name == "sections" ||
                       name == "attachments" || tether_name;
    if (!known && entry.second.getType() == XmlRpc::XmlRpcValue::TypeStruct)
    {
      // A tether's map that `tethers` does not name (a typo in either, or one left out): no tether is made of it.
      unknown += (unknown.empty() ? "" : ", ") + name + " (a map of parameters that `tethers` does not list: " +
                 (dict.hasMember("tethers") ? "add it there" : "there is no `tethers` list") +
                 " to simulate it as a tether)";
    }
    else if (!known)
    {
      std::vector<std::string> names = model;
      names.insert(names.end(), node.begin(), node.end());
      const std::string guess = closestName(name, names);
      unknown += (unknown.empty() ? "" : ", ") + name + (guess.empty() ? "" : " (did you mean " + guess + "?)");
    }
  }
  return unknown;
}

std::string checkVehicleModel(const TetherSetup& setup)
{
  if (setup.options.vehicle_model != "dynamic")
  {
    return "";
  }
  if (setup.params.solver != SolverType::kDirect)
  {
    return "vehicle_model dynamic: needs solver direct (solver is '" + toString(setup.params.solver) +
           "'): only direct couples a vehicle into its step";
  }
  if (setup.options.pose_source != "topic")
  {
    return "vehicle_model dynamic: needs pose_source topic (pose_source is '" + setup.options.pose_source +
           "'): the node publishes " + setup.options.world_frame + " -> " + setup.options.rov_frame +
           " on tf itself and would read its own vehicle back as its input; give poses (setpoints) on pose_topic";
  }
  return "";
}

std::string loadTetherSetup(const XmlRpc::XmlRpcValue& shared, const XmlRpc::XmlRpcValue& own, TetherSetup* setup)
{
  TetherSetup candidate = *setup;
  std::string error;
  for (const XmlRpc::XmlRpcValue* source : {&shared, &own})  // shared first, this tether's own on top
  {
    if (error.empty() && source->valid())
    {
      error = loadTetherParams(*source, &candidate.params);
      error = error.empty() ? loadNodeOptions(*source, &candidate.options) : error;
    }
  }
  error = error.empty() ? checkVehicleModel(candidate) : error;
  if (error.empty() && !candidate.options.vehicle_params.empty())
  {
    std::string why;
    const std::string path = resolveMeshFile(candidate.options.vehicle_params, &why);
    const std::string read =
        path.empty() ? why : spec::loadVehicleParamsFile(path, &candidate.vehicle, &candidate.gains);
    error = read.empty() ? "" : "vehicle_params: " + read;
  }
  if (error.empty())
  {
    candidate.ignored.clear();
    if (candidate.options.has_vehicle_start && candidate.options.vehicle_model != "dynamic")
    {
      const Eigen::Vector4d& start = candidate.options.vehicle_start;
      std::ostringstream out;
      out << "vehicle_start [" << start[0] << ", " << start[1] << ", " << start[2] << ", " << start[3]
          << "] is ignored: vehicle_model is " << candidate.options.vehicle_model
          << ", so the vehicle end is where its poses put it (the first attaches it); vehicle_start places a "
             "dynamic vehicle (vehicle_model: dynamic)";
      candidate.ignored.push_back(out.str());
    }
    *setup = candidate;
  }
  return error;
}

}  // namespace rov_tether::ros_layer
