// The tether in a camera, without ROS: the rendered mask and depth against the closed-form image of a
// tube, the projection against OpenCV's projectPoints, clipping, occlusion and the shape history.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <set>
#include <sstream>

#include "camera_fixtures.hpp"
#include "rov_tether/camera/dataset_writer.hpp"
#include "rov_tether/camera/png_file.hpp"
#include "rov_tether/camera/shape_history.hpp"
#include "rov_tether/camera/tether_renderer.hpp"
#include "rov_tether/scenario/scenario_yaml.hpp"

namespace rov_tether::camera
{
namespace
{

/// The VGA test camera: 640 x 480, f = 500 px; `d` its distortion.
CameraIntrinsics vga(std::vector<double> d = {}) { return test::pinhole(640, 480, 500.0, std::move(d)); }

using test::kBarrel;

/// `n` segments from a to b.
std::vector<Position> line(const Position& a, const Position& b, int n = 100)
{
  std::vector<Position> points;
  for (int i = 0; i <= n; ++i)
  {
    points.push_back(a + (b - a) * (static_cast<double>(i) / n));
  }
  return points;
}

/// Renders one tube with the camera at the world origin, world = optical frame.
RenderStats renderOne(TetherRenderer& renderer, const CameraModel& camera, const std::vector<Position>& points,
                      double diameter, const Eigen::Isometry3d& pose = Eigen::Isometry3d::Identity(),
                      const std::vector<const Occluder*>& occluders = {})
{
  const std::vector<Tube> tubes = {Tube{&points, diameter / 2.0}};
  return renderer.render(camera, pose, tubes, occluders);
}

/// The rows [v_lo, v_hi] of pixel centres whose rays come within r of the line {(s, y0, Z)} (parallel to
/// x): in the y-z plane the ray is the direction (y_n, 1) and the axis the point (y0, Z), so the ray is
/// within r where its angle is within asin(r / |(y0, Z)|) of the axis' angle.
std::pair<double, double> bandRows(double y0, double z, double r, double fy, double cy)
{
  const double theta = std::atan2(y0, z);
  const double alpha = std::asin(r / std::hypot(y0, z));
  return {fy * std::tan(theta - alpha) + cy, fy * std::tan(theta + alpha) + cy};
}

/// Depth of the first point of the ray t (x_n, y_n, 1) on the cylinder of radius r around {(s, y0, Z)}:
/// the smaller root of (t y_n - y0)^2 + (t - Z)^2 = r^2.
double cylinderDepth(double yn, double y0, double z, double r)
{
  const double a = 1.0 + yn * yn;
  const double b = -2.0 * (yn * y0 + z);
  const double c = y0 * y0 + z * z - r * r;
  return (-b - std::sqrt(b * b - 4.0 * a * c)) / (2.0 * a);
}

TEST(Camera, StraightTetherMatchesTheAnalyticTube)
{
  // A 6 m tether of 5 cm diameter across the view, 2 m in front and 0.1 m below the optical axis,
  // parallel to the image rows: its image is the band of bandRows, f d / Z = 12.5 px wide.
  const CameraModel camera(vga());
  TetherRenderer renderer;
  const double y0 = 0.1, z = 2.0, d = 0.05;
  renderOne(renderer, camera, line({-3.0, y0, z}, {3.0, y0, z}), d);
  const auto [v_lo, v_hi] = bandRows(y0, z, d / 2.0, 500.0, 239.5);
  const double width = 500.0 * d / z;
  double worst_outside = 0.0, worst_width = 0.0, worst_depth = 0.0;
  int missing = 0;
  for (int u = 0; u < camera.width(); ++u)
  {
    int count = 0;
    for (int v = 0; v < camera.height(); ++v)
    {
      const bool in_mask = renderer.mask().at<std::uint8_t>(v, u) == 255;
      const float depth = renderer.depth().at<float>(v, u);
      ASSERT_EQ(in_mask, std::isfinite(depth)) << "mask and depth disagree at " << u << ", " << v;
      if (in_mask)
      {
        ++count;
        worst_outside = std::max({worst_outside, v_lo - v, v - v_hi});
        const double expected = cylinderDepth(camera.ray(u, v).y(), y0, z, d / 2.0);
        worst_depth = std::max(worst_depth, std::abs(depth - expected));
      }
      else if (v > v_lo && v < v_hi)
      {
        ++missing;  // a pixel centre inside the band that the mask lacks
      }
    }
    worst_width = std::max(worst_width, std::abs(count - width));
  }
  std::printf(
      "[ measured ] straight tube: band rows %.3f-%.3f; mask pixels outside it by at most %.3f px, "
      "width off f d / Z = %.2f px by at most %.3f px, depth off by at most %.3g m, %d missing\n",
      v_lo, v_hi, std::max(worst_outside, 0.0), width, worst_width, worst_depth, missing);
  EXPECT_LE(worst_outside, 1.0);  // the bound: every mask pixel within 1 px of the analytic tube
  EXPECT_LE(worst_width, 1.0);    // width f d / Z within 1 px
  EXPECT_LE(worst_depth, 1e-3);   // depth within 1 mm
  EXPECT_EQ(missing, 0);
}

TEST(Camera, ObliqueTetherIsAsWideAsItsDepthSays)
{
  // A tether in the plane y = 0 going away from 1 m to 4 m: in column u its axis is at the depth Z(u)
  // where x / z = (u - cx) / f, and the tube is about f d / Z(u) wide (12.5 to 50 px here, d = 0.1 m).
  // Exactly, the column's rays within r of the axis line span y_n in [-y_e, y_e], where the distance of
  // the ray (x_n, y_e, 1) to the line, |a . (dir x e)| / |dir x e|, is r: the mask's count in the column
  // is that span in pixels within 1 px (the pixel grid). On the centre row the ray meets the tube where
  // its distance to the axis is r (a quadratic in the depth).
  const CameraModel camera(vga());
  TetherRenderer renderer;
  const Position a(-1.0, 0.0, 1.0), b(1.5, 0.0, 4.0);
  const Eigen::Vector3d e = (b - a).normalized();
  const double d = 0.1, r = d / 2.0;
  renderOne(renderer, camera, line(a, b), d);
  double worst_count = 0.0, worst_approximation = 0.0, worst_depth = 0.0;
  int columns = 0;
  for (int u = 0; u < camera.width(); ++u)
  {
    const double xn = (u - 319.5) / 500.0;
    // a + s (b - a) projects to column u: (a.x + s dx) = xn (a.z + s dz).
    const double s = (xn * a.z() - a.x()) / ((b.x() - a.x()) - xn * (b.z() - a.z()));
    if (s < 0.05 || s > 0.95)
    {
      continue;  // near the ends the round caps widen it
    }
    const Position axis = a + s * (b - a);
    const auto distance = [&](double yn)
    {
      const Eigen::Vector3d n = Eigen::Vector3d(xn, yn, 1.0).cross(e);
      return std::abs(a.dot(n)) / n.norm();
    };
    double lo = 0.0, hi = 1.0;  // the distance grows with |y_n| (symmetric about the plane y = 0)
    for (int k = 0; k < 100; ++k)
    {
      (distance(0.5 * (lo + hi)) < r ? lo : hi) = 0.5 * (lo + hi);
    }
    const double width = 500.0 * 2.0 * lo;
    int count = 0;
    for (int v = 0; v < camera.height(); ++v)
    {
      count += renderer.mask().at<std::uint8_t>(v, u) == 255;
    }
    worst_count = std::max(worst_count, std::abs(count - width));
    worst_approximation = std::max(worst_approximation, std::abs(width - 500.0 * d / axis.z()));
    const Eigen::Vector2d ray = camera.ray(u, 240);
    const Eigen::Vector3d dir(ray.x(), ray.y(), 1.0);
    // Distance from t dir to the axis line is r: |(t dir - a) x e|^2 = r^2, a quadratic in t.
    const Eigen::Vector3d p = dir.cross(e), q = (-a).cross(e);
    const double qa = p.squaredNorm(), qb = 2.0 * p.dot(q), qc = q.squaredNorm() - r * r;
    const double expected = (-qb - std::sqrt(qb * qb - 4.0 * qa * qc)) / (2.0 * qa);
    worst_depth = std::max(worst_depth, std::abs(renderer.depth().at<float>(240, u) - expected));
    ++columns;
  }
  std::printf(
      "[ measured ] oblique tube over %d columns: mask count off the exact width by at most %.3f px; "
      "exact width off f d / Z by at most %.3f px; depth on the centre row off by at most %.3g m\n",
      columns, worst_count, worst_approximation, worst_depth);
  EXPECT_GT(columns, 300);
  EXPECT_LE(worst_count, 1.0);
  EXPECT_LE(worst_approximation, 0.5);  // f d / Z is the width to half a pixel at these depths
  EXPECT_LE(worst_depth, 1e-3);
}

TEST(Camera, ProjectionMatchesOpenCvProjectPoints)
{
  // The plumb_bob model of CameraModel against OpenCV's projectPoints, over points filling the view, and
  // every pixel's ray back through projectPoints onto its pixel.
  const CameraModel camera(vga(kBarrel));
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<cv::Point3d> points;
  for (int i = 0; i < 2000; ++i)
  {
    const double z = 0.5 + 5.0 * (uniform(random) + 1.0);
    const Eigen::Vector2d edge = camera.ray(0, 0).cwiseAbs();
    points.emplace_back(uniform(random) * edge.x() * z, uniform(random) * edge.y() * z, z);
  }
  const cv::Mat K(3, 3, CV_64F, const_cast<double*>(camera.intrinsics().K.data()));
  const cv::Mat D(kBarrel, true);
  std::vector<cv::Point2d> pixels;
  cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, D, pixels);
  double worst = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const Eigen::Vector2d p = camera.project({points[i].x, points[i].y, points[i].z});
    worst = std::max(worst, std::hypot(p.x() - pixels[i].x, p.y() - pixels[i].y));
  }
  std::vector<cv::Point3d> rays;
  for (int v = 0; v < camera.height(); v += 7)
  {
    for (int u = 0; u < camera.width(); u += 7)
    {
      rays.emplace_back(camera.ray(u, v).x(), camera.ray(u, v).y(), 1.0);
    }
  }
  cv::projectPoints(rays, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, D, pixels);
  double worst_ray = 0.0;
  std::size_t k = 0;
  for (int v = 0; v < camera.height(); v += 7)
  {
    for (int u = 0; u < camera.width(); u += 7, ++k)
    {
      worst_ray = std::max(worst_ray, std::hypot(pixels[k].x - u, pixels[k].y - v));
    }
  }
  std::printf("[ measured ] projection off projectPoints by at most %.3g px; pixel rays by %.3g px\n", worst,
              worst_ray);
  EXPECT_LE(worst, 0.1);
  EXPECT_LE(worst_ray, 0.1);
}

