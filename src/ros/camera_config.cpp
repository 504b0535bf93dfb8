#include "rov_tether/ros/camera_config.hpp"

#include <sensor_msgs/image_encodings.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace rov_tether::ros_layer
{
namespace
{

bool isNumber(const XmlRpc::XmlRpcValue& v)
{
  return v.getType() == XmlRpc::XmlRpcValue::TypeDouble || v.getType() == XmlRpc::XmlRpcValue::TypeInt;
}

double toDouble(const XmlRpc::XmlRpcValue& v)
{
  return v.getType() == XmlRpc::XmlRpcValue::TypeInt ? static_cast<int>(const_cast<XmlRpc::XmlRpcValue&>(v))
                                                     : static_cast<double>(const_cast<XmlRpc::XmlRpcValue&>(v));
}

/// Reads a list of numbers of one of `sizes`; "" or the problem.
std::string readList(const XmlRpc::XmlRpcValue& v, const std::string& field, const std::vector<int>& sizes,
                     std::vector<double>* out)
{
  if (v.getType() != XmlRpc::XmlRpcValue::TypeArray || std::find(sizes.begin(), sizes.end(), v.size()) == sizes.end())
  {
    std::string allowed;
    for (int s : sizes)
    {
      allowed += (allowed.empty() ? "" : " or ") + std::to_string(s);
    }
    return field + ": expected a list of " + allowed + " numbers";
  }
  out->clear();
  for (int i = 0; i < v.size(); ++i)
  {
    if (!isNumber(v[i]))
    {
      return field + "[" + std::to_string(i) + "]: expected a number";
    }
    out->push_back(toDouble(v[i]));
  }
  return "";
}

std::string readCamera(XmlRpc::XmlRpcValue& entry, const std::string& field, CameraConfig* camera)
{
  if (entry.getType() != XmlRpc::XmlRpcValue::TypeStruct)
  {
    return field + ": expected a map with name, frame, info_topic or width/height/K/D, image_topic or rate";
  }
  static const std::vector<std::string> known = {"name", "frame", "info_topic",  "width", "height",
                                                 "K",    "D",     "image_topic", "rate"};
  for (const auto& item : entry)
  {
    if (std::find(known.begin(), known.end(), item.first) == known.end())
    {
      return field + ": unknown field '" + item.first +
             "' (expected name, frame, info_topic, width, height, K, D, image_topic, rate)";
    }
  }
  const auto text = [&](const char* key, std::string* out) -> std::string
  {
    if (!entry.hasMember(key))
    {
      return "";
    }
    if (entry[key].getType() != XmlRpc::XmlRpcValue::TypeString)
    {
      return field + "." + key + ": expected a string";
    }
    *out = static_cast<std::string>(entry[key]);
    return "";
  };
  std::string error;
  for (const auto& [key, out] :
       std::vector<std::pair<const char*, std::string*>>{{"name", &camera->name},
                                                         {"frame", &camera->frame},
                                                         {"info_topic", &camera->info_topic},
                                                         {"image_topic", &camera->image_topic}})
  {
    if (!(error = text(key, out)).empty())
    {
      return error;
    }
  }
  if (camera->name.empty() ||
      camera->name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") !=
          std::string::npos ||
      std::isdigit(static_cast<unsigned char>(camera->name[0])))
  {
    return field + ".name = '" + camera->name + "': expected a ROS name (letters, digits, '_', not a digit first)";
  }
  if (camera->frame.empty())
  {
    return field + ".frame: missing (the camera's tf optical frame)";
  }
  const bool fixed = entry.hasMember("width") || entry.hasMember("height") || entry.hasMember("K");
  if (camera->info_topic.empty() == !fixed)
  {
    return field + ": give either info_topic or the fixed intrinsics width, height, K (and D)";
  }
  if (fixed)
  {
    for (const char* key : {"width", "height"})
    {
      if (!entry.hasMember(key) || entry[key].getType() != XmlRpc::XmlRpcValue::TypeInt)
      {
        return field + "." + key + ": expected a whole number of pixels";
      }
    }
    camera->intrinsics.width = static_cast<int>(entry["width"]);
    camera->intrinsics.height = static_cast<int>(entry["height"]);
    std::vector<double> values;
    if (!entry.hasMember("K") || !(error = readList(entry["K"], field + ".K", {9}, &values)).empty())
    {
      return error.empty() ? field + ".K: missing" : error;
    }
    std::copy(values.begin(), values.end(), camera->intrinsics.K.begin());
    if (entry.hasMember("D"))
    {
      if (!(error = readList(entry["D"], field + ".D", {0, 4, 5}, &camera->intrinsics.D)).empty())
      {
        return error;
      }
    }
    const auto errors = camera->intrinsics.validate(field + ".");
    if (!errors.empty())
    {
      return errors.front();
    }
  }
  if (entry.hasMember("rate"))
  {
    if (!camera->image_topic.empty())
    {
      return field + ": give either image_topic or rate";
    }
    if (!isNumber(entry["rate"]) || !(toDouble(entry["rate"]) > 0.0 && toDouble(entry["rate"]) <= 1000.0))
    {
      return field + ".rate: must be a number in (0, 1000] Hz";
    }
    camera->rate = toDouble(entry["rate"]);
  }
  return "";
}

}  // namespace

std::string loadCameraConfigs(const XmlRpc::XmlRpcValue& list, const std::vector<std::string>& reserved,
                              std::vector<CameraConfig>* cameras)
{
  if (list.getType() != XmlRpc::XmlRpcValue::TypeArray)
  {
    return "cameras: expected a list of cameras";
  }
  std::vector<CameraConfig> result;
  auto& entries = const_cast<XmlRpc::XmlRpcValue&>(list);
  for (int i = 0; i < entries.size(); ++i)
  {
    const std::string field = "cameras[" + std::to_string(i) + "]";
    CameraConfig camera;
    const std::string error = readCamera(entries[i], field, &camera);
    if (!error.empty())
    {
      return error;
    }
    const bool taken =
        std::find(reserved.begin(), reserved.end(), camera.name) != reserved.end() ||
        std::any_of(result.begin(), result.end(), [&](const CameraConfig& c) { return c.name == camera.name; });
    if (taken)
    {
      return field + ".name = '" + camera.name + "': already used by another camera or a tether";
    }
    result.push_back(camera);
  }
  *cameras = result;
  return "";
}

std::string intrinsicsFromCameraInfo(const sensor_msgs::CameraInfo& info, camera::CameraIntrinsics* intrinsics)
{
  if (!info.distortion_model.empty() && info.distortion_model != "plumb_bob")
  {
    return "distortion_model '" + info.distortion_model + "': only plumb_bob is supported";
  }
  if (info.binning_x > 1 || info.binning_y > 1 || info.roi.width != 0 || info.roi.height != 0)
  {
    return "binning or a region of interest: not supported (the full image is rendered)";
  }
  camera::CameraIntrinsics result;
  result.width = static_cast<int>(std::min<std::uint32_t>(info.width, camera::CameraIntrinsics::kMaxSide + 1));
  result.height = static_cast<int>(std::min<std::uint32_t>(info.height, camera::CameraIntrinsics::kMaxSide + 1));
  std::copy(info.K.begin(), info.K.end(), result.K.begin());
  result.D = info.D;
  const auto errors = result.validate();
  if (!errors.empty())
  {
    return errors.front();
  }
  *intrinsics = result;
  return "";
}

void toImageMessage(const cv::Mat& image, const std_msgs::Header& header, sensor_msgs::Image* msg)
{
  msg->header = header;
  msg->height = static_cast<std::uint32_t>(image.rows);
  msg->width = static_cast<std::uint32_t>(image.cols);
  msg->encoding =
      image.type() == CV_32FC1 ? sensor_msgs::image_encodings::TYPE_32FC1 : sensor_msgs::image_encodings::MONO8;
  msg->is_bigendian = 0;
  msg->step = static_cast<std::uint32_t>(image.cols * image.elemSize());
  msg->data.resize(static_cast<std::size_t>(msg->step) * image.rows);
  for (int r = 0; r < image.rows; ++r)
  {
    std::memcpy(&msg->data[static_cast<std::size_t>(r) * msg->step], image.ptr(r), msg->step);
  }
}

namespace
{

/// The pixels `previous` and `current` of `image`, of `size` bytes each, into msg's data: a copy of a
/// size known at compile time is a move, where one of a size known at run time is a call per pixel.
template <std::size_t size>
void copyPixels(const cv::Mat& image, const std::vector<int>& previous, const std::vector<int>& current,
                sensor_msgs::Image* msg)
{
  for (const std::vector<int>* changed : {&previous, &current})
  {
    for (int i : *changed)
    {
      std::memcpy(&msg->data[i * size], image.data + i * size, size);
    }
  }
}

}  // namespace

void updateImageMessage(const cv::Mat& image, const std::vector<int>& current, std::vector<int>* previous,
                        const std_msgs::Header& header, sensor_msgs::Image* msg)
{
  const std::size_t element = image.elemSize();
  const bool same =
      msg->width == static_cast<std::uint32_t>(image.cols) && msg->height == static_cast<std::uint32_t>(image.rows) &&
      msg->step == image.cols * element && image.isContinuous() &&
      msg->encoding ==
          (image.type() == CV_32FC1 ? sensor_msgs::image_encodings::TYPE_32FC1 : sensor_msgs::image_encodings::MONO8);
  if (!same)
  {
    toImageMessage(image, header, msg);
    previous->reserve(image.total());
  }
  else if (previous->size() + current.size() > image.total() / 8)
  {
    // Many changed pixels (a tether filling the view): one straight copy of the image is cheaper than
    // a scattered copy per pixel.
    std::memcpy(msg->data.data(), image.data, image.total() * element);
    msg->header = header;
  }
  else
  {
    msg->header = header;
    if (element == 1)
    {
      copyPixels<1>(image, *previous, current, msg);  // mono8
    }
    else
    {
      copyPixels<4>(image, *previous, current, msg);  // 32FC1
    }
  }
  previous->assign(current.begin(), current.end());
}

}  // namespace rov_tether::ros_layer
