#include "rov_tether/ros/camera_config.hpp"

#include <sensor_msgs/image_encodings.h>

#include <algorithm>
#include <cstring>
#include <new>
#include <stdexcept>

#include "rov_tether/ros/obstacle_config.hpp"
#include "rov_tether/ros/xmlrpc_yaml.hpp"
#include "rov_tether/spec/camera_reader.hpp"

namespace rov_tether::ros_layer
{

std::string loadCameraConfigs(const XmlRpc::XmlRpcValue& list, const std::vector<std::string>& reserved,
                              std::vector<CameraConfig>* cameras)
{
  // The one reader of cameras (spec::readCameras, as the scenario runner's), for cameras on tf frames.
  // Their names with the tethers' (`reserved`): validateWorldSpec, the world's one check of names.
  std::vector<spec::CameraSpec> read;
  std::string error = spec::readCameras(toYaml(list), spec::CameraMount::kTfFrame, &read);
  error = error.empty() ? validateWorldSpec(namesOnly(reserved, {}, read)) : error;
  if (error.empty())
  {
    *cameras = std::move(read);
  }
  return error;
}

std::string intrinsicsFromCameraInfo(const sensor_msgs::CameraInfo& info, camera::CameraIntrinsics* intrinsics)
{
  if (!info.distortion_model.empty() && info.distortion_model != "plumb_bob")
  {
    return "distortion_model '" + info.distortion_model + "': only plumb_bob is supported";
  }
  if (info.binning_x > 1 || info.binning_y > 1)
  {
    return "binning_x = " + std::to_string(info.binning_x) + ", binning_y = " + std::to_string(info.binning_y) +
           ": binning is not supported (the full image is rendered)";
  }
  // sensor_msgs/CameraInfo: a roi of all zeros, or one the size of the image at (0, 0), is the full image.
  const sensor_msgs::RegionOfInterest& roi = info.roi;
  const bool no_roi = roi.width == 0 && roi.height == 0;
  const bool full_roi = roi.x_offset == 0 && roi.y_offset == 0 && roi.width == info.width && roi.height == info.height;
  if (!no_roi && !full_roi)
  {
    return "roi (x_offset, y_offset, width, height) = (" + std::to_string(roi.x_offset) + ", " +
           std::to_string(roi.y_offset) + ", " + std::to_string(roi.width) + ", " + std::to_string(roi.height) +
           "): a region of interest other than the full image is not supported (the full image is rendered)";
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

std::string buildCameraModel(const camera::CameraIntrinsics& intrinsics, std::unique_ptr<camera::CameraModel>* model,
                             const CameraModelBuilder& build, const camera::BuildAbandoned& abandoned)
{
  const std::string size = std::to_string(intrinsics.width) + "x" + std::to_string(intrinsics.height);
  const camera::BuildAbandoned asked = abandoned ? abandoned : [] { return false; };
  try
  {
    *model = build ? build(intrinsics, asked) : std::make_unique<camera::CameraModel>(intrinsics, asked);
    return "";
  }
  catch (const std::invalid_argument& e)
  {
    return e.what();
  }
  catch (const camera::CameraBuildAbandoned& e)
  {
    return e.what();
  }
  catch (const std::bad_alloc&)
  {
    return "building the " + size + " camera ran out of memory";
  }
  catch (const std::exception& e)
  {
    return "building the " + size + " camera failed: " + e.what();
  }
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