TEST(Camera, DistortedTetherFollowsOpenCvProjection)
{
  // A thin tether across the top left of a strongly distorted view, where the lens bends its image: the
  // mask must follow the curve projectPoints gives for its axis: every mask pixel within the tube's
  // radius (f r / Z, times the distortion's local scale) + 1 px of it, and the curve's own pixels in it.
  const CameraModel camera(vga(kBarrel));
  TetherRenderer renderer;
  const Position a(-1.2, -0.55, 1.5), b(1.2, -0.65, 1.6);
  const double d = 0.01;
  renderOne(renderer, camera, line(a, b, 20), d);
  std::vector<cv::Point3d> axis;
  for (int i = 0; i <= 4000; ++i)
  {
    const Position p = a + (b - a) * (i / 4000.0);
    axis.emplace_back(p.x(), p.y(), p.z());
  }
  const cv::Mat K(3, 3, CV_64F, const_cast<double*>(camera.intrinsics().K.data()));
  std::vector<cv::Point2d> curve;
  cv::projectPoints(axis, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, cv::Mat(kBarrel, true), curve);
  // The local scale of the distortion is below 1 (barrel), so f r / Z bounds the radius in pixels.
  const double radius_px = 500.0 * (d / 2.0) / 1.5;
  double worst = 0.0;
  for (int i : renderer.pixels())
  {
    const int u = i % camera.width(), v = i / camera.width();
    double nearest = 1e9;
    for (const auto& p : curve)
    {
      nearest = std::min(nearest, std::hypot(p.x - u, p.y - v));
    }
    worst = std::max(worst, nearest - radius_px);
  }
  int on_curve = 0, missed = 0;
  for (const auto& p : curve)
  {
    const int u = static_cast<int>(std::lround(p.x)), v = static_cast<int>(std::lround(p.y));
    if (u >= 0 && v >= 0 && u < camera.width() && v < camera.height() && std::hypot(p.x - u, p.y - v) < 0.3)
    {
      ++on_curve;
      missed += renderer.mask().at<std::uint8_t>(v, u) != 255;
    }
  }
  std::printf(
      "[ measured ] distorted tube: %zu pixels, farthest %.3f px beyond the radius from projectPoints' "
      "curve; %d of %d curve pixels missed\n",
      renderer.pixels().size(), worst, missed, on_curve);
  EXPECT_GT(renderer.pixels().size(), 500u);
  EXPECT_LE(worst, 1.0);
  EXPECT_GT(on_curve, 100);
  EXPECT_EQ(missed, 0);
}

