#pragma once
// tether_node's `cameras` parameter and CameraInfo, converted to the camera library's types.

#include <XmlRpcValue.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <functional>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "rov_tether/camera/camera_model.hpp"
#include "rov_tether/spec/camera_intrinsics.hpp"
#include "rov_tether/spec/camera_spec.hpp"

namespace rov_tether::ros_layer
{

/// One entry of the private list parameter `cameras`: the one description of a camera (spec::CameraSpec, a
/// WorldSpec's), with its tf fields (name: outputs under ~<name>/; frame; info_topic or the fixed intrinsics;
/// image_topic or rate).
using CameraConfig = spec::CameraSpec;

/// Reads the `cameras` list (names, frames, topics, intrinsics, rate). Returns "" or every problem, each
/// naming the entry and field. `reserved` names may not be used (the tethers' own namespaces).
std::string loadCameraConfigs(const XmlRpc::XmlRpcValue& list, const std::vector<std::string>& reserved,
                              std::vector<CameraConfig>* cameras);

/// Intrinsics from a CameraInfo: "" or why it cannot be used (distortion model other than plumb_bob,
/// binning or a region of interest other than the full image, invalid K, more than 4096 x 4096 pixels).
std::string intrinsicsFromCameraInfo(const sensor_msgs::CameraInfo& info, camera::CameraIntrinsics* intrinsics);

/// What builds a camera model: CameraModel's constructor unless a test gives one that fails as memory would. It
/// is handed the build's `abandoned` (never empty), which it may ask, throwing CameraBuildAbandoned when it says so.
using CameraModelBuilder =
    std::function<std::unique_ptr<camera::CameraModel>(const camera::CameraIntrinsics&, const camera::BuildAbandoned&)>;

/// Builds the model of `intrinsics` into *model (with `build`, CameraModel's constructor when empty). Returns
/// "" or why it cannot be built, *model left as it was then: invalid intrinsics, a distortion that folds
/// over, a build `abandoned` part-way (CameraBuildAbandoned's words), or any other std::exception (std::bad_alloc: out
/// of memory). Never throws: a camera that cannot be built is refused, and the node goes on.
std::string buildCameraModel(const camera::CameraIntrinsics& intrinsics, std::unique_ptr<camera::CameraModel>* model,
                             const CameraModelBuilder& build = {}, const camera::BuildAbandoned& abandoned = {});

/// Copies `image` (CV_8UC1 as mono8, CV_32FC1 as 32FC1) into `msg`, reusing its storage.
void toImageMessage(const cv::Mat& image, const std_msgs::Header& header, sensor_msgs::Image* msg);

/// Brings `msg`, which held `image`'s previous content, up to date by copying only the pixels (indices
/// v * width + u) in `previous` and `current`, where it can have changed; `previous` becomes `current`.
/// A full copy when `msg` does not have the image's size and encoding yet, or when the changed pixels are
/// more than an eighth of the image (one straight copy is then cheaper than one per pixel). (A renderer's
/// image changes only at its last and its new tether pixels: this saves copying megabytes per frame.)
void updateImageMessage(const cv::Mat& image, const std::vector<int>& current, std::vector<int>* previous,
                        const std_msgs::Header& header, sensor_msgs::Image* msg);

}  // namespace rov_tether::ros_layer
