#include "rov_tether/spec/camera_reader.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "rov_tether/core/status.hpp"
#include "rov_tether/spec/yaml_read.hpp"

namespace rov_tether::spec
{
namespace
{

const std::vector<std::string> kTfFrameFields = {"name", "frame", "info_topic",  "width", "height",
                                                 "K",    "D",     "image_topic", "rate"};
const std::vector<std::string> kVehicleFields = {"name",  "position", "orientation", "rate",
                                                 "width", "height",   "K",           "D"};

/// A number as a user wrote it (64.5, 0, 1e+06), not std::to_string's fixed six decimals.
std::string shown(double value)
{
  std::ostringstream text;
  text << value;
  return text.str();
}

/// The naming rule of both paths: a ROS name (the node publishes under ~<name>/) and a directory name
/// (the runner writes cameras/<name>/).
bool isCameraName(const std::string& name)
{
  return !name.empty() && name.size() <= 64 &&
         name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") ==
             std::string::npos &&
         !std::isdigit(static_cast<unsigned char>(name[0]));
}

/// The fixed width, height, K and D, each required but D; "" or the first problem.
std::string readIntrinsics(const YAML::Node& node, const std::string& field, camera::CameraIntrinsics* intrinsics)
{
  std::string error;
  for (const char* key : {"width", "height"})
  {
    if (!node[key])
    {
      return field + "." + key + ": missing (a whole number of pixels)";
    }
    double size = 0.0;
    if (!(error = readNumber(node[key], field + "." + key, &size)).empty())
    {
      return error;
    }
    if (size != std::floor(size) || size < 1 || size > camera::CameraIntrinsics::kMaxSide)
    {
      return field + "." + key + " = " + shown(size) +
             ": must be a whole number in [1, 16384] px (and width x height at most 4096 x 4096)";
    }
    (std::string(key) == "width" ? intrinsics->width : intrinsics->height) = static_cast<int>(size);
  }
  if (!node["K"])
  {
    return field + ".K: missing (fx, 0, cx, 0, fy, cy, 0, 0, 1)";
  }
  if (!(error = readVector(node["K"], field + ".K", 9, intrinsics->K.data())).empty())
  {
    return error;
  }
  if (node["D"])
  {
    const YAML::Node d = node["D"];
    if (!d.IsSequence() || (d.size() != 0 && d.size() != 4 && d.size() != 5))
    {
      return field + ".D: expected a list of 5 plumb_bob coefficients (k1, k2, p1, p2, k3), or 4, or none";
    }
    intrinsics->D.resize(d.size());
    if (d.size() > 0 && !(error = readVector(d, field + ".D", d.size(), intrinsics->D.data())).empty())
    {
      return error;
    }
  }
  const auto errors = intrinsics->validate(field + ".");
  return errors.empty() ? "" : errors.front();
}

/// A tf-frame camera's frame and topics, and the choice of intrinsics and timing; "" or the first problem.
std::string readTfFrameFields(const YAML::Node& node, const std::string& field, CameraSpec* camera, bool* fixed)
{
  for (const auto& [key, out] : {std::pair{"frame", &camera->frame}, std::pair{"info_topic", &camera->info_topic},
                                 std::pair{"image_topic", &camera->image_topic}})
  {
    if (node[key])
    {
      const std::string error = readText(node[key], field + "." + key, out);
      if (!error.empty())
      {
        return error;
      }
    }
  }
  if (camera->frame.empty())
  {
    return field + ".frame: missing (the camera's tf optical frame)";
  }
  *fixed = node["width"] || node["height"] || node["K"] || node["D"];
  if (camera->info_topic.empty() == !*fixed)
  {
    return field + ": give either info_topic or the fixed intrinsics width, height, K (and D)";
  }
  if (node["rate"] && !camera->image_topic.empty())
  {
    return field + ": give either image_topic or rate";
  }
  return "";
}

/// A vehicle camera's position and orientation; "" or the first problem.
std::string readVehicleFields(const YAML::Node& node, const std::string& field, CameraSpec* camera)
{
  for (const auto& [key, out] :
       {std::pair{"position", &camera->position}, std::pair{"orientation", &camera->orientation}})
  {
    if (node[key])
    {
      const std::string error = readVector(node[key], field + "." + key, 3, out->data());
      if (!error.empty())
      {
        return error;
      }
    }
  }
  if (camera->position.cwiseAbs().maxCoeff() > kMaxCameraOffset)
  {
    return field + ".position = [" + shown(camera->position.x()) + ", " + shown(camera->position.y()) + ", " +
           shown(camera->position.z()) + "]: must be within +-100 m of the vehicle";
  }
  if (camera->orientation.cwiseAbs().maxCoeff() > kMaxCameraAngle)
  {
    return field + ".orientation = [" + shown(camera->orientation.x()) + ", " + shown(camera->orientation.y()) + ", " +
           shown(camera->orientation.z()) + "]: each angle must be within +-360 deg";
  }
  return "";
}

/// Reads one entry; "" or the first problem, naming `field` (cameras[k]).
std::string readCamera(const YAML::Node& node, const std::string& field, CameraMount mount, CameraSpec* camera)
{
  const std::vector<std::string>& fields = mount == CameraMount::kTfFrame ? kTfFrameFields : kVehicleFields;
  if (!node.IsMap())
  {
    return field + ": expected a map with " + joinMessages(fields, ", ");
  }
  for (const auto& entry : node)
  {
    const std::string key = entry.first.as<std::string>();
    if (std::find(fields.begin(), fields.end(), key) == fields.end())
    {
      return field + ": unknown field '" + key + "' (expected " + joinMessages(fields, ", ") + ")";
    }
  }
  if (!node["name"])
  {
    return field + ".name: missing";
  }
  std::string error = readText(node["name"], field + ".name", &camera->name);
  if (!error.empty() || !isCameraName(camera->name))
  {
    const std::string value = node["name"].IsScalar() ? node["name"].Scalar() : "";
    return field + ".name = '" + value +
           "': expected 1-64 letters, digits or '_', not a digit first (a ROS name and a directory name)";
  }
  bool fixed = true;
  error = mount == CameraMount::kTfFrame ? readTfFrameFields(node, field, camera, &fixed)
                                         : readVehicleFields(node, field, camera);
  if (!error.empty())
  {
    return error;
  }
  if (node["rate"])
  {
    if (!(error = readNumber(node["rate"], field + ".rate", &camera->rate)).empty())
    {
      return error;
    }
    if (!(camera->rate > 0.0 && camera->rate <= 1000.0))
    {
      return field + ".rate = " + shown(camera->rate) + ": must be in (0, 1000] Hz";
    }
  }
  return fixed ? readIntrinsics(node, field, &camera->intrinsics) : "";
}

}  // namespace

std::string readCameras(const YAML::Node& node, CameraMount mount, std::vector<CameraSpec>* cameras)
{
  if (!node.IsSequence())
  {
    return "cameras: expected a list of cameras";
  }
  std::vector<CameraSpec> read;
  for (std::size_t k = 0; k < node.size(); ++k)
  {
    const std::string field = "cameras[" + std::to_string(k) + "]";
    CameraSpec camera;
    const std::string error = readCamera(node[k], field, mount, &camera);
    if (!error.empty())
    {
      return error;
    }
    read.push_back(camera);
  }
  *cameras = std::move(read);
  return "";
}

}  // namespace rov_tether::spec
