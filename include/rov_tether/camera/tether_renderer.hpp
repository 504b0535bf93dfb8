#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <opencv2/core.hpp>
#include <vector>

#include "rov_tether/camera/camera_model.hpp"
#include "rov_tether/camera/occluder.hpp"
#include "rov_tether/core/cable.hpp"

namespace rov_tether::camera
{

/// A tether to draw: its particles in the world frame (spool first) and the tube's radius [m].
struct Tube
{
  const std::vector<Position>* points = nullptr;
  double radius = 0.01;
};

/// What one render found.
struct RenderStats
{
  std::size_t pixels = 0;           ///< Pixels where the tether is visible.
  double coverage = 0.0;            ///< pixels / image pixels [-].
  double nearest_depth = 0.0;       ///< Smallest depth of a visible pixel [m]; NaN when none.
  std::size_t segments_drawn = 0;   ///< Segments (after clipping) that reached the pixel loop.
  std::size_t occluded_pixels = 0;  ///< Tether pixels hidden by an occluder.
};

/**
 * Draws tethers as tubes in a camera image: a mask (mono8, 255 where a tether is visible) and a depth
 * image (32FC1, depth along the optical axis of the nearest tube surface [m], NaN elsewhere).
 *
 * Each segment is a capsule (a cylinder of the tube's radius with round ends, so joints are seamless).
 * A pixel belongs to the tether when the ray through its centre hits a capsule; its depth is that of the
 * first hit, nearest over all tubes. Segments are clipped at kNearClip + radius in front of the camera
 * (what lies behind is dropped) and culled outside the image's rays; the rest are drawn nearest first,
 * each testing, row by row, the pixels whose rays lie in its CapsuleFootprint over the row's band of y,
 * but for those where a nearer segment is already drawn in front of its nearest point. Occluders
 * then hide the tether pixels behind their surface. Buffers are kept between renders and only the
 * previous render's pixels are cleared, so a render allocates nothing once the image size is set.
 */
class TetherRenderer
{
 public:
  /// Nothing nearer to the camera than this (plus the tube's radius) is drawn [m].
  static constexpr double kNearClip = 0.01;

  /// Renders `tubes` seen by `camera` at `world_from_camera` (the optical frame's pose in the world:
  /// p_world = world_from_camera * p_camera), hidden where `occluders` are nearer.
  RenderStats render(const CameraModel& camera, const Eigen::Isometry3d& world_from_camera,
                     const std::vector<Tube>& tubes, const std::vector<const Occluder*>& occluders);

  const cv::Mat& mask() const { return mask_; }    ///< CV_8UC1
  const cv::Mat& depth() const { return depth_; }  ///< CV_32FC1 [m]
  /// Indices (v * width + u) of the visible tether pixels of the last render.
  const std::vector<int>& pixels() const { return pixels_; }

 private:
  /// A segment to draw, clipped, in the optical frame: both ends at z > radius.
  struct Capsule
  {
    Eigen::Vector3d a, b;
    double radius;
    double nearest;  ///< Smallest depth of its points [m].
  };
  void prepare(const CameraModel& camera);
  /// Clips segment (a, b) (optical frame) and, unless it is out of view, adds it to capsules_.
  void addSegment(const CameraModel& camera, Eigen::Vector3d a, Eigen::Vector3d b, double radius);
  /// Draws a capsule into the depth image and pixels_ where it is nearer than what is drawn.
  void drawCapsule(const CameraModel& camera, const Capsule& segment);
  /// Removes the pixels an occluder hides; returns how many.
  std::size_t occlude(const CameraModel& camera, const Eigen::Isometry3d& world_from_camera,
                      const std::vector<const Occluder*>& occluders);

  cv::Mat mask_;
  cv::Mat depth_;
  std::vector<int> pixels_;
  std::vector<Capsule> capsules_;  ///< This render's segments in view.
};

/// Draws the tether pixels (TetherRenderer::pixels() of a render of the same size) on an 8-bit, 3-channel
/// image: each one half way to `colour` (BGR), so the image stays visible under the tether.
void drawOverlay(cv::Mat& image, const std::vector<int>& pixels, const cv::Vec3b& colour = cv::Vec3b(0, 255, 255));

}  // namespace rov_tether::camera