TEST(Camera, SegmentsBehindTheCameraAreClipped)
{
  const CameraModel camera(vga());
  TetherRenderer renderer;
  // Entirely behind the camera, where a projection without clipping (x / z with z < 0) lands mid-image.
  RenderStats stats = renderOne(renderer, camera, line({-0.5, 0.2, -2.0}, {0.5, -0.2, -1.0}), 0.05);
  EXPECT_EQ(stats.pixels, 0u);
  EXPECT_EQ(cv::countNonZero(renderer.mask()), 0);
  // Through the image plane near the optical axis, from 2 m behind to 3 m in front, so that it passes
  // within a few centimetres of the lens in view. What is drawn is the part in front of the near clip
  // alone, pixel for pixel, and nothing is nearer than the clip.
  const Position behind(0.001, 0.0, -2.0), front(0.05, 0.03, 3.0);
  const double near = TetherRenderer::kNearClip + 0.025;
  const Position cut = behind + (front - behind) * ((near - behind.z()) / (front.z() - behind.z()));
  stats = renderOne(renderer, camera, {behind, front}, 0.05);
  const cv::Mat crossing = renderer.mask().clone();
  double nearest = stats.nearest_depth;
  renderOne(renderer, camera, {cut, front}, 0.05);
  EXPECT_GT(stats.pixels, 1000u);
  EXPECT_EQ(cv::countNonZero(crossing != renderer.mask()), 0);
  EXPECT_GE(nearest, TetherRenderer::kNearClip);
}

TEST(Camera, ACameraLookingAwayGivesAnEmptyMask)
{
  const CameraModel camera(vga(kBarrel));
  TetherRenderer renderer;
  const auto points = line({-3.0, 0.1, 2.0}, {3.0, 0.1, 2.0});
  EXPECT_GT(renderOne(renderer, camera, points, 0.05).pixels, 5000u);
  // Turned round (yaw 180 degrees about the image's y axis): the tether is behind it.
  Eigen::Isometry3d away = Eigen::Isometry3d::Identity();
  away.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const RenderStats stats = renderOne(renderer, camera, points, 0.05, away);
  EXPECT_EQ(stats.pixels, 0u);
  EXPECT_EQ(stats.coverage, 0.0);
  EXPECT_TRUE(std::isnan(stats.nearest_depth));
  EXPECT_EQ(cv::countNonZero(renderer.mask()), 0);
  EXPECT_EQ(cv::countNonZero(renderer.depth() == renderer.depth()), 0);  // NaN everywhere
  // Turned 90 degrees, the tether beside the view: culled, not drawn.
  away.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_EQ(renderOne(renderer, camera, points, 0.05, away).pixels, 0u);
}

