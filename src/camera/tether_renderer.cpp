#include "rov_tether/camera/tether_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rov_tether/camera/capsule.hpp"

namespace rov_tether::camera
{
namespace
{

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

void TetherRenderer::prepare(const CameraModel& camera)
{
  if (mask_.rows != camera.height() || mask_.cols != camera.width())
  {
    mask_ = cv::Mat(camera.height(), camera.width(), CV_8UC1, cv::Scalar(0));
    depth_ = cv::Mat(camera.height(), camera.width(), CV_32FC1, cv::Scalar(std::nanf("")));
    pixels_.clear();
    pixels_.reserve(static_cast<std::size_t>(camera.width()) * camera.height());
    return;
  }
  if (pixels_.size() > mask_.total() / 8)
  {
    // Many pixels drawn (a tether filling the view): clearing whole images is cheaper than pixel by pixel.
    mask_.setTo(cv::Scalar(0));
    depth_.setTo(cv::Scalar(std::nanf("")));
  }
  else
  {
    auto* mask = mask_.ptr<std::uint8_t>();
    auto* depth = depth_.ptr<float>();
    for (int i : pixels_)
    {
      mask[i] = 0;
      depth[i] = std::nanf("");
    }
  }
  pixels_.clear();
}

RenderStats TetherRenderer::render(const CameraModel& camera, const Eigen::Isometry3d& world_from_camera,
                                   const std::vector<Tube>& tubes, const std::vector<const Occluder*>& occluders)
{
  prepare(camera);
  capsules_.clear();
  const Eigen::Isometry3d camera_from_world = world_from_camera.inverse();
  for (const Tube& tube : tubes)
  {
    if (tube.points == nullptr || tube.points->size() < 2 || !(tube.radius > 0.0))
    {
      continue;
    }
    const auto& points = *tube.points;
    Eigen::Vector3d previous = camera_from_world * points[0];
    for (std::size_t i = 1; i < points.size(); ++i)
    {
      const Eigen::Vector3d next = camera_from_world * points[i];
      addSegment(camera, previous, next, tube.radius);
      previous = next;
    }
  }
  // Nearest first: where a nearer segment already hides a pixel, a farther one skips it.
  std::sort(capsules_.begin(), capsules_.end(),
            [](const Capsule& p, const Capsule& q) { return p.nearest < q.nearest; });
  for (const Capsule& capsule : capsules_)
  {
    drawCapsule(camera, capsule);
  }
  RenderStats stats;
  stats.segments_drawn = capsules_.size();
  stats.occluded_pixels = occlude(camera, world_from_camera, occluders);
  auto* mask = mask_.ptr<std::uint8_t>();
  const auto* depth = depth_.ptr<float>();
  double nearest = kInf;
  for (int i : pixels_)
  {
    mask[i] = 255;
    nearest = std::min<double>(nearest, depth[i]);
  }
  stats.pixels = pixels_.size();
  stats.coverage = static_cast<double>(pixels_.size()) / (static_cast<double>(camera.width()) * camera.height());
  stats.nearest_depth = pixels_.empty() ? std::nan("") : nearest;
  return stats;
}

void TetherRenderer::addSegment(const CameraModel& camera, Eigen::Vector3d a, Eigen::Vector3d b, double radius)
{
  // Behind the camera (or too close to see): clip at the near plane.
  const double near = kNearClip + radius;
  if (a.z() < near && b.z() < near)
  {
    return;
  }
  if (a.z() < near)
  {
    a += (b - a) * ((near - a.z()) / (b.z() - a.z()));
  }
  else if (b.z() < near)
  {
    b += (a - b) * ((near - b.z()) / (a.z() - b.z()));
  }
  if ((b - a).squaredNorm() < 1e-24)
  {
    return;  // a segment of particles still on the spool: the neighbours' round ends cover it
  }
  // Outside the image's rays: both ends further than the radius beyond one side of the view frustum.
  const RayBounds& rb = camera.rayBounds();
  const auto beyond = [&](double nx, double ny, double nz)
  {
    const double norm = std::sqrt(nx * nx + ny * ny + nz * nz);
    return (nx * a.x() + ny * a.y() + nz * a.z()) < -radius * norm &&
           (nx * b.x() + ny * b.y() + nz * b.z()) < -radius * norm;
  };
  if (beyond(-1.0, 0.0, rb.x_max) || beyond(1.0, 0.0, -rb.x_min) || beyond(0.0, -1.0, rb.y_max) ||
      beyond(0.0, 1.0, -rb.y_min))
  {
    return;
  }
  capsules_.push_back(Capsule{a, b, radius, std::min(a.z(), b.z()) - radius});
}

void TetherRenderer::drawCapsule(const CameraModel& camera, const Capsule& segment)
{
  const Eigen::Vector3d& a = segment.a;
  const Eigen::Vector3d& b = segment.b;
  const double radius = segment.radius;
  const float nearest = static_cast<float>(segment.nearest);
  // Row by row, the columns whose rays can hit the capsule (its footprint over the row's band of y),
  // widened by a pixel against rounding; each of those pixels' rays is intersected exactly.
  const CapsuleFootprint footprint(a, b, radius);
  const RayBounds& rb = camera.rayBounds();
  if (footprint.xMin() > rb.x_max || footprint.xMax() < rb.x_min)
  {
    return;
  }
  const CapsuleRay capsule(a, b, radius);
  const int width = camera.width();
  const float* rays = camera.rays();
  auto* depth = depth_.ptr<float>();
  const auto [v0, v1] = camera.rowsBetween(footprint.yMin(), footprint.yMax());
  std::pair<int, int> columns(-1, -2);  // the previous row's, to start from
  for (int v = v0; v <= v1; ++v)
  {
    XRange x = footprint.xRange(camera.rowYMin(v), camera.rowYMax(v));
    if (x.empty())
    {
      continue;
    }
    columns = camera.columnsBetween(v, x.lo, x.hi, columns);
    if (camera.rowYMin(v) < camera.rowYMax(v) && columns.first <= columns.second)
    {
      // A distorted row bends: over those columns alone its band of y is narrower, and so is x's range.
      const auto [y_lo, y_hi] = camera.rowYBetween(v, columns.first, columns.second);
      x = footprint.xRange(y_lo, y_hi);
      if (x.empty())
      {
        continue;
      }
      columns = camera.columnsBetween(v, x.lo, x.hi, columns);
    }
    const auto [first, last] = columns;
    const int u0 = std::max(0, first - 1), u1 = std::min(width - 1, last + 1);
    for (int i = v * width + u0, end = v * width + u1; i <= end; ++i)
    {
      if (depth[i] <= nearest)
      {
        continue;  // a nearer segment hides it (false while NaN: nothing drawn there yet)
      }
      const double t = capsule.hit(rays[2 * i], rays[2 * i + 1]);
      if (t == kInf)
      {
        continue;
      }
      const float d = static_cast<float>(t);
      if (std::isnan(depth[i]))
      {
        pixels_.push_back(i);
        depth[i] = d;
      }
      else if (d < depth[i])
      {
        depth[i] = d;
      }
    }
  }
}

std::size_t TetherRenderer::occlude(const CameraModel& camera, const Eigen::Isometry3d& world_from_camera,
                                    const std::vector<const Occluder*>& occluders)
{
  if (occluders.empty())
  {
    return 0;
  }
  const Eigen::Vector3d origin = world_from_camera.translation();
  const Eigen::Matrix3d rotation = world_from_camera.linear();
  auto* depth = depth_.ptr<float>();
  const int width = camera.width();
  std::size_t kept = 0;
  for (int i : pixels_)
  {
    const Eigen::Vector2d ray = camera.ray(i % width, i / width);
    const Eigen::Vector3d direction = rotation * Eigen::Vector3d(ray.x(), ray.y(), 1.0);
    double nearest = kInf;
    for (const Occluder* occluder : occluders)
    {
      nearest = std::min(nearest, occluder->depthOnRay(origin, direction));
    }
    if (nearest < depth[i])
    {
      depth[i] = std::nanf("");
    }
    else
    {
      pixels_[kept++] = i;
    }
  }
  const std::size_t hidden = pixels_.size() - kept;
  pixels_.resize(kept);
  return hidden;
}

void drawOverlay(cv::Mat& image, const std::vector<int>& pixels, const cv::Vec3b& colour)
{
  auto* data = image.ptr<cv::Vec3b>();
  for (int i : pixels)
  {
    for (int c = 0; c < 3; ++c)
    {
      data[i][c] = static_cast<std::uint8_t>((data[i][c] + colour[c] + 1) / 2);
    }
  }
}

}  // namespace rov_tether::camera
