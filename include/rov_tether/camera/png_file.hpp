#pragma once
// PNG files of the camera dataset, written with libpng (docs/benchmarks.md, "The runner's start-up").

#include <opencv2/core.hpp>
#include <string>

namespace rov_tether::camera
{

/// Writes `image` to `path` as a PNG: CV_8UC1 and CV_16UC1 as grey (8 and 16 bits), CV_8UC3 (BGR, as OpenCV
/// keeps colour) as RGB, fast compression. Returns false when the file cannot be written or the type is none
/// of these. Not OpenCV's imwrite: its codec library loads some 116 more shared libraries into every program
/// that links it, at every start (docs/benchmarks.md, "The runner's start-up").
bool writePng(const std::string& path, const cv::Mat& image);

}  // namespace rov_tether::camera