TEST(Camera, TheSeabedHidesWhatIsBelowIt)
{
  // World z up; the camera 1 m above a seabed at z = -2, looking down at 45 degrees along +x. A tether
  // lying across the view on the bed (axis on the plane, as the contact puts it) shows its upper half:
  // every visible pixel's point lies on or above the plane, and there are fewer than without the bed.
  const CameraModel camera(vga());
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.0, 0.0, -1.0);
  // Optical z = forward and down, x = -y world (right), y = down-forward.
  Eigen::Matrix3d r;
  const double c = std::sqrt(0.5);
  r.col(2) = Eigen::Vector3d(c, 0.0, -c);
  r.col(0) = Eigen::Vector3d(0.0, -1.0, 0.0);
  r.col(1) = r.col(2).cross(r.col(0));
  pose.linear() = r;
  const SeabedOccluder seabed(-2.0);
  TetherRenderer renderer;
  const auto on_bed = line({1.0, -3.0, -2.0}, {1.0, 3.0, -2.0});
  const std::size_t free_pixels = renderOne(renderer, camera, on_bed, 0.05, pose).pixels;
  const RenderStats stats = renderOne(renderer, camera, on_bed, 0.05, pose, {&seabed});
  double lowest = 1e9;
  for (int i : renderer.pixels())
  {
    const Eigen::Vector2d ray = camera.ray(i % camera.width(), i / camera.width());
    const Eigen::Vector3d p = pose * (Eigen::Vector3d(ray.x(), ray.y(), 1.0) * renderer.depth().ptr<float>()[i]);
    lowest = std::min(lowest, p.z());
  }
  std::printf("[ measured ] tube on the bed: %zu of %zu pixels visible, lowest visible point z = %.5f m\n",
              stats.pixels, free_pixels, lowest);
  EXPECT_GT(stats.pixels, 100u);
  EXPECT_LT(stats.pixels, free_pixels);
  EXPECT_EQ(stats.occluded_pixels, free_pixels - stats.pixels);
  EXPECT_GE(lowest, -2.0 - 1e-5);
  // Buried 10 cm: nothing shows.
  EXPECT_EQ(renderOne(renderer, camera, line({1.0, -3.0, -2.1}, {1.0, 3.0, -2.1}), 0.05, pose, {&seabed}).pixels, 0u);
}

TEST(Camera, BadIntrinsicsAreRefusedNamingTheField)
{
  CameraIntrinsics c = vga();
  c.K[0] = -1.0;
  EXPECT_THROW({ CameraModel bad(c); }, std::invalid_argument);
  c = vga({0.1, 0.2});
  EXPECT_NE(c.validate().at(0).find("D: 2 coefficients"), std::string::npos);
  c = vga();
  c.width = 0;
  EXPECT_NE(c.validate().at(0).find("width = 0"), std::string::npos);
  // A distortion that folds over inside the image (k1 = -1 turns back at r = 0.58).
  c = vga({-1.0, 0.0, 0.0, 0.0, 0.0});
  try
  {
    CameraModel folded(c);
    FAIL() << "a folding distortion was accepted";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find("D:"), std::string::npos) << e.what();
  }
}

// A distorted camera's build (seconds at 1920x1080) asks whether it is abandoned before each stretch of
// kRowsPerStretch rows and once before its row tables, and stops at the first yes: the node's shutdown and the next
// CameraInfo need not wait for it. Asked and never told, it builds each ray as one cv::undistortPoints call over the
// whole image does (the stretches take each pixel on its own, as that call does: bit for bit).
TEST(Camera, ABuildAskedToStopPartWayStopsThere)
{
  const CameraIntrinsics c = vga(kBarrel);
  const int stretches = (c.height + CameraModel::kRowsPerStretch - 1) / CameraModel::kRowsPerStretch;  // 30
  int asked = 0;
  EXPECT_THROW(CameraModel(c, [&] { return ++asked == 3; }), CameraBuildAbandoned);
  EXPECT_EQ(asked, 3) << "the build went on after it was told to stop";

  asked = 0;
  const CameraModel model(c, [&] { return ++asked < 0; });
  EXPECT_EQ(asked, stretches + 1);
  std::vector<cv::Point2d> pixels, rays;
  for (int v = 0; v < c.height; ++v)
  {
    for (int u = 0; u < c.width; ++u)
    {
      pixels.emplace_back(u, v);
    }
  }
  const cv::Mat k_mat(3, 3, CV_64F, const_cast<double*>(c.K.data()));
  std::array<double, 5> d = c.plumbBob();
  cv::undistortPoints(pixels, rays, k_mat, cv::Mat(1, 5, CV_64F, d.data()), cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 200, 1e-14));
  int different = 0;
  for (std::size_t i = 0; i < pixels.size(); ++i)
  {
    const int u = static_cast<int>(pixels[i].x), v = static_cast<int>(pixels[i].y);
    different +=
        model.ray(u, v).x() != static_cast<float>(rays[i].x) || model.ray(u, v).y() != static_cast<float>(rays[i].y);
  }
  EXPECT_EQ(different, 0);

  // An undistorted camera's rays take no inversion: it is asked once, before the row tables.
  asked = 0;
  EXPECT_THROW(CameraModel(vga(), [&] { return ++asked == 1; }), CameraBuildAbandoned);
  EXPECT_EQ(asked, 1);
}

