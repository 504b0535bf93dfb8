#include "rov_tether/camera/tether_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rov_tether::camera
{
namespace
{

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Pieces are about this long on the image (or as long as the tube is wide, when wider) [px].
constexpr double kPiecePixels = 16.0;
/// At most this many pieces per segment.
constexpr int kMaxPieces = 512;

/// Depth of the first hit of the ray t (x, y, 1), t > 0, on a capsule; +inf when it misses. The capsule
/// is the set of points within `r` of the segment from a to b (Quilez's ray-capsule intersection,
/// with a direction that is not normalised, so t is the depth along the optical axis).
struct CapsuleRay
{
  CapsuleRay(const Eigen::Vector3d& a_in, const Eigen::Vector3d& b_in, double r)
      : a(a_in), b(b_in), ba(b_in - a_in), baba(ba.squaredNorm()), baoa(-ba.dot(a_in)), r2(r * r)
  {
    c = baba * a.squaredNorm() - baoa * baoa - r2 * baba;
    cap_a = a.squaredNorm() - r2;
    cap_b = b.squaredNorm() - r2;
  }

  double hit(double x, double y) const
  {
    const double dd = x * x + y * y + 1.0;
    const double bard = ba.x() * x + ba.y() * y + ba.z();
    const double rdoa = -(a.x() * x + a.y() * y + a.z());
    const double k2 = baba * dd - bard * bard;
    const double k1 = baba * rdoa - baoa * bard;
    const double h = k1 * k1 - k2 * c;
    if (h < 0.0)
    {
      return kInf;  // misses the infinite cylinder, and so the capsule inside it
    }
    if (k2 > 1e-12 * baba * dd)
    {
      const double t = (-k1 - std::sqrt(h)) / k2;
      const double along = baoa + t * bard;
      if (along > 0.0 && along < baba && t > 0.0)
      {
        return t;
      }
    }
    // The round ends: the nearer hit of the two balls (the first hit of a union is the nearest).
    return std::min(ball(a, cap_a, x, y, dd), ball(b, cap_b, x, y, dd));
  }

  static double ball(const Eigen::Vector3d& centre, double cc, double x, double y, double dd)
  {
    const double dc = centre.x() * x + centre.y() * y + centre.z();
    const double disc = dc * dc - dd * cc;
    if (disc < 0.0)
    {
      return kInf;
    }
    const double t = (dc - std::sqrt(disc)) / dd;
    return t > 0.0 ? t : kInf;
  }

  Eigen::Vector3d a, b, ba;
  double baba, baoa, r2, c = 0.0, cap_a = 0.0, cap_b = 0.0;
};

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
  auto* mask = mask_.ptr<std::uint8_t>();
  auto* depth = depth_.ptr<float>();
  for (int i : pixels_)
  {
    mask[i] = 0;
    depth[i] = std::nanf("");
  }
  pixels_.clear();
}

RenderStats TetherRenderer::render(const CameraModel& camera, const Eigen::Isometry3d& world_from_camera,
                                   const std::vector<Tube>& tubes, const std::vector<const Occluder*>& occluders)
{
  prepare(camera);
  segments_drawn_ = 0;
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
      drawSegment(camera, previous, next, tube.radius);
      previous = next;
    }
  }
  RenderStats stats;
  stats.segments_drawn = segments_drawn_;
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

void TetherRenderer::drawSegment(const CameraModel& camera, Eigen::Vector3d a, Eigen::Vector3d b, double radius)
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
  ++segments_drawn_;
  const double length_px = camera.maxFocal() * std::hypot(a.x() / a.z() - b.x() / b.z(), a.y() / a.z() - b.y() / b.z());
  const double radius_px = camera.maxFocal() * radius / std::max(a.z(), b.z());
  const int pieces =
      std::clamp(static_cast<int>(std::ceil(length_px / std::max(kPiecePixels, radius_px))), 1, kMaxPieces);
  Eigen::Vector3d start = a;
  for (int k = 1; k <= pieces; ++k)
  {
    const Eigen::Vector3d end = k == pieces ? b : a + (b - a) * (static_cast<double>(k) / pieces);
    drawPiece(camera, Capsule{start, end, radius});
    start = end;
  }
}

void TetherRenderer::drawPiece(const CameraModel& camera, const Capsule& piece)
{
  // The capsule lies in the box [lo, hi]; its image in normalised coordinates in the box's (z > 0).
  const Eigen::Vector3d lo = piece.a.cwiseMin(piece.b).array() - piece.radius;
  const Eigen::Vector3d hi = piece.a.cwiseMax(piece.b).array() + piece.radius;
  const RayBounds& rb = camera.rayBounds();
  const double x_min = std::max(lo.x() / (lo.x() >= 0.0 ? hi.z() : lo.z()), rb.x_min);
  const double x_max = std::min(hi.x() / (hi.x() >= 0.0 ? lo.z() : hi.z()), rb.x_max);
  const double y_min = std::max(lo.y() / (lo.y() >= 0.0 ? hi.z() : lo.z()), rb.y_min);
  const double y_max = std::min(hi.y() / (hi.y() >= 0.0 ? lo.z() : hi.z()), rb.y_max);
  if (x_min > x_max || y_min > y_max)
  {
    return;
  }
  // The rectangle's pixels: its corners without distortion (an affine map); with distortion, points
  // along its edges every 8 px or so (the distortion is monotonic within the image's rays).
  double u_min = kInf, u_max = -kInf, v_min = kInf, v_max = -kInf;
  const auto extend = [&](double x, double y)
  {
    const Eigen::Vector2d p = camera.toPixel(x, y);
    u_min = std::min(u_min, p.x()), u_max = std::max(u_max, p.x());
    v_min = std::min(v_min, p.y()), v_max = std::max(v_max, p.y());
  };
  const int samples = camera.intrinsics().distorted()
                          ? 2 + static_cast<int>(camera.maxFocal() * std::max(x_max - x_min, y_max - y_min) / 8.0)
                          : 1;
  for (int k = 0; k <= samples; ++k)
  {
    const double s = static_cast<double>(k) / samples;
    const double x = x_min + s * (x_max - x_min);
    const double y = y_min + s * (y_max - y_min);
    extend(x, y_min), extend(x, y_max), extend(x_min, y), extend(x_max, y);
  }
  const int u0 = std::max(0, static_cast<int>(std::floor(u_min)) - 1);
  const int u1 = std::min(camera.width() - 1, static_cast<int>(std::ceil(u_max)) + 1);
  const int v0 = std::max(0, static_cast<int>(std::floor(v_min)) - 1);
  const int v1 = std::min(camera.height() - 1, static_cast<int>(std::ceil(v_max)) + 1);

  const CapsuleRay capsule(piece.a, piece.b, piece.radius);
  const int width = camera.width();
  const float* rays = camera.rays();
  auto* depth = depth_.ptr<float>();
  for (int v = v0; v <= v1; ++v)
  {
    for (int u = u0; u <= u1; ++u)
    {
      const int i = v * width + u;
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
