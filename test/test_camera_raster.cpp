// Which pixels the renderer tests: the footprint of a tube segment against the rays that hit it, and the
// rendered image against a renderer that tests every pixel of the image.
#include <gtest/gtest.h>

#include <random>

#include "camera_fixtures.hpp"
#include "rov_tether/camera/capsule.hpp"
#include "rov_tether/camera/tether_renderer.hpp"

namespace rov_tether::camera
{
namespace
{

/// The 720p test camera: 1280 x 720, f = 900 px; `d` its distortion.
CameraIntrinsics camera720p(std::vector<double> d = {}) { return test::pinhole(1280, 720, 900.0, std::move(d)); }

using test::kBarrel;

/// A random capsule in front of the camera (both ends at z > r) and random rays near it.
struct RandomCapsules
{
  std::mt19937 random{11};
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(random); }
  Eigen::Vector3d end(double r)
  {
    const double z = r + uniform(0.005, 4.0);
    return {uniform(-1.5, 1.5) * z, uniform(-1.0, 1.0) * z, z};
  }
};

TEST(CameraRaster, FootprintHoldsEveryHittingRay)
{
  // Any ray (x, y, 1) that hits the capsule (CapsuleRay, the renderer's exact test) must lie in the
  // footprint: y in [yMin, yMax], and x in xRange of every band of y that holds y.
  RandomCapsules sample;
  int hits = 0, outside = 0;
  for (int k = 0; k < 400; ++k)
  {
    const double r = sample.uniform(0.001, 0.2);
    const Eigen::Vector3d a = sample.end(r), b = k % 4 == 0 ? a + Eigen::Vector3d(0, 0, 0.3) : sample.end(r);
    const CapsuleRay capsule(a, b, r);
    const CapsuleFootprint footprint(a, b, r);
    for (int j = 0; j < 2000; ++j)
    {
      // Rays around the segment's image (its ends' images widened).
      const double s = sample.uniform(-0.3, 1.3);
      const Eigen::Vector3d p = a + s * (b - a);
      const double x = p.x() / p.z() + sample.uniform(-0.5, 0.5), y = p.y() / p.z() + sample.uniform(-0.5, 0.5);
      if (capsule.hit(x, y) == CapsuleRay::kMiss)
      {
        continue;
      }
      ++hits;
      const double below = sample.uniform(0.0, 0.05), above = sample.uniform(0.0, 0.05);
      for (const XRange& range : {footprint.xRange(y, y), footprint.xRange(y - below, y + above)})
      {
        outside += !(x >= range.lo && x <= range.hi);
      }
      outside += !(y >= footprint.yMin() && y <= footprint.yMax() && x >= footprint.xMin() && x <= footprint.xMax());
    }
  }
  std::printf("[ measured ] footprint: %d hitting rays, %d outside it\n", hits, outside);
  EXPECT_GT(hits, 50000);
  EXPECT_EQ(outside, 0);
}

TEST(CameraRaster, FootprintIsTheSilhouetteAlongTheBody)
{
  // Away from the round ends, a row crosses the tube between its two silhouette lines, and the footprint
  // is that interval: found here by bisection on the exact test, from a ray on the axis outwards.
  const Eigen::Vector3d a(-1.0, -0.6, 2.0), b(1.2, 0.5, 3.5);
  const double r = 0.05;
  const CapsuleRay capsule(a, b, r);
  const CapsuleFootprint footprint(a, b, r);
  double worst = 0.0;
  for (double s = 0.2; s <= 0.8; s += 0.05)
  {
    const Eigen::Vector3d p = a + s * (b - a);
    const double y = p.y() / p.z(), centre = p.x() / p.z();
    const auto edge = [&](double outside)
    {
      double in = centre, out = outside;
      for (int k = 0; k < 80; ++k)
      {
        const double mid = 0.5 * (in + out);
        (capsule.hit(mid, y) == CapsuleRay::kMiss ? out : in) = mid;
      }
      return in;
    };
    const XRange range = footprint.xRange(y, y);
    worst = std::max({worst, std::abs(range.lo - edge(centre - 1.0)), std::abs(range.hi - edge(centre + 1.0))});
  }
  std::printf("[ measured ] footprint off the silhouette along the body by at most %.3g\n", worst);
  EXPECT_LE(worst, 1e-9);  // a thousandth of a pixel's 1 / f at f ~ 1e3 px would be 1e-6
}

/// Depth image drawn by testing every pixel's ray against every segment (tethers wholly beyond the near
/// clip, so no clipping applies): the nearest hit, NaN where none.
cv::Mat everyPixel(const CameraModel& camera, const std::vector<Position>& points, double r)
{
  cv::Mat depth(camera.height(), camera.width(), CV_32FC1, cv::Scalar(std::nanf("")));
  for (std::size_t k = 1; k < points.size(); ++k)
  {
    const CapsuleRay capsule(points[k - 1], points[k], r);
    for (int v = 0; v < camera.height(); ++v)
    {
      for (int u = 0; u < camera.width(); ++u)
      {
        const Eigen::Vector2d ray = camera.ray(u, v);
        const double t = capsule.hit(ray.x(), ray.y());
        float& d = depth.at<float>(v, u);
        if (t != CapsuleRay::kMiss && !(d <= static_cast<float>(t)))
        {
          d = static_cast<float>(t);
        }
      }
    }
  }
  return depth;
}

TEST(CameraRaster, RendererDrawsWhatEveryPixelsRaySees)
{
  // The renderer tests only the pixels of each segment's footprint; testing every pixel must find the
  // same pixels and depths. Tethers as a vehicle's camera sees its own: one leaving from beside the lens
  // and running away nearly along the view (its near segments fill much of the image), one arching
  // across; with and without a lens that bends the rows.
  std::vector<std::vector<Position>> tethers(2);
  for (int i = 0; i <= 40; ++i)
  {
    const double s = i / 40.0;
    tethers[0].emplace_back(0.004 + 1.5 * s * s, 0.012 + 0.3 * s, 0.035 + 6.0 * s);
    tethers[1].emplace_back(-3.0 + 6.0 * s, 0.3 + 0.8 * (s - 0.5) * (s - 0.5), 1.5 + 2.0 * std::sin(M_PI * s));
  }
  for (const auto& d : {std::vector<double>{}, kBarrel})
  {
    const CameraModel camera(camera720p(d));
    TetherRenderer renderer;
    for (const auto& points : tethers)
    {
      const std::vector<Tube> tubes = {Tube{&points, 0.01}};
      const RenderStats stats = renderer.render(camera, Eigen::Isometry3d::Identity(), tubes, {});
      const cv::Mat expected = everyPixel(camera, points, 0.01);
      int differ = 0;
      for (int i = 0; i < camera.width() * camera.height(); ++i)
      {
        const float want = expected.ptr<float>()[i], got = renderer.depth().ptr<float>()[i];
        differ += std::isnan(want) != std::isnan(got) || std::abs(want - got) > 1e-6f ||
                  (renderer.mask().data[i] == 255) != !std::isnan(want);
      }
      std::printf("[ measured ] %s camera: %zu tether pixels (coverage %.3f), %d differ from every pixel's test\n",
                  d.empty() ? "pinhole" : "barrel", stats.pixels, stats.coverage, differ);
      EXPECT_GT(stats.pixels, 1000u);
      EXPECT_EQ(differ, 0);
    }
  }
}

}  // namespace
}  // namespace rov_tether::camera