TEST(Camera, ShapeHistoryInterpolatesToAStamp)
{
  TetherParams params;
  params.cable_length = 5.0;
  params.initial_deployed_length = 2.0;
  params.noise = 0.0;
  Tether tether(params, Position::Zero(), Position(1.0, 0.0, 0.0));
  ShapeHistory history(1.0, 0.0);
  std::vector<Position> before, after, middle;
  for (int k = 0; k < 400; ++k)  // 2 s of a vehicle moving at 1 m/s: pay-out releases particles
  {
    const Status fed = tether.addVehicleSample(tether.time() + 0.005, Position(1.0 + tether.time() + 0.005, 0.0, 0.0));
    ASSERT_TRUE(fed.ok) << fed.message;
    tether.step();
    history.record(tether);
  }
  EXPECT_NEAR(history.newest(), 2.0, 1e-9);
  EXPECT_NEAR(history.oldest(), 1.0, 0.006);  // one shape at or before newest - span is kept
  ASSERT_TRUE(history.shapeAt(1.5, before));
  ASSERT_TRUE(history.shapeAt(1.505, after));
  ASSERT_TRUE(history.shapeAt(1.5025, middle));
  ASSERT_EQ(before.size(), after.size());
  ASSERT_EQ(middle.size(), before.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < middle.size(); ++i)
  {
    worst = std::max(worst, (middle[i] - 0.5 * (before[i] + after[i])).norm());
  }
  EXPECT_LE(worst, 1e-6);  // float storage: 1e-7 relative
  // The vehicle end at a stamp between steps: interpolated as the vehicle moved (x = 1 + t).
  EXPECT_NEAR(middle.back().x(), 2.5025, 1e-5);
  EXPECT_FALSE(history.shapeAt(0.5, middle));
  EXPECT_FALSE(history.shapeAt(2.1, middle));
  // Time going back (a reset) starts the history again.
  const Status reset = tether.reset(0.0);
  ASSERT_TRUE(reset.ok) << reset.message;
  history.record(tether);
  EXPECT_EQ(history.oldest(), 0.0);
  EXPECT_EQ(history.newest(), 0.0);
}

}  // namespace
}  // namespace rov_tether::camera

namespace rov_tether::camera
{
namespace
{

std::string readText(const std::string& path)
{
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(Dataset, CameraPoseFollowsTheVehicleItsHeadingAndTheMount)
{
  // A camera 0.5 m ahead of the vehicle, pitched 20 degrees down, on a vehicle heading along +y (yaw 90
  // degrees): it sits at vehicle + (0, 0.5, 0) and looks along (0, cos 20, -sin 20); image right is +x
  // of the world (the vehicle's right), image down is down and forward.
  ScenarioCamera mount;
  mount.position = {0.5, 0.0, 0.0};
  mount.orientation = {0.0, 20.0, 0.0};
  const Eigen::Isometry3d pose = cameraPose(mount, Position(1.0, 2.0, -3.0), M_PI / 2);
  const double c = std::cos(20.0 * M_PI / 180.0), s = std::sin(20.0 * M_PI / 180.0);
  EXPECT_LE((pose.translation() - Position(1.0, 2.5, -3.0)).norm(), 1e-12);
  EXPECT_LE((pose.linear().col(2) - Eigen::Vector3d(0.0, c, -s)).norm(), 1e-12);
  EXPECT_LE((pose.linear().col(0) - Eigen::Vector3d(1.0, 0.0, 0.0)).norm(), 1e-12);
  EXPECT_LE((pose.linear().col(1) - Eigen::Vector3d(0.0, -s, -c)).norm(), 1e-12);
}

TEST(Dataset, TheVehicleTurnsAtItsYawRateLimit)
{
  // Out along +x for 10 s, then along +y: the heading starts at 0 and turns 90 degrees at 30 deg/s,
  // so it reaches 90 degrees 3 s after the corner and is 45 degrees 1.5 s after it.
  Scenario scenario;
  scenario.vehicle = {{0.0, {0, 0, 0}}, {10.0, {5, 0, 0}}, {20.0, {5, 5, 0}}};
  VehicleHeading heading(scenario);
  EXPECT_NEAR(heading.yawAt(5.0), 0.0, 1e-12);
  EXPECT_NEAR(heading.yawAt(11.5), M_PI / 4, 0.006);  // one 10 ms step of 0.3 degrees
  EXPECT_NEAR(heading.yawAt(13.05), M_PI / 2, 1e-12);
  EXPECT_NEAR(heading.yawAt(25.0), M_PI / 2, 1e-12);  // held after the path ends
}

/// WCAG 2.1 contrast ratio of a BGR colour against black (docs/references.md, "Seeing the cable in rviz").
double contrastWithBlack(const cv::Vec3b& bgr)
{
  const auto linear = [](int v)
  {
    const double c = v / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
  };
  const double luminance = 0.2126 * linear(bgr[2]) + 0.7152 * linear(bgr[1]) + 0.0722 * linear(bgr[0]);
  return (luminance + 0.05) / 0.05;
}

// The depth preview is for a person: in a 16-bit PNG a tether 1 to 20 m away reads 1000 to 20000 of 65535,
// which an ordinary viewer shows black to dark grey. The preview is black exactly where there is no depth;
// every tether pixel stands out from that black as the rviz colours must (contrast ratio 3, the WCAG
// minimum for graphics, docs/references.md), nearer is lighter, and depths at or beyond the scale's far end
// (the farthest a tether point can be) share its colour.
TEST(Dataset, DepthPreviewIsBlackWithoutTetherAndLighterNearer)
{
  const std::uint16_t depths[] = {0, 300, 1000, 5000, 12000, 20000, 60000};
  cv::Mat depth_mm(1, static_cast<int>(std::size(depths)), CV_16UC1);
  for (int i = 0; i < depth_mm.cols; ++i)
  {
    depth_mm.at<std::uint16_t>(i) = depths[i];
  }
  cv::Mat preview;
  depthPreview(depth_mm, 20.0, preview);
  ASSERT_EQ(preview.type(), CV_8UC3);
  ASSERT_EQ(preview.size(), depth_mm.size());
  EXPECT_EQ(preview.at<cv::Vec3b>(0), cv::Vec3b(0, 0, 0));
  double worst = 1e9;
  for (int i = 1; i < depth_mm.cols; ++i)
  {
    worst = std::min(worst, contrastWithBlack(preview.at<cv::Vec3b>(i)));
    if (i + 1 < depth_mm.cols && depths[i + 1] <= 20000)
    {
      EXPECT_GT(contrastWithBlack(preview.at<cv::Vec3b>(i)), contrastWithBlack(preview.at<cv::Vec3b>(i + 1)))
          << depths[i] << " mm against " << depths[i + 1] << " mm";
    }
  }
  EXPECT_GE(worst, 3.0);
  EXPECT_EQ(preview.at<cv::Vec3b>(6), preview.at<cv::Vec3b>(5));  // 60 m beyond the 20 m scale: its far end
  std::printf("[ measured ] depth preview: lowest contrast ratio with black %.2f (minimum 3)\n", worst);
}

TEST(Dataset, RunnerWritesMasksDepthAndAnIndexWithoutChangingTheRun)
{
  Scenario scenario;
  ASSERT_EQ(
      loadScenario(std::string(ROV_TETHER_SOURCE_DIR) + "/scenarios/datasets/forward_camera_dive.yaml", &scenario), "");
  scenario.duration = 32.0;  // into the return leg, where the camera sees its tether
  ASSERT_EQ(scenario.cameras.size(), 1u);
  const std::string dir = testing::TempDir() + "rov_tether_dataset";
  std::filesystem::remove_all(dir);
  DatasetWriter writer(scenario, dir);
  RunSummary summary;
  ASSERT_EQ(runScenario(scenario, dir, &summary, {&writer}), "");
  const std::string state_with_camera = readText(dir + "/state.csv");
  const std::string shape_with_camera = readText(dir + "/shape.csv");
  ASSERT_EQ(runScenario(scenario, dir + "/plain", &summary), "");
  // Looking changes nothing: the same rows as a run without the camera.
  EXPECT_EQ(state_with_camera, readText(dir + "/plain/state.csv"));
  EXPECT_EQ(shape_with_camera, readText(dir + "/plain/shape.csv"));

  const ScenarioCamera& spec = scenario.cameras[0];
  const std::size_t frames = static_cast<std::size_t>(scenario.duration * spec.rate) + 1;  // 161
  std::ifstream index(dir + "/cameras/forward/index.csv");
  std::string line;
  std::getline(index, line);
  EXPECT_EQ(line, "frame,t,coverage");
  std::size_t rows = 0, seen = 0;
  double worst_coverage = 0.0, worst_time = 0.0;
  for (; std::getline(index, line); ++rows)
  {
    std::size_t frame = 0;
    double t = 0.0, coverage = 0.0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%zu,%lf,%lf", &frame, &t, &coverage), 3) << line;
    EXPECT_EQ(frame, rows);
    // Frame k shows the last physics step at or before k / rate.
    worst_time = std::max(worst_time, frame / spec.rate - t);
    EXPECT_GE(frame / spec.rate - t, -1e-9);
    char name[32];
    std::snprintf(name, sizeof(name), "%06zu.png", frame);
    const cv::Mat mask = cv::imread(dir + "/cameras/forward/mask_" + name, cv::IMREAD_UNCHANGED);
    const cv::Mat depth = cv::imread(dir + "/cameras/forward/depth_" + name, cv::IMREAD_UNCHANGED);
    const cv::Mat preview = cv::imread(dir + "/cameras/forward/depth_preview_" + name, cv::IMREAD_UNCHANGED);
    ASSERT_EQ(mask.type(), CV_8UC1);
    ASSERT_EQ(depth.type(), CV_16UC1);
    ASSERT_EQ(preview.type(), CV_8UC3) << name;
    ASSERT_EQ(preview.size(), depth.size());
    // The preview shows the tether where the depth has it, and black elsewhere.
    cv::Mat lit;
    cv::cvtColor(preview, lit, cv::COLOR_BGR2GRAY);
    EXPECT_EQ(cv::countNonZero((lit > 0) != (depth > 0)), 0) << name;
    ASSERT_EQ(mask.cols, 640);
    ASSERT_EQ(depth.rows, 480);
    // Depth where and only where the mask is set (every tether point here is under 65 m away).
    EXPECT_EQ(cv::countNonZero(mask != ((depth > 0) & 255)), 0) << name;
    EXPECT_EQ(cv::countNonZero((mask != 0) & (mask != 255)), 0) << name;
    worst_coverage = std::max(worst_coverage, std::abs(coverage - cv::countNonZero(mask) / (640.0 * 480.0)));
    if (cv::countNonZero(mask) > 0)
    {
      ++seen;
      double lo = 0.0, hi = 0.0;
      cv::minMaxLoc(depth, nullptr, &hi);
      cv::minMaxLoc(depth, &lo, nullptr, nullptr, nullptr, depth > 0);
      // The tether is in front of the camera and no further than the deployed cable reaches.
      EXPECT_GE(lo, 1000.0 * TetherRenderer::kNearClip);
      EXPECT_LE(hi, 1000.0 * (summary.deployed_max + 1.0));
    }
  }
  std::printf(
      "[ measured ] dataset: %zu frames, the tether in %zu; coverage off the mask by %.3g; frame time "
      "at most %.4f s before k / rate\n",
      rows, seen, worst_coverage, worst_time);
  EXPECT_EQ(rows, frames);
  EXPECT_GT(seen, 10u);  // it turns and looks back along its tether from 28.6 s on
  EXPECT_LE(worst_coverage, 1e-6);
  EXPECT_LT(worst_time, scenario.params.time_step);
  std::filesystem::remove_all(dir);
}

/// How a run with MidRunLook ends.
enum class Ending
{
  kSucceeds,
  kFails,          ///< the observer's error at 0.5 s
  kCsvCannotMove,  ///< a directory made at 0.5 s where shape.csv goes
};

/// Looks once, at 0.5 s, at what the output directory holds then, and makes the run end as asked.
class MidRunLook : public RunObserver
{
 public:
  MidRunLook(std::filesystem::path forward, Ending ending) : forward_(std::move(forward)), ending_(ending) {}
  double nextTime() const override { return looked_ ? std::numeric_limits<double>::infinity() : 0.5; }
  std::string observe(const Tether& /*sim*/) override
  {
    looked_ = true;
    for (const auto& entry : std::filesystem::directory_iterator(forward_))
    {
      seen.insert(entry.path().filename().string());
    }
    partial_frames = std::filesystem::exists(forward_.parent_path() / ".forward.partial" / "mask_000000.png");
    if (ending_ == Ending::kCsvCannotMove)
    {
      std::filesystem::create_directories(forward_.parent_path().parent_path() / "shape.csv" / "in_the_way");
    }
    return ending_ == Ending::kFails ? "stopped here" : "";
  }
  std::set<std::string> seen;   ///< cameras/forward/'s files in the middle of the run
  bool partial_frames = false;  ///< whether the run's first frame was in cameras/.forward.partial/ then

 private:
  std::filesystem::path forward_;
  Ending ending_;
  bool looked_ = false;
};

/// The names of the entries of `where`.
std::set<std::string> entriesOf(const std::filesystem::path& where)
{
  std::set<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(where))
  {
    names.insert(entry.path().filename().string());
  }
  return names;
}

/// The entries anywhere under `where` whose names end in ".partial" (the runs' temporaries), as one line.
std::string temporariesUnder(const std::filesystem::path& where)
{
  std::string found;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(where))
  {
    const std::string name = entry.path().filename().string();
    if (name.size() >= 8 && name.compare(name.size() - 8, 8, ".partial") == 0)
    {
      found += entry.path().string() + " ";
    }
  }
  return found;
}

// A camera's directory is replaced whole, and only by a run that succeeded (runScenario's observer hooks): the
// frames go to cameras/.forward.partial/ as the run goes, with the earlier cameras/forward/ as it was meanwhile; a
// run that fails half-way, or whose CSV files cannot move into place, removes them and leaves the earlier dataset
// as it was; one that succeeds leaves exactly its own frames, none of the earlier run's past them. A
// cameras/.forward.earlier (an earlier dataset moved aside by a run that stopped while it moved its own) or a symbolic
// link at cameras/forward is refused before the run, naming it, and nothing is written. Before, the frames were written
// in place: a run that failed or was stopped left its frames over the earlier run's, under its own index.csv.
TEST(Dataset, ACameraDirectoryIsReplacedWholeOnlyWhenTheRunSucceeded)
{
  Scenario scenario;
  ASSERT_EQ(
      loadScenario(std::string(ROV_TETHER_SOURCE_DIR) + "/scenarios/datasets/forward_camera_dive.yaml", &scenario), "");
  scenario.duration = 1.0;
  ASSERT_EQ(scenario.cameras.size(), 1u);
  const std::filesystem::path dir = testing::TempDir() + "rov_tether_dataset_replaced";
  const std::filesystem::path forward = dir / "cameras" / "forward";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(forward);
  std::ofstream(forward / "index.csv") << "an earlier dataset\n";
  std::ofstream(forward / "mask_000999.png") << "an earlier frame\n";
  const std::set<std::string> earlier{"index.csv", "mask_000999.png"};
  const std::string in_the_way = "cannot move '" + (dir / "shape.csv").string() +
                                 "' into place: " + std::make_error_code(std::errc::is_a_directory).message() +
                                 ". No CSV output was replaced: every CSV file is as it was before this run";
  for (const Ending ending : {Ending::kFails, Ending::kCsvCannotMove, Ending::kSucceeds})
  {
    SCOPED_TRACE(static_cast<int>(ending));
    DatasetWriter writer(scenario, dir.string());
    MidRunLook look(forward, ending);
    RunSummary summary;
    EXPECT_EQ(runScenario(scenario, dir.string(), &summary, {&writer, &look}),
              ending == Ending::kFails ? "stopped here" : (ending == Ending::kCsvCannotMove ? in_the_way : ""));
    EXPECT_EQ(look.seen, earlier);  // as it was in the middle of the run
    EXPECT_TRUE(look.partial_frames);
    EXPECT_EQ(entriesOf(dir / "cameras"), std::set<std::string>{"forward"});
    EXPECT_EQ(temporariesUnder(dir), "");
    std::filesystem::remove_all(dir / "shape.csv");
    if (ending != Ending::kSucceeds)
    {
      // Where the CSV files did not move into place, neither did the dataset.
      EXPECT_EQ(entriesOf(forward), earlier);
      EXPECT_EQ(readText((forward / "index.csv").string()), "an earlier dataset\n");
      continue;
    }
    EXPECT_TRUE(summary.replaced_left.empty());
    const std::size_t frames = scenario.cameraFrames(scenario.cameras[0]);
    const std::set<std::string> written = entriesOf(forward);
    EXPECT_EQ(written.size(), 1 + 3 * frames);  // index.csv and three images a frame
    EXPECT_EQ(written.count("mask_000999.png"), 0u);
    char last[32];
    std::snprintf(last, sizeof last, "mask_%06zu.png", frames - 1);
    EXPECT_EQ(written.count(last), 1u);
  }
  const std::string state = readText((dir / "state.csv").string());
  std::filesystem::create_directories(dir / "cameras" / ".forward.earlier");
  {
    DatasetWriter refused(scenario, dir.string());
    RunSummary summary;
    const std::string error = runScenario(scenario, dir.string(), &summary, {&refused});
    EXPECT_EQ(error.rfind("cannot write '" + forward.string() + "/': '" +
                              (dir / "cameras" / ".forward.earlier").string() + "' is in the way",
                          0),
              0u)
        << error;
  }
  std::filesystem::remove(dir / "cameras" / ".forward.earlier");
  std::filesystem::rename(forward, dir / "elsewhere");
  std::filesystem::create_directory_symlink(dir / "elsewhere", forward);
  {
    DatasetWriter refused(scenario, dir.string());
    RunSummary summary;
    const std::string error = runScenario(scenario, dir.string(), &summary, {&refused});
    EXPECT_EQ(error, "cannot write '" + forward.string() +
                         "/': it is a symbolic link, which the run would replace with a directory (write to where it "
                         "points)");
  }
  EXPECT_EQ(entriesOf(dir / "cameras"), std::set<std::string>{"forward"});
  EXPECT_EQ(readText((dir / "state.csv").string()), state);  // nothing was written
  EXPECT_EQ(temporariesUnder(dir), "");
  std::filesystem::remove_all(dir);
}

// writePng (libpng) read back by OpenCV's own PNG reader: every sample exact (PNG is lossless), 16-bit values
// above 255 in the right byte order (a missing swap reads 0x0102 as 0x0201), BGR colours in their channels,
// and refusals: an unwritable path, a type the dataset never writes, an empty image.
TEST(Dataset, PngFilesReadBackExactly)
{
  const std::string dir = std::filesystem::temp_directory_path() / "rov_tether_png_test";
  std::filesystem::create_directories(dir);
  cv::Mat grey(3, 5, CV_8UC1), depth(4, 3, CV_16UC1), colour(2, 3, CV_8UC3);
  cv::randu(grey, 0, 256);
  cv::randu(depth, 0, 65536);
  depth.at<std::uint16_t>(0, 0) = 0x0102;
  cv::randu(colour, 0, 256);
  colour.at<cv::Vec3b>(0, 0) = cv::Vec3b(255, 0, 10);  // blue in OpenCV's BGR
  for (const cv::Mat* image : {&grey, &depth, &colour})
  {
    const std::string path = dir + "/image.png";
    ASSERT_TRUE(rov_tether::camera::writePng(path, *image));
    const cv::Mat back = cv::imread(path, cv::IMREAD_UNCHANGED);
    ASSERT_EQ(back.type(), image->type());
    ASSERT_EQ(back.size(), image->size());
    EXPECT_EQ(cv::norm(back, *image, cv::NORM_INF), 0.0);
  }
  EXPECT_FALSE(rov_tether::camera::writePng(dir + "/no/such/dir/image.png", grey));
  EXPECT_FALSE(rov_tether::camera::writePng(dir + "/float.png", cv::Mat(2, 2, CV_32FC1, cv::Scalar(1.0))));
  EXPECT_FALSE(rov_tether::camera::writePng(dir + "/empty.png", cv::Mat()));
  std::filesystem::remove_all(dir);
}

TEST(Dataset, BadCamerasInAScenarioAreNamed)
{
  const std::string base =
      "spool: [0, 0, 0]\nvehicle: [[0, 1, 0, 0], [10, 5, 0, 0]]\nduration: 5\ncameras:\n  - {name: front, ";
  const std::string intrinsics = "width: 64, height: 48, K: [50, 0, 31.5, 0, 50, 23.5, 0, 0, 1]";
  Scenario scenario;
  EXPECT_EQ(parseScenario(base + intrinsics + "}\n", &scenario), "");
  ASSERT_EQ(scenario.cameras.size(), 1u);
  EXPECT_EQ(scenario.cameras[0].rate, 10.0);
  const std::pair<std::string, std::string> cases[] = {
      {base + "width: 64, height: 48}\n", "cameras[0].K: missing"},
      {base + intrinsics + ", rate: 0}\n", "cameras[0].rate = 0"},
      {base + intrinsics + ", D: [0.1, 0.2]}\n", "cameras[0].D: expected a list of 5"},
      {base + intrinsics + ", fov: 90}\n", "cameras[0]: unknown field 'fov'"},
      {base + "width: 64.5, height: 48, K: [50, 0, 31.5, 0, 50, 23.5, 0, 0, 1]}\n", "cameras[0].width = 64.5"},
      {base + "width: 64, height: 48, K: [-50, 0, 31.5, 0, 50, 23.5, 0, 0, 1]}\n", "cameras[0].K: fx"},
      {base + intrinsics + "}\n  - {name: front, " + intrinsics + "}\n", "cameras[1].name = 'front': used twice"},
      {"spool: [0, 0, 0]\nduration: 5\ncameras:\n  - {name: front, " + intrinsics + "}\n", "no vehicle path"},
      {"spool: [0, 0, 0]\nvehicle: [[0, 1, 0, 0]]\nduration: 5\ncameras:\n  - {name: '../x', " + intrinsics + "}\n",
       "cameras[0].name = '../x'"},
  };
  for (const auto& [text, expected] : cases)
  {
    const std::string error = parseScenario(text, &scenario);
    EXPECT_NE(error.find(expected), std::string::npos) << "got: " << error << "\nexpected: " << expected;
  }
}

}  // namespace
}  // namespace rov_tether::camera
